#!/usr/bin/python3
"""Figures of a wetdem diagnosis (DIR/diagnosis.json -> DIR/figures/*.png). Debian's matplotlib.

gap_map.png      cells (condition x observable) coloured by z, before and (if an effect was chosen) after
observables.png  each observable against its condition: observations with error bars, baseline band, the
                 chosen effect's band, and with refit the re-fitted null's band (when not the calibrated model)
ranking.png      held-out chi^2 of every fitted candidate against the null model (with refit: each one's setting),
                 each runner-up's near-tie zone (run fresh when its bar ends in it) and what the fresh runs made of
                 it (named, tied, or dropped with its fresh chi^2)
reach.png        what the table can see: each candidate's largest shift (sigma) in the table at the strongest
                 strength that ran (stepped past the file's probes where it showed nothing), beyond the table,
                 and on its fresh runs, against the 3 sigma from which a cell shows it
limits.png       after a no_gap: each candidate's runs set against the observations (signed sqrt of the chi^2
                 difference, in sigma), ruled out (filled) past the threshold, and the limit that brackets
next_experiment.png  when two effects tie: the best measurements that would separate them (and pairs of them,
                 and an assay on every sample), each as the fitted models' separation and what is left once each
                 model re-fits its strength to the other's value, against the separation the verdict needs
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(d):
    j = json.load(open(os.path.join(d, "diagnosis.json")))
    out = os.path.join(d, "figures")
    os.makedirs(out, exist_ok=True)
    cells = j["cells"]
    conds = list(dict.fromkeys(c["condition"] for c in cells))
    obs = list(dict.fromkeys(c["observable"] for c in cells))
    after = all("after" in c for c in cells)
    # A second effect fitted on top of the first (diagnosis.md, "A second effect"): the pair's fresh runs.
    second = (j.get("second") or {}).get("effect") if all("after_second" in c for c in cells) else None

    # The fresh runs drawn are the chosen effect's; when the verdict named none (its fresh runs did not confirm
    # it), they are still the best candidate's, and the label says so.
    fresh = j.get("fresh") or [{}]
    name = j["effect"] or f"{fresh[0].get('effect')}, not confirmed"

    # Gap map. Each panel's title carries the table's χ² against its 1 % point (diagnosis.md, "A gap spread
    # over the table"): a gap with no dark cell can still be one.
    # The table's test goes on a line of its own: three panels' one-line titles ran into each other.
    def table(t):
        return f"\nχ² {t['chi2']:.1f} over {t['cells']} cells, p = {t['p']:.2g}" if t else ""
    panels = [("baseline" + table(j.get("table")), lambda c: c["z"])] + (
        [(f"with {name}, fresh seeds" + table(fresh[0].get("table_after")), lambda c: c["after"]["z"])] if after else [])
    if second:
        s2 = j["second"]
        chi2 = f"\nχ² {s2['chi2_after']:.1f} over {len(cells)} cells" if s2.get("chi2_after") is not None else ""
        # Taken on through the joint fit (diagnosis.md, "A second effect", step 7): the first runs re-fitted.
        joint = s2.get("joint") or {}
        first = f"{j['effect']} at {joint['first_in_pair']:.3g}" if joint.get("named") else j["effect"]
        panels.append((f"with {first} + {second}, fresh seeds{chi2}", lambda c: c["after_second"]["z"]))
    # The panels share the condition axis (labels on the first only), each at least 3 inches wide for its title;
    # a cell without an observation is grey with a dash, not white (white is z = 0); |z| > 3 is written in white
    # on the dark colours.
    fig, axes = plt.subplots(1, len(panels), figsize=(2.8 + len(panels) * max(3.0, 0.85 * len(obs)), 2.4 + 0.45 * len(conds)),
                             squeeze=False, sharey=True, layout="constrained")
    cmap = plt.get_cmap("RdBu_r").copy()
    cmap.set_bad("0.85")
    for p, (ax, (title, zf)) in enumerate(zip(axes[0], panels)):
        m = [[float("nan")] * len(obs) for _ in conds]
        for c in cells:
            m[conds.index(c["condition"])][obs.index(c["observable"])] = zf(c)
        im = ax.imshow(m, cmap=cmap, vmin=-5, vmax=5, aspect="auto")
        ax.set_xticks(range(len(obs)), obs, rotation=30, ha="right", fontsize=8)
        if p == 0:
            ax.set_yticks(range(len(conds)), conds, fontsize=8)
        for i in range(len(conds)):
            for k in range(len(obs)):
                z = m[i][k]
                ax.text(k, i, "–" if z != z else f"{z:+.1f}", ha="center", va="center", fontsize=8,
                        color="white" if z == z and abs(z) > 3 else "black")
        ax.set_title(title, fontsize=9)
    # The constrained layout sets the title just above the panels' two-line titles and the colour bar beside the
    # last panel (a fixed offset left an inch of white above them and beside the bar).
    fig.suptitle("z = (obs − model) / √(σ² + SE²) per cell", fontsize=10)
    fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8, fraction=0.03, pad=0.01, label="z")
    fig.savefig(os.path.join(out, "gap_map.png"), dpi=120, bbox_inches="tight")
    plt.close(fig)

    # Observables against the condition: x is liquid.content when it varies (else the first key that does);
    # every other key that varies (drum.rpm, ...) makes groups drawn with their own marker and line style.
    keys = sorted({k for c in cells for k in c["condition_si"]})
    varying = [k for k in keys if len({c["condition_si"].get(k) for c in cells}) > 1]
    xkey = "liquid.content" if "liquid.content" in varying else (varying[0] if varying else (keys[0] if keys else None))
    gkeys = [k for k in varying if k != xkey]
    group_of = lambda c: tuple(c["condition_si"].get(k) for k in gkeys)  # noqa: E731
    groups = sorted({group_of(c) for c in cells}, key=lambda g: tuple(x if x is not None else 0 for x in g))
    styles = [("o", "-"), ("s", "--"), ("^", ":"), ("D", "-.")]
    # Group tags and the x axis in the table's own units (the condition label, e.g. "drum.rpm=30"), not SI
    # (rad/s); a liquid content is drawn in vol %.
    shown = {}
    for c in cells:
        for part in c["condition"].split(", "):
            k, _, v = part.partition("=")
            shown[(k, c["condition_si"].get(k))] = v
    xscale, xlabel = (100.0, "liquid content (vol %)") if xkey == "liquid.content" else (1.0, f"{xkey} (SI)")
    ncols = min(4, len(obs))
    nrows = (len(obs) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 3.3 * nrows + 0.8), squeeze=False)
    for ax in axes.flat[len(obs):]:
        ax.set_visible(False)
    for ax, o in zip(axes.flat, obs):
        for gi, g in enumerate(groups):
            mk, ls = styles[gi % len(styles)]
            tag = ", ".join(f"{k.split('.')[-1]} {shown.get((k, v), f'{v:g}')}" for k, v in zip(gkeys, g))
            sfx = f" [{tag}]" if tag else ""
            first = gi == 0
            cs = sorted([c for c in cells if c["observable"] == o and group_of(c) == g],
                        key=lambda c: c["condition_si"].get(xkey, 0))
            if not cs:
                continue
            x = [xscale * c["condition_si"].get(xkey, 0) for c in cs]
            m = [c["model"] for c in cs]
            s_ = [2 * c["model_se"] for c in cs]
            ax.fill_between(x, [a - b for a, b in zip(m, s_)], [a + b for a, b in zip(m, s_)], color="0.7", alpha=0.5,
                            label="model, baseline (±2 SE)" if first else None)
            ax.plot(x, m, color="0.35", ls=ls)
            if all("null_refit" in c for c in cs) and j.get("null_refit", {}).get("setting", 0) != 0:
                mr = [c["null_refit"]["model"] for c in cs]
                sr = [2 * c["null_refit"]["model_se"] for c in cs]
                ax.fill_between(x, [a - b for a, b in zip(mr, sr)], [a + b for a, b in zip(mr, sr)],
                                color="tab:green", alpha=0.25,
                                label=f"no effect, {j['null_refit']['label']} (±2 SE)" if first else None)
                ax.plot(x, mr, color="tab:green", ls=ls)
            # Fresh-seed bands of the chosen effect and of the pair (a second effect on top), ±2 SE.
            for key, on, colour, alpha, label in (("after", after, "tab:orange", 0.35, name),
                                                 ("after_second", second, "tab:purple", 0.3,
                                                  f"{j['effect']} + {second}")):
                if not on:
                    continue
                ma = [c[key]["model"] for c in cs]
                sa = [2 * c[key]["model_se"] for c in cs]
                ax.fill_between(x, [a - b for a, b in zip(ma, sa)], [a + b for a, b in zip(ma, sa)],
                                color=colour, alpha=alpha,
                                label=f"with {label}, fresh seeds (±2 SE)" if first else None)
                ax.plot(x, ma, color=colour, ls=ls)
            # With groups, the legend entry shows the group's line style with its marker: the model lines of
            # that group (e.g. the 60 rpm rows) are drawn dashed like it.
            ax.errorbar(x, [c["y"] for c in cs], yerr=[c["sigma"] for c in cs], fmt=mk, color="k", capsize=3,
                        label=None if tag else "observed (±σ)")
            if tag:
                ax.plot([], [], color="k", marker=mk, ls=ls, label="observed (±σ), model lines" + sfx)
        ax.set_xlabel(xlabel if xkey else "condition")
        ax.set_title(o, fontsize=9)
    # One legend for the figure (the first panel's entries: bands, then each group's observations).
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 5), fontsize=8, frameon=False)
    named = " + ".join(j.get("effects") or ([j["effect"]] if j["effect"] else []))
    title = f"{j['name']}: verdict {j['verdict']}" + (f" ({named})" if named else "")
    if j.get("tied"):
        title += ", tied with " + ", ".join(j["tied"])
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0, 0.6 / (3.3 * nrows + 0.8), 1, 1))
    fig.savefig(os.path.join(out, "observables.png"), dpi=120)
    plt.close(fig)

    # Ranking.
    rk = j.get("ranking") or []
    refit = lambda r: f"\n{r['refit']['label']}" if "refit" in r else ""  # noqa: E731
    null = "none (null)" + (f"\n{j['null_refit']['label']}" if "null_refit" in j else "")
    # What the verdict made of each candidate, on its bar: the one named, those tied with it, and those whose
    # probes the table cannot see (never named first on their held-out score alone: a lower bar can come second).
    # The one first held out whose fresh runs did not confirm it, when another's did (passed_over): why the
    # named bar is not the shortest.
    # A runner-up run fresh (a near tie) and then dropped by its fresh runs says so, with its fresh χ²: it
    # would otherwise look like one never run.
    unseen = set(j.get("unseen") or [])
    passed = (j.get("passed_over") or {}).get("effect")
    fresh = {f["effect"]: f.get("chi2_after") for f in (j.get("fresh") or []) if f.get("effect")}
    def role(e):
        r = "named" if e == j.get("effect") else "tied" if e in (j.get("tied") or []) else ""
        r = "not confirmed fresh" if e == passed else r
        if not r and e in fresh:
            r = "run fresh, dropped"
        if r and fresh.get(e) is not None:
            r += f": fresh χ² {fresh[e]:.3g}"
        return r + (", " if r else "") + "probes not seen" if e in unseen else r
    names = [null] + [r["effect"] + (f" ({role(r['effect'])})" if role(r["effect"]) else "") + refit(r) for r in rk]
    vals = [j["null_loco_chi2"]] + [r["loco_chi2"] for r in rk]
    fig, ax = plt.subplots(figsize=(9.0, 1 + (0.65 if "refit" in j else 0.4) * len(names)))
    shade = {"named": "tab:blue"}
    bars = ax.barh(range(len(names)), vals,
                   color=["0.6"] + [shade.get(role(r["effect"]).replace(":", ",").split(",")[0], "lightsteelblue") for r in rk])
    for b, r in zip(bars[1:], rk):
        if r["effect"] in unseen:
            b.set_hatch("///")
            b.set_edgecolor("0.3")
    ax.set_yticks(range(len(names)), names)
    ax.invert_yaxis()
    # The near-tie zone of each runner-up (verdict.h, near_tie_margin): from the first's held-out χ² to that
    # plus the larger of twice the tie margin and tie_noise standard deviations of the paired held-out
    # difference (the probes' noise). A bar ending inside its zone was run fresh, and the fresh runs decided.
    zone_label = "near-tie zone from the first\n(a bar ending in it is run fresh)"
    for i, r in enumerate(rk[1:], start=2):
        m = r.get("near_tie_margin")
        if m is None or not rk:
            continue
        lo = rk[0]["loco_chi2"]
        ax.errorbar([lo + m / 2], [i + 0.28], xerr=[[m / 2], [m / 2]], fmt="none", ecolor="tab:orange", elinewidth=2,
                    capsize=3, alpha=0.8, label=zone_label, zorder=3)
        zone_label = None
    # The chosen candidate's χ² is often a thousandth of the null's: a log axis, and each value written out.
    pos = [v for v in vals if v > 0]
    if pos and max(pos) > 100 * min(pos):
        ax.set_xscale("log")
    for i, v in enumerate(vals):
        ax.text(v, i, f" {v:.3g}", va="center", fontsize=8)
    # The rule's lines: the noise floor (what noise alone scores held out) and the effect margin a candidate
    # must reach (the floor plus `ratio` of the gap above it, and min_drop below the null).
    floor = j.get("noise_floor_chi2")
    rule = j.get("rule") or {}
    if floor is not None and vals and "ratio" in rule:
        margin = min(floor + rule["ratio"] * (vals[0] - floor), vals[0] - rule.get("min_drop", 0.0))
        if floor > 0:
            ax.axvline(floor, color="0.4", ls="--", lw=1, label=f"noise floor {floor:.3g}")
        ax.axvline(margin, color="tab:red", ls=":", lw=1.2, label=f"effect margin {margin:.3g}")
    if ax.get_legend_handles_labels()[0]:  # beside the axes: inside, it hides the bars' ends and whiskers
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.set_xlim(right=max(vals) * (3.0 if ax.get_xscale() == "log" else 1.15) if vals else 1)
    ax.set_xlabel("held-out χ² (leave one condition out)\nlower is better")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "ranking.png"), dpi=120, bbox_inches="tight")
    plt.close(fig)
    next_experiment(j, out)
    reach(j, out)
    limits(j, out)


def limits(j, out):
    """What a table without a gap rules out (diagnosis.md, stage 8b; limits.h): every run of every candidate."""
    rows = [x for x in (j.get("limits") or []) if x.get("runs")]
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(9.5, 1.3 + 0.55 * len(rows)))

    def signed_root(d):
        return (1 if d >= 0 else -1) * abs(d) ** 0.5

    vs = [signed_root(r["delta_chi2"]) for x in rows for r in x["runs"]]
    right = max([3.0] + vs)
    # Two runs closer than a label's width: the second label goes under its marker (and so on, alternating),
    # so that "0.009" and "0.0164" do not print over each other.
    near = 0.05 * (right * 1.1 - min([-3.0] + vs))
    for i, x in enumerate(rows):
        last, below = None, False
        for r in sorted(x["runs"], key=lambda r: r["delta_chi2"]):
            v = signed_root(r["delta_chi2"])
            below = (not below) if last is not None and v - last < near else False
            last = v
            out_ = r["ruled_out"]
            ax.plot(v, i, "o", ms=7, color="tab:red" if out_ else "white", mec="tab:red" if out_ else "tab:gray")
            # The run's own threshold (2 x its scatter when that is past the table's): a tick on the row.
            ax.plot(signed_root(r["rule_out_at"]), i, "|", color="tab:red", ms=11, alpha=0.5)
            ax.annotate(f"{r['strength']:.3g}", (v, i), textcoords="offset points", xytext=(0, -13 if below else 7),
                        ha="center", fontsize=6.5)
    labels = []
    # An effect with a second parameter has a row per value run, the default first, and a limit with that
    # parameter free (limits_free_shape), said on its first row.
    free = {f["effect"]: f for f in j.get("limits_free_shape") or []}
    for i, x in enumerate(rows):
        f = free.get(x["effect"])
        name = x["effect"] + (f" ({f['shape_name'].split(' (')[0]} = {x['shape']:g})" if f and x.get("shape") else "")
        if x["ruled_out_from"] > 0:
            lab = f"{name}: out from {x['ruled_out_from']:.3g}"
            if x.get("about", 0) > 0:
                lab += f"\n(limit about {x['about']:.3g})"
        else:
            lab = f"{name}: allowed to {x['allowed_to']:.3g}"
        if f and (i == 0 or rows[i - 1]["effect"] != x["effect"]):
            lab += (f"\n[{f['shape_name'].split(' (')[0]} free: out from {f['ruled_out_from']:.3g}]"
                    if f["ruled_out_from"] > 0 else f"\n[{f['shape_name'].split(' (')[0]} free: not ruled out]")
        labels.append(lab)
    t = rows[0]["threshold"] ** 0.5
    ax.axvline(t, color="tab:red", ls=":", lw=1.2, label=f"√Δχ² = {t:.2g}: a {t:.2g} σ shift not shown")
    ax.axvline(0, color="k", lw=0.6)
    ax.plot([], [], "o", color="tab:red", label="ruled out")
    ax.plot([], [], "o", color="white", mec="tab:gray", label="allowed")
    ax.plot([], [], "|", color="tab:red", alpha=0.5, ms=11, label="that run's threshold (with its seed scatter)")
    ax.set_yticks(range(len(rows)), labels, fontsize=7)
    ax.set_ylim(len(rows) - 0.4, -0.7)
    ax.set_xlim(min(-3.0, ax.get_xlim()[0]), right * 1.1)
    finish_rows(fig, ax, len(rows), "signed √Δχ²: how far the observations reject the run, in σ (strength by "
                "each marker)", "What this table rules out: each candidate's runs against the observations",
                os.path.join(out, "limits.png"), 0.12)


def reach(j, out):
    """What the table can see of each candidate (diagnosis.md, stage 8; power.h)."""
    rows = [r for r in (j.get("reach") or []) if r.get("strongest_probed", 0) > 0]
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(9.5, 1.3 + 0.5 * len(rows)))
    y = list(range(len(rows)))
    table = [r["max_abs_z"] for r in rows]
    beyond = [r.get("beyond_max_abs_z", 0.0) if r.get("beyond_condition") else 0.0 for r in rows]
    ax.barh(y, table, color="lightsteelblue", label="in the table (probe runs, strongest that ran)")
    ax.barh(y, beyond, height=0.4, color="tab:orange", label="beyond the table (where it comes closest)")
    fresh = [(i, r["fresh"]["max_abs_z"]) for i, r in enumerate(rows) if r.get("fresh")]
    if fresh:
        ax.plot([f[1] for f in fresh], [f[0] for f in fresh], "k^", ms=6, label="fresh runs at the fitted strength")
    # Where the strongest showed beyond the table by 3 sigma, weaker strengths ran there too (power.cpp,
    # beyond_weaker): each one's measured shift, on the same row.
    weaker = [(i, w["max_abs_z"], w["strength"]) for i, r in enumerate(rows)
              for w in ((r.get("beyond_weaker") or {}).get("runs") or [])]
    if weaker:
        ax.plot([w[1] for w in weaker], [w[0] for w in weaker], "D", color="saddlebrown", ms=5,
                label="beyond, at weaker strengths (the same seeds)")
    labels = []
    for i, r in enumerate(rows):
        top = max([table[i], beyond[i], r["fresh"]["max_abs_z"] if r.get("fresh") else 0.0] +
                  [w[1] for w in weaker if w[0] == i])
        where = (f"table: {r['cell']}" if table[i] >= beyond[i]
                 else f"beyond: {r['beyond_observable']} at {r['beyond_condition']}")
        # Under 3 sigma in one measurement but shown when repeated (power.cpp, beyond_repeats): say how often.
        if table[i] < beyond[i] < 3.0 and int(r.get("beyond_repeats") or 0) > 1:
            where += f" (3 σ when measured {int(r['beyond_repeats'])} times)"
        # The weaker strengths run there, in the text (markers close together would hide their labels).
        runs = [f"{w[2]:.3g}: {w[1]:.1f} σ" for w in weaker if w[0] == i]
        if runs:
            where += "\n  weaker, there: " + ", ".join(runs)
        ax.text(top, i, f"  {where}", va="center", fontsize=6.5)
        lab = f"{r['effect']} up to {r['strongest_probed']:.3g}"
        if r.get("extended_from", 0) > 0:
            lab += f"\n(stepped past {r['extended_from']:.3g})"
        labels.append(lab + ("" if r["visible"] else "  [unseen]"))
    ax.axvline(3.0, color="tab:red", ls=":", lw=1.2, label="3 σ: a cell shows it")
    ax.set_yticks(y, labels, fontsize=7)
    ax.invert_yaxis()
    right = max(max(table), max(beyond), max((f[1] for f in fresh), default=0.0),
                max((w[1] for w in weaker), default=0.0), 3.0)
    ax.set_xlim(0, right * 1.9)
    finish_rows(fig, ax, len(rows), "largest shift of one cell (σ of the cell's noise and the runs' own)",
                "What this table can see: each candidate against the model without it",
                os.path.join(out, "reach.png"), 0.1)


def finish_rows(fig, ax, n, xlabel, title, path, gap):
    """A figure of one row per candidate: its labels, the legend under it (`gap` below the axes), saved."""
    ax.set_xlabel(xlabel)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -gap - 0.4 / n), ncol=2, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


def next_experiment(j, out):
    """The next experiment's proposals (diagnosis.md, "The separation after re-fit")."""
    nx = j.get("next_experiment") or {}
    props = nx.get("proposals") or []
    if not props:
        return
    a, b = (nx.get("effects") or ["a", "b"])[:2]
    rows = []  # (label, plain, after re-fit or None)
    for q in props[:10]:
        where = "table" if q["in_table"] else "new"
        tag = f" [assay, {where}]" if q["assay"] else f" [{where}]"
        rows.append((f"{q['observable']} at {q['condition']}{tag}", q["separation"], q.get("refit_separation")))
    groups = [len(rows)]  # where the pairs start, then the series: a line between the groups
    for w in (nx.get("pairs") or [])[:3]:
        rows.append((f"pair: {w['first']['observable']} at {w['first']['condition']}\n"
                     f"   + {w['second']['observable']} at {w['second']['condition']}",
                     w["separation"], w["refit_separation"]))
    groups.append(len(rows))
    for s in nx.get("assay_series") or []:
        rows.append((f"{s['observable']} on every sample ({s['conditions']} conditions)", s["separation"],
                     s.get("refit_separation")))
    fig, ax = plt.subplots(figsize=(9.5, 1.2 + 0.42 * len(rows)))
    y = range(len(rows))
    ax.barh(y, [r[1] for r in rows], color="lightsteelblue", label=f"the fitted models ({a}, {b}) apart")
    ax.barh(y, [r[2] if r[2] is not None else 0 for r in rows], height=0.45, color="tab:blue",
            label="left once each re-fits its strength")
    for g in sorted(set(groups)):
        if 0 < g < len(rows):
            ax.axhline(g - 0.5, color="0.6", lw=0.8, ls="--")
    for i, r in enumerate(rows):
        # After the longer of the two bars: a re-fit can leave more apart than the plain fit (a rival that
        # cannot follow the other's value there), and the label must not sit on its bar.
        value = f" {r[1]:.2g}" + (f" / {r[2]:.2g}" if r[2] is not None else " / not re-fitted")
        ax.text(max(r[1], r[2] or 0.0), i, value, va="center", fontsize=7)
    need = max(2.0, nx.get("needed_separation") or 0.0)
    ax.axvline(need, color="tab:red", ls=":", lw=1.2, label=f"what the verdict needs: {need:.2g} σ")
    ax.set_yticks(list(y), [r[0] for r in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlim(right=max(max(max(r[1], r[2] or 0.0) for r in rows), need) * 1.3)
    ax.set_xlabel("separation (σ of the measurement and both models' errors)")
    ax.set_title(f"Next experiment: {a} or {b}? (single measurements, pairs, series; "
                 "each best first by what is left after the re-fit)", fontsize=9)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.07 - 0.35 / len(rows)), ncol=3, frameon=False)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "next_experiment.png"), dpi=120, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    main(sys.argv[1])
