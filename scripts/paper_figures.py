#!/usr/bin/python3
"""The paper's figures, tables and findings from the runs of scripts/paper.sh (issue 19, docs/paper.md).

Usage: /usr/bin/python3 scripts/paper_figures.py OUT [--size reduced|full] [--list-frames]

Reads the studies in OUT (pp2_l5, extended, pp2_l3, pp1_l5: each run's summary.json through index.json; twin,
pp2_l5/calibration, diagnosis) and writes:
  OUT/figures/pp2_l5_aor.png      AoR (mean, error bars: its standard deviation over the window) against the liquid
                                  content, one curve per V_max (paper Fig. 9)
  OUT/figures/pp2_l3_aor.png      PP2 at l = 3 against l = 5, the calibrated set (finding 5)
  OUT/figures/pp1_l5_aor.png      PP1 at l = 5, one panel per V_min, one curve per V_max (paper Fig. 11)
  OUT/figures/fwet_extended.png   f_wet against the liquid content up to 80 %, V_max 1 % and 10 % (paper Fig. 8)
  OUT/figures/beds.png            a dry and a 10 % bed seen along the axis, by liquid and by agglomerate
  OUT/paper.md                    every figure with the table of its numbers, the calibration, the findings table
  OUT/findings.json               the findings table as data
--list-frames prints the frames the bed picture reads (paths relative to OUT), for paper.sh --export.
Every number of the findings table is computed here from the runs' summaries; nothing is typed in.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

NOTES = {
    "reduced": "REDUCED: 60 mm periodic slice, 30 rpm, stiffness 1e5, 0.6 revolution (assets/paper/reduced/; "
               "not the paper's sizes)",
    "smoke": "SMOKE TEST: runs of 0.18 s on the reduced cases (assets/paper/smoke/): machinery only, no physics",
    "full": "",
}


# ---------------------------------------------------------------------------------------------- runs
def load_study(d):
    """Runs of a study directory: dicts with the axis values (SI), the summary (None if not complete), the dir."""
    p = os.path.join(d, "index.json")
    if not os.path.exists(p):
        return []
    ix = json.load(open(p))
    runs = []
    for r in ix["runs"]:
        rd = os.path.join(d, r["run_dir"])
        s = None
        sp = os.path.join(rd, "summary.json")
        if os.path.exists(sp):
            s = json.load(open(sp))
        vals = {v["key"]: v["si"] for v in r["values"]}
        runs.append({"values": vals, "summary": s, "dir": rd, "seed": r["seed"]})
    return runs


def val(run, key, default=None):
    v = run["values"].get(key)
    if v is None and run["summary"] is not None:
        # a key not varied by the study: the resolved case in the summary
        sec, _, leaf = key.partition(".")
        c = run["summary"].get("case", {}).get(sec, {})
        for k, x in c.items():
            if (k == leaf or k.startswith(leaf + "_")) and isinstance(x, (int, float)):
                return x
    return default if v is None else v


def num(s, key):
    if s is None:
        return None
    v = s.get(key)
    return v if isinstance(v, (int, float)) and not (isinstance(v, float) and math.isnan(v)) else None


def pct(x):
    return None if x is None else 100.0 * x


def fmt(x, nd=2):
    if x is None:
        return "–"
    return ("%." + str(nd) + "f") % x


def key_of(x):
    return round(x, 9) if x is not None else None


def table_md(header, rows):
    cell = lambda x: str(x).replace("|", "\\|")  # noqa: E731  (a '|' inside a cell would split it)
    out = ["| " + " | ".join(cell(h) for h in header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        out.append("| " + " | ".join(cell(x) for x in r) + " |")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------- figures
def wrap(note, width=95):
    import textwrap
    return "\n".join(textwrap.wrap(note, width)) if note else ""


def plt_setup():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def aor_curves(ax, runs, line_key, title, note, label_fmt="V_max = %g %%", shared_dry=True):
    """AoR mean ± sd against φ_L per value of line_key; the dry run (content 0) is drawn on every curve
    (shared_dry), or each curve has its own (the l = 3 / l = 5 comparison)."""
    dry = [r for r in runs if r["summary"] and key_of(val(r, "liquid.content")) == 0] if shared_dry else []
    lines = {}
    for r in runs:
        if not r["summary"] or (shared_dry and key_of(val(r, "liquid.content")) == 0):
            continue
        lines.setdefault(key_of(val(r, line_key)), []).append(r)
    keys = sorted(lines)
    for k, lv in enumerate(keys):
        pts = sorted(dry + lines[lv], key=lambda r: val(r, "liquid.content"))
        dodge = 0.1 * (k - 0.5 * (len(keys) - 1))  # curves side by side (in % of φ_L), so the error bars show
        xs = [pct(val(r, "liquid.content")) + dodge for r in pts if num(r["summary"], "aor_deg_mean") is not None]
        ys = [num(r["summary"], "aor_deg_mean") for r in pts if num(r["summary"], "aor_deg_mean") is not None]
        es = [num(r["summary"], "aor_deg_std") or 0 for r in pts if num(r["summary"], "aor_deg_mean") is not None]
        ss = [sem(r["summary"]) for r in pts if num(r["summary"], "aor_deg_mean") is not None]
        # Thin and faint: the sd over the window (the bed's fluctuation, the cohesive index); thick: the SEM of
        # the mean, which is what decides whether two curves differ.
        line = ax.errorbar(xs, ys, yerr=ss, marker="o", capsize=4, elinewidth=2.2, label=label_fmt % (100 * lv))
        ax.errorbar(xs, ys, yerr=es, fmt="none", ecolor=line[0].get_color(), elinewidth=0.8, alpha=0.35)
    ax.set_xlabel("liquid content φ_L (vol %%)%s" % (" (curves offset by up to ±%g %% to show their bars)" %
                                                     (0.05 * (len(keys) - 1)) if len(keys) > 1 else ""))
    ax.set_ylabel("dynamic angle of repose (deg)")
    done, planned = sum(1 for r in runs if r["summary"]), len(runs)
    part = "\n%d of %d runs complete: the missing points are not yet run" % (done, planned) if done < planned else ""
    ax.set_title(title + part + ("\n" + wrap(note, 85) if note else ""), fontsize=8.5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")


def aor_table(runs, line_key, line_name):
    contents = sorted({key_of(val(r, "liquid.content")) for r in runs if r["summary"]})
    lines = sorted({key_of(val(r, line_key)) for r in runs if r["summary"] and key_of(val(r, "liquid.content")) != 0})
    rows = []
    for c in contents:
        row = ["%g" % (100 * c)]
        for lv in lines:
            hit = [r for r in runs if r["summary"] and key_of(val(r, "liquid.content")) == c and
                   (c == 0 or key_of(val(r, line_key)) == lv)]
            if hit:
                s = hit[0]["summary"]
                row.append("%s ± %s (SEM %s)%s" % (fmt(num(s, "aor_deg_mean"), 1), fmt(num(s, "aor_deg_std"), 1),
                                                   fmt(num(s, "aor_sem_block"), 2),
                                                   " flagged" if s.get("aor_flag") else ""))
            else:
                row.append("–")
        rows.append(row)
    return table_md(["φ_L (%)"] + ["%s = %g %%" % (line_name, 100 * lv) for lv in lines], rows)


def fwet_runs(ext, pp2):
    """The extended stage's runs, with the PP2 l = 5 grid's runs at its V_max values and liquid contents it lacks
    (the same base case: 0, 1.25 and 2.5 %), so that each f_wet curve starts where the grid does. Where both hold
    a point the extended run is used (the two are bitwise the same run where both are complete)."""
    have = {(key_of(val(r, "liquid.content")), key_of(val(r, "liquid.v_max"))) for r in ext if r["summary"]}
    vms = {key_of(val(r, "liquid.v_max")) for r in ext}
    extra = [r for r in pp2 if r["summary"] and key_of(val(r, "liquid.v_max")) in vms and
             (key_of(val(r, "liquid.content")), key_of(val(r, "liquid.v_max"))) not in have and
             not (key_of(val(r, "liquid.content")) == 0 and any(k[0] == 0 for k in have))]
    return ext + extra


def fwet_figure(plt, ext, path, note):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    dry = [r for r in ext if r["summary"] and key_of(val(r, "liquid.content")) == 0]
    lines = {}
    for r in ext:
        if r["summary"] and key_of(val(r, "liquid.content")) != 0:
            lines.setdefault(key_of(val(r, "liquid.v_max")), []).append(r)
    rows = {}
    for lv in sorted(lines):
        pts = sorted(dry + lines[lv], key=lambda r: val(r, "liquid.content"))
        xs = [pct(val(r, "liquid.content")) for r in pts]
        ys = [num(r["summary"], "f_wet_mean") for r in pts]
        ax.plot(xs, ys, marker="o", label="V_max = %g %%" % (100 * lv))
        for x, y, r in zip(xs, ys, pts):
            rows.setdefault(x, {})[lv] = (y, num(r["summary"], "bridges_mean"))
    # Planned runs that are not complete are drawn as hollow triangles below the curves' range, so that a missing
    # point is not read as a curve that ends (nor as f_wet = 0).
    todo = [r for r in ext if not r["summary"]]
    for i, lv in enumerate(sorted(lines)):
        xs = [pct(val(r, "liquid.content")) for r in todo if key_of(val(r, "liquid.v_max")) == lv and
              key_of(val(r, "liquid.content")) != 0]
        if xs:
            ax.plot([x + (i - 0.5) * 1.2 for x in xs], [-0.04] * len(xs), linestyle="none", marker="^",
                    mfc="none", color="C%d" % i, label="V_max = %g %%: planned, not complete" % (100 * lv))
    if todo:
        ax.set_xlim(-2, max(pct(val(r, "liquid.content")) for r in ext) + 2)
        ax.set_ylim(-0.08, 1.05)
    ax.set_xlabel("liquid content φ_L (vol %)")
    ax.set_ylabel("fraction of wet contacts f_wet")
    ax.set_title("PP2 l = 5, V_min = 10 %%: f_wet against liquid content (paper Fig. 8)%s" %
                 ("\n" + wrap(note, 85) if note else ""), fontsize=8.5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    lvs = sorted(lines)
    t = table_md(["φ_L (%)"] + ["f_wet (bridges) at V_max = %g %%" % (100 * lv) for lv in lvs],
                 [["%g" % x] + ["%s (%s)" % (fmt(rows[x].get(lv, (None, None))[0], 3),
                                              fmt(rows[x].get(lv, (None, None))[1], 0)) for lv in lvs]
                  for x in sorted(rows)])
    return t


def last_frame(run):
    fj = os.path.join(run["dir"], "frames", "frames.json")
    if not os.path.exists(fj):
        return None
    frames = json.load(open(fj)).get("frames", [])
    if not frames:
        return None
    return os.path.join(run["dir"], "frames", sorted(frames, key=lambda f: f.get("step", 0))[-1]["file"])


def bed_runs(pp2):
    dry = [r for r in pp2 if r["summary"] and key_of(val(r, "liquid.content")) == 0]
    wet = [r for r in pp2 if r["summary"] and key_of(val(r, "liquid.content")) == key_of(0.1) and
           key_of(val(r, "liquid.v_max")) == key_of(0.01)]
    return (dry[0] if dry else None), (wet[0] if wet else None)


def beds_figure(plt, pp2, path, note):
    import bed_picture
    dry, wet = bed_runs(pp2)
    if not dry or not wet or not last_frame(dry) or not last_frame(wet):
        return None
    frames = [bed_picture.read_glb(last_frame(r)) for r in (dry, wet)]
    R = 0.5 * dry["summary"]["case"]["drum"]["diameter_m"]
    fig, axes = plt.subplots(2, 2, figsize=(9.0, 8.2))
    for col, (r, fr, name) in enumerate(zip((dry, wet), frames, ("dry", "10 %, V_max 1 %"))):
        t = fr["extras"].get("time", float("nan"))
        bed_picture.draw_bed(axes[0][col], fr, R, "liquid", title="%s, t = %.3g s: liquid" % (name, t),
                             liquid_max=0.1)
        bed_picture.draw_bed(axes[1][col], fr, R, "agglomerate",
                             title="%s: agglomerates, one colour each\n(grey: no bridge; window mean %s particles, "
                                   "D/d_eq %s)" %
                             (name, fmt(num(r["summary"], "agglomerate_size_mean"), 1),
                              fmt(num(r["summary"], "drum_to_agglomerate_ratio"), 1)))
    fig.suptitle("PP2 l = 5, last frame seen along the drum axis (the end plate's view)" +
                 ("\n" + wrap(note, 110) if note else ""), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [os.path.relpath(last_frame(r), os.path.dirname(os.path.dirname(path))) for r in (dry, wet)]


# ---------------------------------------------------------------------------------------------- findings
def find(runs, **kv):
    out = []
    for r in runs:
        if not r["summary"]:
            continue
        if all(key_of(val(r, k.replace("_", ".", 1))) == key_of(v) for k, v in kv.items()):
            out.append(r)
    return out


def one(runs, **kv):
    f = find(runs, **kv)
    return f[0]["summary"] if f else None


def sem(s):
    return num(s, "aor_sem_block") or num(s, "aor_sem_tau") or 0.0


def findings(st, cal, diag, truth):
    pp2, ext, l3, pp1 = st["pp2_l5"], st["extended"], st["pp2_l3"], st["pp1_l5"]
    rows = []

    def add(n, statement, measured, criterion, holds, note=""):
        rows.append({"finding": n, "statement": statement, "measured": measured, "criterion": criterion,
                     "holds": holds, "note": note})

    # 1. Onset.
    contents = sorted({key_of(val(r, "liquid.content")) for r in pp2 if r["summary"]})
    fw = {c: num(one(pp2, liquid_content=c, liquid_v_max=0.01) or one(pp2, liquid_content=c), "f_wet_mean")
          for c in contents}
    ao = {c: one(pp2, liquid_content=c, liquid_v_max=0.01) or one(pp2, liquid_content=c) for c in contents}
    if contents and ao.get(0.0):
        onset = next((c for c in contents if c > 0 and (fw.get(c) or 0) > 0.05), None)
        d0 = num(ao[0.0], "aor_deg_mean")
        rise = {c: (num(ao[c], "aor_deg_mean") - d0, 2 * math.hypot(sem(ao[c]), sem(ao[0.0])))
                for c in contents if c > 0 and ao.get(c) and num(ao[c], "aor_deg_mean") is not None and d0 is not None}
        flat_below = all(abs(d) <= e for c, (d, e) in rise.items() if c < 0.05 - 1e-9)
        up_above = all(d > e for c, (d, e) in rise.items() if c > 0.05 + 1e-9)
        measured = ("PP2 l = 5, V_max = 1 %%: f_wet > 0.05 first at φ_L = %s %% (f_wet %s); AoR − dry: %s" %
                    ("%g" % pct(onset) if onset is not None else "none",
                     ", ".join("%g %%: %s" % (pct(c), fmt(fw[c], 3)) for c in contents),
                     ", ".join("%g %%: %+.1f° (±%.1f)" % (pct(c), d, e) for c, (d, e) in sorted(rise.items()))))
        ok = onset is not None and abs(onset - 0.05) < 1e-9 and flat_below and up_above
        note = "" if ok else ("onset %s %% against 5 %%; AoR flat below 5 %%: %s; rising above: %s" % (
            "%g" % pct(onset) if onset is not None else "none", "yes" if flat_below else "no",
            "yes" if up_above else "no"))
        pp1_dry, pp1_first = one(pp1, liquid_content=0.0), one(pp1, liquid_content=0.0125, liquid_v_min=0.0,
                                                                liquid_v_max=0.01)
        if pp1_dry and pp1_first:
            d = num(pp1_first, "aor_deg_mean") - num(pp1_dry, "aor_deg_mean")
            e = 2 * math.hypot(sem(pp1_first), sem(pp1_dry))
            measured += ("; PP1 V_min = 0, V_max = 1 %%, 1.25 %%: AoR − dry %+.1f° (±%.1f), f_wet %s" %
                         (d, e, fmt(num(pp1_first, "f_wet_mean"), 3)))
            ok_pp1 = d > e and (num(pp1_first, "f_wet_mean") or 0) > 0.05
            if not ok_pp1:
                note += ("; " if note else "") + "PP1 not cohesive at 1.25 %% (AoR rise %+.1f° against ±%.1f)" % (d, e)
            ok = ok and ok_pp1
        add(1, "Onset: PP2 with V_min = 10 % bridges from φ_L ≈ 5 % (AoR flat up to 5 %, rising after); PP1 with "
            "V_min = 0 is cohesive from the first drop", measured,
            "f_wet > 0.05 first at 5 %; |AoR − dry| ≤ 2σ below 5 %, > 2σ above (σ: blocked SEMs combined); PP1 "
            "AoR(1.25 %) − dry > 2σ", "yes" if ok else "no", note)
    # 2. Saturation of f_wet. A curve has saturated only where its plateau is seen: its last two liquid contents
    # agree within 5 % of its top. A curve still rising at its last point says only that saturation lies beyond
    # it; the 95 %-of-top point of such a curve is an artefact of where the runs stop, not a saturation point.
    sat = {}
    for lv in (0.01, 0.1):
        pts = sorted((val(r, "liquid.content"), num(r["summary"], "f_wet_mean")) for r in fwet_runs(ext, pp2)
                     if r["summary"] and (key_of(val(r, "liquid.v_max")) == key_of(lv) or
                                          key_of(val(r, "liquid.content")) == 0))
        pts = [(c, f) for c, f in pts if f is not None]
        if sum(1 for c, _ in pts if c > 0) >= 2:
            top = max(f for _, f in pts)
            seen = abs(pts[-1][1] - pts[-2][1]) <= 0.05 * top
            sat[lv] = (next(c for c, f in pts if f >= 0.95 * top) if seen else None, top, pts)
    if len(sat) == 2:
        def curve(lv):
            s, top, pts = sat[lv]
            if s is not None:
                return "reaches 95 %% of its plateau (%s) at φ_L = %g %%" % (fmt(top, 3), pct(s))
            return "has not saturated by %g %%, still rising there (%s → %s from %g %%)" % (
                pct(pts[-1][0]), fmt(pts[-2][1], 3), fmt(pts[-1][1], 3), pct(pts[-2][0]))

        def judge(lv, lo, hi, later_ok):
            """True/False against the paper's range [lo, hi]; None while a curve still rises below hi (the runs
            above decide). A curve still rising past hi holds only where the paper says "and later"."""
            s, _, pts = sat[lv]
            if s is None:
                return None if pts[-1][0] < hi - 1e-9 else later_ok
            return lo - 1e-9 <= s <= hi + 1e-9
        s1, s10 = sat[0.01][0], sat[0.1][0]
        ok1 = judge(0.01, 0.05, 0.2, False)
        ok10 = judge(0.1, 0.2, 0.8, True)
        if ok10 and s1 is not None and s10 is not None:
            ok10 = s10 > s1
        holds = "no" if False in (ok1, ok10) else ("incomplete" if None in (ok1, ok10) else "yes")
        note = []
        for lv, ok, paper in ((0.01, ok1, "~10 %"), (0.1, ok10, "~40 %")):
            if ok is False:
                note.append("V_max = %g %%: f_wet %s, against %s" % (pct(lv), curve(lv), paper))
            elif ok is None:
                note.append("V_max = %g %%: still rising at %g %%, the last liquid content run; the runs above it "
                            "decide" % (pct(lv), pct(sat[lv][2][-1][0])))
        add(2, "Saturation of f_wet: near 10 vol % for V_max = 1 %, near 40 vol % (40–80) for V_max = 10 %",
            "f_wet at V_max = 1 %% %s; at V_max = 10 %% it %s" % (curve(0.01), curve(0.1)),
            "a plateau seen (last two points within 5 %); saturation point 5–20 % at V_max = 1 %, 20–80 % and "
            "later at V_max = 10 %", holds, "; ".join(note))
    # 3. Non-monotonic in V_max at 10 %.
    at10 = sorted((val(r, "liquid.v_max"), r["summary"]) for r in find(pp2, liquid_content=0.1))
    if len(at10) >= 3:
        aor = [(v, num(s, "aor_deg_mean")) for v, s in at10]
        br = [(v, num(s, "bridges_mean")) for v, s in at10]
        va = max(aor, key=lambda t: t[1] if t[1] is not None else -1e9)[0]
        vb = max(br, key=lambda t: t[1] if t[1] is not None else -1e9)[0]
        inner_a = va not in (at10[0][0], at10[-1][0])
        inner_b = vb not in (at10[0][0], at10[-1][0])
        ok = inner_a and inner_b and key_of(va) == key_of(0.01)
        add(3, "At φ_L = 10 % (PP2 l = 5) the AoR is non-monotonic in V_max, highest at V_max = 1 %, and so is the "
            "number of wet contacts",
            "AoR by V_max: %s; bridges: %s; maximum at %g %% (AoR), %g %% (bridges)" % (
                ", ".join("%g %%: %s°" % (pct(v), fmt(a, 1)) for v, a in aor),
                ", ".join("%g %%: %s" % (pct(v), fmt(b, 0)) for v, b in br), pct(va), pct(vb)),
            "interior maximum of both, the AoR's at 1 %", "yes" if ok else ("partly" if inner_a or inner_b else "no"),
            "" if ok else "AoR maximum at %g %% (%s), bridges at %g %% (%s)" % (
                pct(va), "interior" if inner_a else "at the grid's edge", pct(vb),
                "interior" if inner_b else "at the grid's edge"))
    # 4. Calibrated sets.
    if cal:
        best = cal.get("emulator", {}) or {}
        v, lo, hi = best.get("optimum"), best.get("interval_lo"), best.get("interval_hi")
        tv = 0.01
        inside = v is not None and lo is not None and hi is not None and lo <= tv <= hi
        add(4, "Calibrated sets: PP2 V_min = 10 %, V_max = 1 %; PP1 V_min = 0 %, V_max = 1 %",
            "PP2 l = 5 calibrated against the twin's table (truth V_max = 1 %% with pore absorption withheld): "
            "V_max = %s %% [%s, %s] (Δχ² = 1); best grid value %s %%" % (
                fmt(pct(v), 3), fmt(pct(lo), 3), fmt(pct(hi), 3), fmt(pct(cal.get("best_grid")), 3)),
            "the twin's V_max (1 %) inside the interval; the experiment's table is not public: the paper's own "
            "calibration cannot be redone", "yes (twin)" if inside else "no (twin)",
            "" if inside or v is None else "calibrated %s %% against the truth's 1 %% (×%.2g): the withheld absorption "
                                           "moves the calibrated V_max (what the diagnosis is for)" % (fmt(pct(v), 3),
                                                                                           v / tv))
    # 5. l = 3 against l = 5.
    if l3 and pp2:
        diffs = []
        for c in (0.0, 0.0125, 0.025):
            a, b = one(l3, liquid_content=c), (one(pp2, liquid_content=c, liquid_v_max=0.01) or
                                               (one(pp2, liquid_content=c) if c == 0 else None))
            if a and b and num(a, "aor_deg_mean") is not None and num(b, "aor_deg_mean") is not None:
                diffs.append((c, num(b, "aor_deg_mean") - num(a, "aor_deg_mean"), 2 * math.hypot(sem(a), sem(b))))
        a10, b10 = one(l3, liquid_content=0.1), one(pp2, liquid_content=0.1, liquid_v_max=0.01)
        r3, r5 = num(a10, "drum_to_agglomerate_ratio"), num(b10, "drum_to_agglomerate_ratio")
        agree = bool(diffs) and all(abs(d) <= e for _, d, e in diffs)
        clumps = r3 is not None and r5 is not None and r5 < r3 and r5 < 30
        add(5, "AoR at l = 3 and l = 5 agree for PP2 at low liquid; at 10 % the l = 5 bed clumps more "
            "(D / agglomerate size below ≈ 30)",
            "AoR(l5) − AoR(l3): %s; at 10 %%: D/d_eq = %s (l = 5), %s (l = 3); agglomerate %s / %s particles" % (
                ", ".join("%g %%: %+.1f° (±%.1f)" % (pct(c), d, e) for c, d, e in diffs), fmt(r5, 1), fmt(r3, 1),
                fmt(num(b10, "agglomerate_size_mean"), 1), fmt(num(a10, "agglomerate_size_mean"), 1)),
            "|ΔAoR| ≤ 2σ at φ_L ≤ 2.5 %; D/d_eq at l = 5 below 30 and below l = 3's",
            "yes" if agree and clumps else ("partly" if agree or clumps else "no"),
            "" if agree and clumps else "low-liquid AoRs %s; D/d_eq %s" % (
                "agree" if agree else "differ", "as stated" if clumps else "not below 30 or not below l = 3's"))
    # 6. PP1 at 10 %.
    at10 = [(val(r, "liquid.v_min"), val(r, "liquid.v_max"), num(r["summary"], "aor_deg_mean"))
            for r in find(pp1, liquid_content=0.1)]
    at10 = [t for t in at10 if t[2] is not None]
    add(6, "PP1 at 10 vol %: no (V_min, V_max) reproduces the experiment at l = 5 (the scaling gap)",
        ("PP1 AoR at 10 %% over %d (V_min, V_max): %s–%s°" % (len(at10), fmt(min(t[2] for t in at10), 1),
                                                            fmt(max(t[2] for t in at10), 1))) if at10 else
        "no PP1 runs at 10 %", "needs the experiment's AoR at 10 % (not public)", "not checkable",
        "the experimental value is only in the paper's figures")
    # 7. Segregation.
    d_ = one(pp2, liquid_content=0.0)
    w1 = one(pp2, liquid_content=0.0125, liquid_v_max=0.01)
    w10 = one(pp2, liquid_content=0.1, liquid_v_max=0.01)
    if d_ and w10 and num(d_, "surface_size_ratio") is not None:
        rd, r10 = num(d_, "surface_size_ratio"), num(w10, "surface_size_ratio")
        ed = num(d_, "surface_size_ratio_sem") or 0.0
        e10 = num(w10, "surface_size_ratio_sem") or 0.0
        r1 = num(w1, "surface_size_ratio") if w1 else None
        settled = settled_ratio(find(pp2, liquid_content=0.0)[0])
        ok = (r10 is not None and rd - r10 > 2 * math.hypot(ed, e10) and settled is not None and rd > settled)
        add(7, "Dry and lightly wet beds show mild size segregation (large particles at the free surface), "
            "suppressed by cohesion",
            "surface layer's mean radius / bed's: dry %s ± %s (settled, before turning: %s), 1.25 %% %s, 10 %% %s ± %s" %
            (fmt(rd, 3), fmt(ed, 3), fmt(settled, 3), fmt(r1, 3), fmt(r10, 3), fmt(e10, 3)),
            "dry > its settled bed, and dry − 10 % > 2σ", "yes" if ok else "no",
            "" if ok else "dry − 10 %% = %+.3f (±%.3f); dry − settled = %s" % (
                rd - (r10 or float("nan")), 2 * math.hypot(ed, e10),
                "%+.3f" % (rd - settled) if settled is not None else "–"))
    # A finding whose runs are missing (a stage not run, or too few runs) still gets its row.
    need = {1: "pp2_l5 (the dry run and V_max = 1 %; and pp1_l5)", 2: "extended, with both V_max curves",
            3: "pp2_l5 at three or more V_max", 4: "calibration", 5: "pp2_l3 and pp2_l5", 6: "pp1_l5",
            7: "pp2_l5 (dry and 10 %)"}
    stages = {1: ("pp2_l5", "pp1_l5"), 2: ("extended",), 3: ("pp2_l5",), 4: (), 5: ("pp2_l3", "pp2_l5"),
              6: ("pp1_l5",), 7: ("pp2_l5",)}
    have = {r["finding"] for r in rows}
    for k in sorted(need):
        if k not in have:
            # A stage that ran in part says how far it got: the missing runs, not the stage, are the reason.
            part = ["%s: %d of %d runs complete" % (n, sum(1 for r in st[n] if r["summary"]), len(st[n]))
                    for n in stages[k] if st[n]]
            add(k, STATEMENTS[k], "no data: needs the runs of " + need[k], "–", "no data",
                "; ".join(part) if part else "stage not run here")
    rows.sort(key=lambda r: r["finding"])
    return rows


STATEMENTS = {
    1: "Onset: PP2 with V_min = 10 % bridges from φ_L ≈ 5 % (AoR flat up to 5 %, rising after); PP1 with V_min = 0 "
       "is cohesive from the first drop",
    2: "Saturation of f_wet: near 10 vol % for V_max = 1 %, near 40 vol % (40–80) for V_max = 10 %",
    3: "At φ_L = 10 % (PP2 l = 5) the AoR is non-monotonic in V_max, highest at V_max = 1 %, and so is the number "
       "of wet contacts",
    4: "Calibrated sets: PP2 V_min = 10 %, V_max = 1 %; PP1 V_min = 0 %, V_max = 1 %",
    5: "AoR at l = 3 and l = 5 agree for PP2 at low liquid; at 10 % the l = 5 bed clumps more (D / agglomerate "
       "size below ≈ 30)",
    6: "PP1 at 10 vol %: no (V_min, V_max) reproduces the experiment at l = 5 (the scaling gap)",
    7: "Dry and lightly wet beds show mild size segregation (large particles at the free surface), suppressed by "
       "cohesion",
}


def settled_ratio(run):
    """surface_size_ratio of the last sample before the drum starts turning (the poured, settled bed)."""
    ts = os.path.join(run["dir"], "timeseries.csv")
    if not os.path.exists(ts):
        return None
    import csv
    settle = run["summary"]["case"]["run"]["settle_s"]
    last = None
    for row in csv.DictReader(open(ts)):
        t = float(row["time_s"]) if "time_s" in row else float(row["time"])
        if t <= settle + 1e-12 and row.get("surface_size_ratio"):
            last = float(row["surface_size_ratio"])
    return last


# ---------------------------------------------------------------------------------------------- main
def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    out = argv[1]
    size = argv[argv.index("--size") + 1] if "--size" in argv else (
        "full" if "full" in os.path.basename(os.path.abspath(out)) else "reduced")
    st = {k: load_study(os.path.join(out, k)) for k in ("pp2_l5", "extended", "pp2_l3", "pp1_l5")}
    if "--list-frames" in argv:
        for r in bed_runs(st["pp2_l5"]):
            if r and last_frame(r):
                print(os.path.relpath(last_frame(r), out))
        return 0
    plt = plt_setup()
    note = NOTES.get(size, "")
    figs = os.path.join(out, "figures")
    os.makedirs(figs, exist_ok=True)
    md = ["# The paper, reproduced%s" % ({"reduced": " at REDUCED size", "smoke": ": SMOKE TEST"}.get(size, "")), ""]
    if note:
        md += ["**%s.** Every number below comes from these cases, not from the paper's sizes." % note, ""]
    devices = sorted({r["summary"].get("device", "?") for s in st.values() for r in s if r["summary"]})
    versions = sorted({r["summary"].get("code_version", "?") for s in st.values() for r in s if r["summary"]})
    wall = sum((r["summary"].get("wall_time_s", 0) / max(1, r["summary"].get("ensemble", {}).get("runs", 1)))
               for s in st.values() for r in s if r["summary"])
    n_done = sum(1 for s in st.values() for r in s if r["summary"])
    n_all = sum(len(s) for s in st.values())
    # A stage may repeat another's points (the extended range holds some of the PP2 l = 5 grid's): the same
    # resolved case and seed end in the same final state, so distinct final states count the distinct runs.
    finals = {(r["summary"] or {}).get("final_state_hash") for s in st.values() for r in s if r["summary"]}
    finals.discard(None)
    twice = n_done - len(finals) if finals else 0
    md += ["Runs complete: %d of %d%s; device: %s; code: %s; run wall time (each run's share of its batch): %.0f s." %
           (n_done, n_all, " (%d of them the same run in two stages: the same final state)" % twice if twice > 0
            else "", ", ".join(devices) or "–", ", ".join(versions) or "–", wall), ""]

    def section(title, fig, table, caption):
        md.extend(["## " + title, ""])
        if fig:
            md.extend(["![%s](%s)" % (title, fig if "/" in fig else "figures/" + fig), ""])
        md.extend([caption + (" " + note if note else ""), "", table, ""])

    if st["pp2_l5"]:
        fig, ax = plt.subplots(figsize=(6.6, 4.6))
        aor_curves(ax, st["pp2_l5"], "liquid.v_max", "PP2 l = 5, V_min = 10 %: AoR, mean ± SEM (thick) and ± sd over the window (faint)", note)
        fig.tight_layout()
        fig.savefig(os.path.join(figs, "pp2_l5_aor.png"), dpi=120)
        plt.close(fig)
        section("PP2 at l = 5: AoR against liquid content (paper Fig. 9)", "pp2_l5_aor.png",
                aor_table(st["pp2_l5"], "liquid.v_max", "V_max"),
                "AoR in degrees: window mean ± standard deviation (SEM: blocked error of the mean). The dry run is "
                "one run drawn on every curve.")
    if st["pp2_l3"]:
        fig, ax = plt.subplots(figsize=(6.6, 4.6))
        both = [dict(r, values=dict(r["values"], scale=3)) for r in st["pp2_l3"]]
        l5 = [dict(r, values=dict(r["values"], scale=5)) for r in st["pp2_l5"]
              if key_of(val(r, "liquid.content")) == 0 or key_of(val(r, "liquid.v_max")) == key_of(0.01)]
        aor_curves(ax, both + l5, "scale", "PP2 at the calibrated set (V_min 10 %, V_max 1 %): l = 3 and l = 5",
                   note, label_fmt="l = %g", shared_dry=False)
        ax.legend(ax.get_legend_handles_labels()[0], ["l = 3", "l = 5"], fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(figs, "pp2_l3_aor.png"), dpi=120)
        plt.close(fig)
        rows = []
        for c in sorted({key_of(val(r, "liquid.content")) for r in st["pp2_l3"] if r["summary"]}):
            a = one(st["pp2_l3"], liquid_content=c)
            b = one(st["pp2_l5"], liquid_content=c, liquid_v_max=0.01) or (
                one(st["pp2_l5"], liquid_content=c) if c == 0 else None)
            rows.append(["%g" % (100 * c)] + ["%s ± %s" % (fmt(num(s, "aor_deg_mean"), 1), fmt(num(s, "aor_deg_std"), 1))
                                              for s in (a, b)] +
                        [fmt(num(s, "drum_to_agglomerate_ratio"), 1) for s in (a, b)] +
                        [fmt(num(s, "agglomerate_size_mean"), 1) for s in (a, b)])
        section("PP2 at l = 3 against l = 5 (finding 5)", "pp2_l3_aor.png",
                table_md(["φ_L (%)", "AoR l = 3", "AoR l = 5", "D/d_eq l = 3", "D/d_eq l = 5", "agglomerate l = 3",
                          "agglomerate l = 5"], rows),
                "AoR (deg, mean ± sd), D / agglomerate diameter and mass-weighted agglomerate size (particles).")
    if st["pp1_l5"]:
        vmins = sorted({key_of(val(r, "liquid.v_min")) for r in st["pp1_l5"] if r["summary"] and
                        key_of(val(r, "liquid.content")) != 0})
        fig, axes = plt.subplots(1, max(1, len(vmins)), figsize=(4.2 * max(1, len(vmins)), 4.4), squeeze=False)
        dry = [r for r in st["pp1_l5"] if key_of(val(r, "liquid.content")) == 0]
        tables = []
        for ax, vm in zip(axes[0], vmins):
            sub = dry + [r for r in st["pp1_l5"] if key_of(val(r, "liquid.v_min")) == vm and
                         key_of(val(r, "liquid.content")) != 0]
            aor_curves(ax, sub, "liquid.v_max", "PP1 l = 5, V_min = %g %%" % (100 * vm), "")
            tables.append("V_min = %g %%:\n\n%s" % (100 * vm, aor_table(sub, "liquid.v_max", "V_max")))
        if note:
            fig.suptitle(wrap(note, 120), fontsize=8.5)
        fig.tight_layout()
        fig.savefig(os.path.join(figs, "pp1_l5_aor.png"), dpi=110)
        plt.close(fig)
        section("PP1 at l = 5: one panel per V_min (paper Fig. 11)", "pp1_l5_aor.png", "\n\n".join(tables),
                "AoR in degrees: window mean ± standard deviation.")
    if st["extended"]:
        t = fwet_figure(plt, fwet_runs(st["extended"], st["pp2_l5"]), os.path.join(figs, "fwet_extended.png"), note)
        section("f_wet up to 80 % liquid (paper Fig. 8, finding 2)", "fwet_extended.png", t,
                "Window mean of f_wet = bridged pairs / (touching ∪ bridged pairs), and the mean number of bridges.")
    if st["pp2_l5"]:
        used = beds_figure(plt, st["pp2_l5"], os.path.join(figs, "beds.png"), note)
        if used:
            dry, wet = bed_runs(st["pp2_l5"])
            rows = [[name, fmt(num(r["summary"], "aor_deg_mean"), 1), fmt(num(r["summary"], "f_wet_mean"), 3),
                     fmt(num(r["summary"], "agglomerate_size_mean"), 1),
                     fmt(num(r["summary"], "drum_to_agglomerate_ratio"), 1),
                     fmt(num(r["summary"], "surface_size_ratio"), 3)]
                    for name, r in (("dry", dry), ("10 %, V_max 1 %", wet))]
            section("A dry and a wet bed", "beds.png",
                    table_md(["bed", "AoR (deg)", "f_wet", "agglomerate (particles)", "D/d_eq",
                              "surface / bed mean radius"], rows),
                    "Window means of the two runs drawn (the last frame). Frames: " + ", ".join(used) + ".")
    # Calibration and diagnosis.
    cal = None
    cp = os.path.join(out, "pp2_l5", "calibration", "calibration.json")
    if os.path.exists(cp):
        cj = json.load(open(cp))
        k = cj.get("fit", []).index("liquid.v_max") if "liquid.v_max" in cj.get("fit", []) else 0
        pick = lambda v: v[k] if isinstance(v, list) and len(v) > k else None  # noqa: E731
        cal = {"emulator": {"optimum": pick(cj.get("optimum")), "interval_lo": pick(cj.get("interval_lo")),
                            "interval_hi": pick(cj.get("interval_hi")),
                            "open": bool(pick(cj.get("interval_open_lo")) or pick(cj.get("interval_open_hi")))},
               "best_grid": pick(cj.get("best", {}).get("values")),
               "chi2_optimum": cj.get("chi2_optimum")}
    diag = None
    dp = os.path.join(out, "diagnosis", "diagnosis.json")
    if os.path.exists(dp):
        diag = json.load(open(dp))
    truth = None
    tp = os.path.join(out, "twin", "truth.json")
    if os.path.exists(tp):
        truth = json.load(open(tp))
    if cal or diag:
        rows = []
        if cal:
            e = cal["emulator"]
            rows.append(["calibrated V_max (emulator optimum, Δχ² = 1)", "%s %% [%s, %s]" % (
                fmt(pct(e.get("optimum")), 3), fmt(pct(e.get("interval_lo")), 3), fmt(pct(e.get("interval_hi")), 3)),
                "1 % (the twin's model)"])
        if diag:
            best = (diag.get("ranking") or [{}])[0]
            rows.append(["diagnosis verdict", "%s%s" % (diag.get("verdict"), (": " + str(diag.get("effect")))
                                                        if diag.get("effect") else ""), "absorption"])
            absn = [r for r in diag.get("ranking", []) if r.get("effect") == "absorption"]
            if absn:
                a = absn[0]
                iv = a.get("strength_interval") or [None, None]
                rows.append(["fitted absorption capacity", "%s [%s, %s]" % (fmt(a.get("strength"), 4),
                                                                           fmt(iv[0], 4), fmt(iv[1], 4)),
                             "0.03 (pores: 3 % of the particle volume)"])
            rows.append(["held-out shrink (1 − χ²_LOCO,best / χ²_null)", fmt(diag.get("held_out_shrink"), 3),
                         "–"])
            rows.append(["best-ranked candidate", str(best.get("effect")), "absorption"])
        section("Calibration and diagnosis on a twin with pore absorption withheld (item 5)",
                "pp2_l5/figures/chi2.png" if os.path.exists(os.path.join(out, "pp2_l5", "figures", "chi2.png"))
                else None,
                table_md(["quantity", "result", "truth"], rows),
                "The observation table is made by `wetdem twin` from the model with pores that soak up liquid "
                "(withheld); the PP2 l = 5 grid is calibrated against it (V_max), then `wetdem diagnose` looks for "
                "the missing effect. Details: twin/, pp2_l5/calibration/calibration.md, diagnosis/report.md.")
    rows = findings(st, cal, diag, truth)
    json.dump({"size": size, "note": note, "findings": rows}, open(os.path.join(out, "findings.json"), "w"), indent=1)
    md.extend(["## The findings of drum.md, checked" + (" (%s)" % size.upper() if note else ""), ""])
    if note:
        md.extend([note + ": these verdicts are about these cases.", ""])
    md.append(table_md(["#", "statement", "measured", "criterion", "holds", "by how much, where not"],
                       [[str(r["finding"]), r["statement"], r["measured"], r["criterion"], "**%s**" % r["holds"],
                         r["note"]] for r in rows]))
    md.append("")
    open(os.path.join(out, "paper.md"), "w").write("\n".join(md) + "\n")
    print("paper_figures: %s/paper.md, %s/figures/, %s/findings.json (%d findings)" % (out, out, out, len(rows)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
