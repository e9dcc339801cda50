#!/usr/bin/python3
"""Figures of a wetdem study directory (called by `wetdem study collect` and `wetdem calibrate`).

Usage: /usr/bin/python3 scripts/plot_study.py DIR   (Debian's python3-matplotlib)

Writes DIR/figures/*.png:
  aor_vs_liquid.png        AoR against liquid content, one line per value of the swept parameter, replicate
                           standard errors as error bars, observations (value +- sigma) on top (paper Figs. 9-11)
  fwet_vs_liquid.png       fraction of wet contacts against liquid content (Fig. 8)
  bridges_vs_vmax.png      liquid bridges (wet contacts) against V_max at the highest liquid content (Fig. 10)
  chi2.png                 calibration: chi2 against the fitted axis (1-D) or a chi2 map (2-D), optimum marked
  run_timeseries.png       AoR and f_wet against time for one run
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402


def read_csv(path):
    """Rows as dicts; lines starting with '#' are comments (observation tables may have them)."""
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def plain_log_ticks(axis):
    """Log axis labelled 0.1, 1, 10 rather than 10^-1, 10^0, 10^1."""
    axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: "%g" % v))


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def is_pct(rows, key):
    return all(str(r.get(key, "")).strip().endswith("%") for r in rows if r.get(key))


def label(key, pct):
    names = {"liquid.content": "liquid content φ_L", "liquid.v_max": "V_max / V̄_S",
             "liquid.v_min": "V_min / V̄_S"}
    return names.get(key, key) + (" (%)" if pct else " (SI)")


def scale(pct):
    return 100.0 if pct else 1.0


def by_line(points, x_key, line_key):
    """{line value (SI): [(x SI, point row)]}, sorted."""
    lines = {}
    for p in points:
        x = num(p.get(x_key + " [SI]"))
        lv = num(p.get(line_key + " [SI]")) if line_key else 0.0
        if x is None or lv is None:
            continue
        lines.setdefault(lv, []).append((x, p))
    return {k: sorted(v, key=lambda t: t[0]) for k, v in sorted(lines.items())}


def line_vs_x(ax, points, x_key, line_key, obs_key, xs_pct, ls_pct, written):
    for lv, pts in by_line(points, x_key, line_key).items():
        xs, ys, es = [], [], []
        for x, p in pts:
            y = num(p.get(obs_key + "_mean"))
            if y is None:
                continue
            xs.append(x * scale(xs_pct))
            ys.append(y)
            es.append(num(p.get(obs_key + "_se")) or 0.0)
        if not xs:
            continue
        name = written.get((line_key, lv), "%g" % (lv * scale(ls_pct))) if line_key else "runs"
        ax.errorbar(xs, ys, yerr=es, marker="o", capsize=3,
                    label=(label(line_key, False).split(" (")[0] + " = " + name) if line_key else name)


def main():
    d = sys.argv[1]
    fig_dir = os.path.join(d, "figures")
    os.makedirs(fig_dir, exist_ok=True)
    index = json.load(open(os.path.join(d, "index.json")))
    points = read_csv(os.path.join(d, "points.csv"))
    keys = index["axis_keys"]
    fit = index["observations"]["fit"]
    name = index["name"]
    written = {}
    for r in index["runs"]:
        for v in r["values"]:
            if v["si"] is not None:
                written[(v["key"], v["si"])] = v["written"]
    x_key = "liquid.content" if "liquid.content" in keys else (keys[0] if keys else None)
    others = [k for k in keys if k != x_key]
    line_key = next((k for k in fit if k != x_key), others[0] if others else None)
    made = []
    if x_key is None:
        print("plot_study: the study has no axes: no figures against an axis")
    obs_rows = []
    if index["observations"]["file"] and os.path.exists(index["observations"]["file"]):
        obs_rows = [r for r in read_csv(index["observations"]["file"])]

    if x_key:
        xs_pct = is_pct([{x_key: w} for (k, _), w in written.items() if k == x_key], x_key)
        ls_pct = bool(line_key) and is_pct([{line_key: w} for (k, _), w in written.items() if k == line_key],
                                           line_key)
        for obs_key, fname, ylabel, title in [
                ("aor_deg_mean", "aor_vs_liquid.png", "dynamic angle of repose (deg)", "AoR"),
                ("f_wet_mean", "fwet_vs_liquid.png", "fraction of wet contacts f_wet", "f_wet")]:
            fig, ax = plt.subplots(figsize=(6.4, 4.4))
            line_vs_x(ax, points, x_key, line_key, obs_key, xs_pct, ls_pct, written)
            obs = [r for r in obs_rows if r.get("observable") == obs_key and x_key in r]
            if obs:
                ox = []
                for r in obs:
                    v = r[x_key].strip()
                    ox.append(float(v.rstrip("%").strip()) if v.endswith("%") else float(v) * scale(xs_pct))
                ax.errorbar(ox, [float(r["value"]) for r in obs], yerr=[float(r["sigma"]) for r in obs],
                            fmt="s", color="black", mfc="white", capsize=4, label="observed (± σ)", zorder=5)
            ax.set_xlabel(label(x_key, xs_pct))
            ax.set_ylabel(ylabel)
            ax.set_title("%s: %s vs %s (mean ± SE over replicates)" % (name, title, x_key), fontsize=10)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
            fig.tight_layout()
            fig.savefig(os.path.join(fig_dir, fname), dpi=110)
            plt.close(fig)
            made.append(fname)

    vkey = "liquid.v_max" if "liquid.v_max" in keys else None
    if vkey and x_key and x_key != vkey:
        top = max((num(p.get(x_key + " [SI]")) for p in points if num(p.get(x_key + " [SI]")) is not None),
                  default=None)
        sel = sorted([(num(p[vkey + " [SI]"]), p) for p in points
                      if num(p.get(x_key + " [SI]")) == top and num(p.get(vkey + " [SI]"))],
                     key=lambda t: t[0])
        sel = [(v, p) for v, p in sel if num(p.get("bridges_mean_mean")) is not None]
        if sel:
            fig, ax = plt.subplots(figsize=(6.4, 4.4))
            ax.errorbar([v * 100 for v, _ in sel], [num(p["bridges_mean_mean"]) for _, p in sel],
                        yerr=[num(p.get("bridges_mean_se")) or 0 for _, p in sel], marker="o", capsize=3)
            ax.set_xscale("log")
            plain_log_ticks(ax.xaxis)
            ax.set_xlabel("V_max / V̄_S (%)")
            ax.set_ylabel("liquid bridges (wet contacts), window mean")
            ax.set_title("%s: wet contacts vs V_max at %s = %s" % (name, x_key, written.get((x_key, top), top)),
                         fontsize=10)
            ax.grid(alpha=0.3, which="both")
            fig.tight_layout()
            fig.savefig(os.path.join(fig_dir, "bridges_vs_vmax.png"), dpi=110)
            plt.close(fig)
            made.append("bridges_vs_vmax.png")

    cal = os.path.join(d, "calibration")
    if os.path.exists(os.path.join(cal, "calibration.json")):
        cj = json.load(open(os.path.join(cal, "calibration.json")))
        grid = read_csv(os.path.join(cal, "emulator.csv"))
        pts = read_csv(os.path.join(cal, "chi2.csv"))
        f = cj["fit"]
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        pct = [100.0 if k in ("liquid.v_max", "liquid.v_min", "liquid.content") else 1.0 for k in f]
        if len(f) == 1:
            k = f[0]
            ax.plot([float(g[k]) * pct[0] for g in grid], [float(g["chi2"]) for g in grid], label="emulator")
            ax.plot([float(p[k]) * pct[0] for p in pts if p["complete"] == "1"],
                    [float(p["chi2"]) for p in pts if p["complete"] == "1"], "o", label="grid points")
            ax.axvspan(cj["interval_lo"][0] * pct[0], cj["interval_hi"][0] * pct[0], alpha=0.2, color="C2",
                       label="Δχ² = 1 interval")
            ax.axvline(cj["optimum"][0] * pct[0], color="C2", label="optimum %.3g" % (cj["optimum"][0] * pct[0]))
            if cj["log_axis"][0]:
                ax.set_xscale("log")
                plain_log_ticks(ax.xaxis)
            ax.set_yscale("log")
            ax.set_xlabel(label(k, pct[0] == 100.0))
            ax.set_ylabel("χ²")
            ax.legend(fontsize=8)
        else:
            a, b = f[0], f[1]
            xs = sorted({float(g[a]) for g in grid})
            ys = sorted({float(g[b]) for g in grid})
            z = {(float(g[a]), float(g[b])): float(g["chi2"]) for g in grid}
            zz = [[math.log10(max(z.get((x, y), float("nan")), 1e-12)) for x in xs] for y in ys]
            m = ax.pcolormesh([x * pct[0] for x in xs], [y * pct[1] for y in ys], zz, shading="auto")
            fig.colorbar(m, ax=ax, label="log10 χ²")
            ax.plot([float(p[a]) * pct[0] for p in pts], [float(p[b]) * pct[1] for p in pts], "w.",
                    label="grid points")
            ax.plot([cj["optimum"][0] * pct[0]], [cj["optimum"][1] * pct[1]], "r*", ms=14, label="optimum")
            if cj["log_axis"][0]:
                ax.set_xscale("log")
            if cj["log_axis"][1]:
                ax.set_yscale("log")
            ax.set_xlabel(label(a, pct[0] == 100.0))
            ax.set_ylabel(label(b, pct[1] == 100.0))
            ax.legend(fontsize=8)
        ax.set_title("%s: calibration χ² (%d observations)" % (name, cj["observations"]), fontsize=10)
        ax.grid(alpha=0.3, which="both")
        fig.tight_layout()
        fig.savefig(os.path.join(fig_dir, "chi2.png"), dpi=110)
        plt.close(fig)
        made.append("chi2.png")

    # One run's time series: the first complete run at the highest liquid content.
    runs = read_csv(os.path.join(d, "runs.csv"))
    done = [r for r in runs if r["status"] == "complete"]
    if x_key:
        done.sort(key=lambda r: -(num(r.get(x_key + " [SI]")) or 0))
    if done:
        r = done[0]
        ts = read_csv(os.path.join(d, r["run_dir"], "timeseries.csv"))
        t = [float(x["time"]) for x in ts]
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        ax.plot([tt for tt, x in zip(t, ts) if x["aor_deg"]], [float(x["aor_deg"]) for x in ts if x["aor_deg"]],
                "C0.-", label="AoR (deg)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("AoR (deg)", color="C0")
        win = num(r.get("aor_window_length_s"))
        if win is not None and t:
            ax.axvspan(t[-1] - win, t[-1], alpha=0.12, color="gray", label="averaging window")
        ax2 = ax.twinx()
        ax2.plot(t, [float(x["f_wet"]) for x in ts], "C1.-", label="f_wet")
        ax2.set_ylabel("f_wet", color="C1")
        ax2.set_ylim(0, 1.05)
        vals = ", ".join("%s = %s" % (k, r[k]) for k in keys if r.get(k))
        ax.set_title("%s run %s (%s, seed %s)" % (name, r["index"], vals, r["seed"]), fontsize=9)
        ax.grid(alpha=0.3)
        h1, l1 = ax.get_legend_handles_labels()
        h2, l2 = ax2.get_legend_handles_labels()
        ax.legend(h1 + h2, l1 + l2, loc="center left", fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(fig_dir, "run_timeseries.png"), dpi=110)
        plt.close(fig)
        made.append("run_timeseries.png")
    print("plot_study: wrote " + ", ".join(made))


if __name__ == "__main__":
    main()
