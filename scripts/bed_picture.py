#!/usr/bin/python3
"""A drum bed seen along its axis, from a wetdem glTF frame (frames/*.glb), as a camera at the end plate sees it.

Shared by the figure scripts (scripts/paper_figures.py; a per-run picture can call the same draw_bed):
    import bed_picture
    frame = bed_picture.read_glb("run/frames/frame_000123.glb")
    bed_picture.draw_bed(ax, frame, drum_radius=0.07, color_by="liquid")

Usage as a script: /usr/bin/python3 scripts/bed_picture.py FRAME.glb OUT.png [--radius R] [--color liquid|agglomerate|agglomerate_size|size]

The frame's particles are drawn as discs of their own radius in the plane normal to the axis (x, y; gravity -y),
back to front (increasing z), so the discs in front hide those behind as the end plate's view would. Colours:
  liquid       liquid per particle (film + half of each bridge + wall bridges) over the particle's own volume, a
               white-to-blue scale (white: dry)
  agglomerate  the particle's bridge cluster (particles connected by bridges): one colour per cluster (a cycle of
               20), unbridged particles light grey
  agglomerate_size  the same clusters coloured by their size in particles on a log scale
  size         the particle radius (segregation)
"""
import json
import math
import struct
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.cm  # noqa: E402
import matplotlib.collections  # noqa: E402
import matplotlib.colors  # noqa: E402
import matplotlib.patches  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def read_glb(path):
    """The attributes of a wetdem point-cloud frame as lists: x, y, z, radius, liquid (m^3), id, cluster,
    cluster_size (the last two None when the frame has no clusters), and the frame's extras (time, step)."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, _length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2:
        raise ValueError("%s: not a glTF 2.0 binary" % path)
    off = 12
    doc, binary = None, b""
    while off < len(data):
        clen, ctype = struct.unpack_from("<I4s", data, off)
        chunk = data[off + 8:off + 8 + clen]
        if ctype == b"JSON":
            doc = json.loads(chunk.decode("utf-8"))
        elif ctype == b"BIN\x00":
            binary = chunk
        off += 8 + clen
    prim = doc["meshes"][0]["primitives"][0]

    def attribute(name):
        if name not in prim["attributes"]:
            return None
        acc = doc["accessors"][prim["attributes"][name]]
        view = doc["bufferViews"][acc["bufferView"]]
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        k = _COMPONENTS[acc["type"]]
        vals = struct.unpack_from("<%df" % (acc["count"] * k), binary, start)
        return [vals[i * k:(i + 1) * k] for i in range(acc["count"])] if k > 1 else list(vals)

    pos = attribute("POSITION")
    out = {
        "x": [p[0] for p in pos], "y": [p[1] for p in pos], "z": [p[2] for p in pos],
        "radius": attribute("_RADIUS"), "liquid": attribute("_LIQUID_VOLUME"), "id": attribute("_ID"),
        "cluster": attribute("_CLUSTER"), "cluster_size": attribute("_CLUSTER_SIZE"),
        "extras": doc.get("asset", {}).get("extras", {}),
    }
    return out


def draw_bed(ax, frame, drum_radius, color_by="liquid", title=None, liquid_max=None, colorbar=True):
    """Draws the bed on ax (equal aspect, millimetres); returns the mappable of the colour scale (None for the
    one-colour-per-agglomerate view)."""
    n = len(frame["x"])
    order = sorted(range(n), key=lambda i: frame["z"][i])  # back to front: the front discs are drawn last
    if color_by == "liquid":
        frac = [frame["liquid"][i] / (4.0 / 3.0 * math.pi * frame["radius"][i] ** 3) for i in range(n)]
        top = liquid_max if liquid_max else max(max(frac), 1e-12)
        norm = matplotlib.colors.Normalize(0.0, top)
        cmap = matplotlib.colormaps["Blues"]
        colors = [cmap(0.08 + 0.92 * norm(frac[i])) for i in order]
        label = "liquid per particle / own volume"
        mappable = matplotlib.cm.ScalarMappable(norm=norm, cmap=matplotlib.colors.LinearSegmentedColormap.from_list(
            "b", [cmap(0.08), cmap(1.0)]))
    elif color_by == "agglomerate":
        ids = frame["cluster"] or list(range(n))
        sizes = frame["cluster_size"] or [1.0] * n
        cmap = matplotlib.colormaps["tab20"]
        # Colours by rank of the cluster's label, so that neighbouring labels differ.
        labels = sorted({int(ids[i]) for i in range(n) if sizes[i] >= 2})
        rank = {c: k for k, c in enumerate(labels)}
        colors = [(0.85, 0.85, 0.85, 1.0) if sizes[i] < 2 else cmap((rank[int(ids[i])] * 7) % 20 / 19.0)
                  for i in order]
        label = None
        mappable = None
    elif color_by == "agglomerate_size":
        sizes = frame["cluster_size"] or [1.0] * n
        top = max(max(sizes), 2.0)
        norm = matplotlib.colors.LogNorm(2.0, top) if top > 2.0 else matplotlib.colors.Normalize(1.0, 2.0)
        cmap = matplotlib.colormaps["viridis"]
        colors = [(0.85, 0.85, 0.85, 1.0) if sizes[i] < 2 else cmap(norm(sizes[i])) for i in order]
        label = "agglomerate size (particles); grey: no bridge"
        mappable = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    elif color_by == "size":
        rs = frame["radius"]
        norm = matplotlib.colors.Normalize(min(rs) * 2e3, max(rs) * 2e3)
        cmap = matplotlib.colormaps["plasma"]
        colors = [cmap(norm(rs[i] * 2e3)) for i in order]
        label = "particle diameter (mm)"
        mappable = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    else:
        raise ValueError("color_by: liquid, agglomerate, agglomerate_size or size")
    discs = [matplotlib.patches.Circle((frame["x"][i] * 1e3, frame["y"][i] * 1e3), frame["radius"][i] * 1e3)
             for i in order]
    ax.add_collection(matplotlib.collections.PatchCollection(discs, facecolors=colors, edgecolors=(0, 0, 0, 0.35),
                                                             linewidths=0.15))
    R = drum_radius * 1e3
    ax.add_patch(matplotlib.patches.Circle((0, 0), R, fill=False, lw=1.2, color="0.2"))
    ax.set_xlim(-1.05 * R, 1.05 * R)
    ax.set_ylim(-1.05 * R, 1.05 * R)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm), gravity down")
    if title:
        ax.set_title(title, fontsize=9)
    if colorbar and mappable is not None:
        mappable.set_array([])
        plt.colorbar(mappable, ax=ax, fraction=0.046, pad=0.04).set_label(label, fontsize=8)
    return mappable


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    radius, color = 0.07, "liquid"
    if "--radius" in argv:
        radius = float(argv[argv.index("--radius") + 1])
    if "--color" in argv:
        color = argv[argv.index("--color") + 1]
    frame = read_glb(argv[1])
    fig, ax = plt.subplots(figsize=(5.2, 4.6))
    draw_bed(ax, frame, radius, color, title="%s, t = %.3g s" % (argv[1], frame["extras"].get("time", float("nan"))))
    fig.tight_layout()
    fig.savefig(argv[2], dpi=130)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
