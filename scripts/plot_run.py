#!/usr/bin/python3
"""Figures of one wetdem run (called by `wetdem run` at the end; `--no-figures` skips it).

Usage: /usr/bin/python3 scripts/plot_run.py RUN_DIR   (Debian's python3-matplotlib)

Reads RUN_DIR/timeseries.csv and RUN_DIR/figures/plot_data.json (written by the run: the window verdicts of
summary.json, the last frame and its fitted free surface) and writes:
  figures/aor.png  the dynamic angle of repose against time: settling and rotation, the averaging window
                   shaded, the window mean and its error band, and the stationarity verdict
  figures/bed.png  the bed at the last frame seen along the drum axis: every particle a circle of its radius,
                   coloured by its liquid (film + half of each bridge, the snapshots' white-to-blue scale), the
                   drum wall, and the fitted free surface (solid over the fitted columns, dashed beyond)
Exits non-zero (and the run reports it in summary.json figures_error) when a figure cannot be drawn.
"""
import csv
import json
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap, Normalize  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

# The snapshots' liquid scale (app/output/colormap.h): ColorBrewer "Blues" at 0, 1/4, 1/2, 3/4, 1 of the max.
BLUES = LinearSegmentedColormap.from_list("wetdem_liquid", ["#ffffff", "#c6dbef", "#6baed6", "#2171b5", "#08306b"])


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def verdict_text(s):
    """The AoR line of the run's result, as the log prints it."""
    if s.get("aor_flag"):
        return "AoR flagged (bed near the drum centre)", "tab:red"
    mean, sem = s.get("aor_deg_mean"), s.get("aor_sem_block")
    head = "AoR = %.1f° ± %.1f°" % (mean, sem)
    if not s.get("aor_stationary"):
        why = textwrap.fill("NOT STATIONARY, do not quote: " + s.get("aor_stationary_reason", ""), 95)
        return head + "\n" + why, "tab:red"
    if not s.get("aor_sem_reliable"):
        return head + "  (stationary; error bar NOT RELIABLE)", "tab:orange"
    return head + "  (stationary, n_eff %.0f)" % s.get("aor_n_eff", 0), "black"


def plot_aor(run_dir, data):
    rows = []
    with open(os.path.join(run_dir, "timeseries.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    t = [num(r["time"]) for r in rows]
    a = [num(r["aor_deg"]) for r in rows]
    s = data["summary"]
    t0 = data.get("rotation_start_s", 0.0)
    w0, w1 = s["aor_window_s"]

    fig, ax = plt.subplots(figsize=(8, 4.2))
    ax.axvspan(w0, w1, color="0.92", zorder=0, label="averaging window")
    ax.axvline(t0, color="0.5", lw=0.8, ls=":", zorder=1)
    ax.text(t0, 1.0, " drum starts turning", transform=ax.get_xaxis_transform(), va="top", ha="left",
            fontsize=8, color="0.35")
    ax.plot([x for x, y in zip(t, a) if y is not None], [y for y in a if y is not None], ".-", color="tab:blue",
            lw=0.8, ms=2.5, label="dynamic AoR (centre-of-mass angle)", zorder=2)
    text, colour = verdict_text(s)
    if not s.get("aor_flag") and s.get("aor_deg_mean") is not None:
        m, e = s["aor_deg_mean"], s["aor_sem_block"]
        ax.fill_between([w0, w1], [m - e] * 2, [m + e] * 2, color="tab:orange", alpha=0.35, lw=0, zorder=1,
                        label="window mean ± error")
        ax.plot([w0, w1], [m, m], color="tab:orange", lw=1.5, zorder=3)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("dynamic angle of repose (°)")
    ax.set_xlim(0, max(x for x in t if x is not None))
    ax.set_ylim(bottom=0)
    ax.set_title("%s: %s" % (data.get("name", ""), text), fontsize=10, color=colour, loc="left")
    ax.grid(alpha=0.3)
    fig.legend(loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(os.path.join(run_dir, "figures", "aor.png"), dpi=130)
    plt.close(fig)


def plot_bed(run_dir, data):
    fr = data["frame"]
    R = data["drum"]["radius_m"]
    mm = 1e3
    x, y, z, r = fr["x_m"], fr["y_m"], fr["z_m"], fr["radius_m"]
    q = fr["liquid_m3"]
    vmax = fr.get("liquid_color_max_m3") or max(q + [0.0])
    ul = 1e9  # m³ -> µL

    fig, ax = plt.subplots(figsize=(6.4, 6.6))
    # Seen along the axis from +z: the nearest particles (largest z) are drawn last, on top.
    order = sorted(range(len(x)), key=lambda i: z[i])
    circles = [Circle((x[i] * mm, y[i] * mm), r[i] * mm) for i in order]
    coll = PatchCollection(circles, cmap=BLUES, norm=Normalize(0.0, vmax * ul if vmax > 0 else 1.0),
                           edgecolor="0.35", linewidth=0.3)
    coll.set_array([q[i] * ul for i in order])
    ax.add_collection(coll)
    ax.add_patch(Circle((0, 0), R * mm, fill=False, lw=1.5, color="black"))
    ax.plot([0], [0], "+", color="0.4", ms=8)

    sf = data.get("surface", {})
    s = data["summary"]
    label = "no surface fitted"
    if sf.get("valid"):
        al = math.radians(sf["angle_deg"])
        tx, ty = math.cos(al), math.sin(al)
        nx, ny = -math.sin(al), math.cos(al)
        h = sf["height_m"]
        # The line p = h n + u t inside the drum: |h n + u t| <= R.
        half = math.sqrt(max(R * R - h * h, 0.0))
        ax.plot([(h * nx - half * tx) * mm, (h * nx + half * tx) * mm],
                [(h * ny - half * ty) * mm, (h * ny + half * ty) * mm], "--", color="tab:red", lw=1.2)
        layer = sf.get("layer", [])
        if layer:
            us = [x[i] * tx + y[i] * ty for i in layer]
            u0, u1 = min(us), max(us)
            ax.plot([(h * nx + u0 * tx) * mm, (h * nx + u1 * tx) * mm],
                    [(h * ny + u0 * ty) * mm, (h * ny + u1 * ty) * mm], "-", color="tab:red", lw=2.2)
        label = "free surface fitted to this frame: %.1f°\n(median of the top layer; solid: fitted columns)" % abs(
            sf["angle_deg"])
    ax.plot([], [], "-", color="tab:red", lw=2.2, label=label)
    om = data["drum"].get("omega_rad_s", 0.0)
    if om:  # the sense of rotation, outside the wall at the top (ω > 0: anticlockwise seen from +z)
        a0, a1 = (1.75, 1.39) if om < 0 else (1.39, 1.75)
        rr = R * mm * 1.03
        ax.annotate("", xy=(rr * math.cos(a1), rr * math.sin(a1)), xytext=(rr * math.cos(a0), rr * math.sin(a0)),
                    arrowprops=dict(arrowstyle="->", color="0.3", lw=1.2,
                                    connectionstyle="arc3,rad=%g" % (0.15 if om > 0 else -0.15)))
        ax.text(0, rr * 0.93, "drum turns", ha="center", va="top", fontsize=8, color="0.3")
    ax.set_aspect("equal")
    lim = R * mm * 1.08
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm), up")
    cb = fig.colorbar(coll, ax=ax, shrink=0.8, pad=0.02)
    cb.set_label("liquid per particle (µL): film + half of each bridge")
    title = "%s at t = %.2f s, seen along the drum axis (%d particles)" % (data.get("name", ""), fr["time_s"],
                                                                           len(x))
    sub = ""
    if s.get("aor_deg_mean") is not None and not s.get("aor_flag"):
        sub = "run's dynamic AoR %.1f° ± %.1f° over the window" % (s["aor_deg_mean"], s["aor_sem_block"])
    ax.set_title(title + ("\n" + sub if sub else ""), fontsize=9, loc="left")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), fontsize=8, frameon=False)
    fig.tight_layout()
    fig.savefig(os.path.join(run_dir, "figures", "bed.png"), dpi=130)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    run_dir = sys.argv[1]
    with open(os.path.join(run_dir, "figures", "plot_data.json")) as f:
        data = json.load(f)
    failed = []
    for name, fn in (("aor.png", plot_aor), ("bed.png", plot_bed)):
        try:
            fn(run_dir, data)
            print("wrote figures/" + name)
        except Exception as e:  # one figure failing must not stop the other; the exit code reports it
            failed.append("%s: %s: %s" % (name, type(e).__name__, e))
    for f in failed:
        print("FAILED " + f)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
