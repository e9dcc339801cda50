#!/usr/bin/python3
"""Validation matrix of the sim-to-real diagnosis (diagnosis.md §5; docs/diagnosis.md).

For every candidate effect at a weak and a strong strength, plus null twins, it writes a twin file, runs
`wetdem twin` (truth seeds of its own) and `wetdem diagnose` against the twin's observations, all through one
shared run store, and writes OUT/matrix.json and OUT/matrix.md: the confusion matrix (truth -> verdict/effect),
the top-1 identification rate over effect twins, the median held-out shrink where the verdict is `effect`, the
null outcomes, the device and the wall time.

  /usr/bin/python3 scripts/twin_matrix.py --wetdem build/host/wetdem --out matrix \
      --diagnosis assets/diagnosis/micro/diagnose.toml --twin-base assets/diagnosis/micro/twin_null.toml
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time

# Truth overrides per effect: (weak, strong), as case keys the diagnosis is not told about.
TRUTHS = {
    "cohesion": ('"cohesion.surface_energy" = "0.03 J/m2"', '"cohesion.surface_energy" = "0.1 J/m2"'),
    "absorption": ('"absorption.capacity" = 0.02\n"absorption.rate" = 10.0',
                   '"absorption.capacity" = 0.08\n"absorption.rate" = 10.0'),
    "evaporation": ('"liquid.evaporation_time" = "5 s"', '"liquid.evaporation_time" = "1 s"'),
    "spread": ('"liquid.wetted_fraction" = 0.6', '"liquid.wetted_fraction" = 0.25'),
    "viscous": ('"liquid.viscosity" = "0.01 Pa s"', '"liquid.viscosity" = "0.2 Pa s"'),
    "hysteresis": ('"liquid.theta_receding" = "20 deg"', '"liquid.theta_receding" = "2 deg"'),
}

# The same truths in the diagnosis's strength units (host/diagnose/effects.cpp; theta = 30 deg for hysteresis).
TRUTH_STRENGTH = {"cohesion": (0.03, 0.1), "absorption": (0.02, 0.08), "evaporation": (0.2, 1.0),
                  "spread": (0.4, 0.75), "viscous": (0.01, 0.2), "hysteresis": (10.0, 28.0)}


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)} (see {log})")


def row_of(d, name, effect, truth, twins):
    j = json.load(open(os.path.join(d, "diagnosis", "diagnosis.json")))
    level = name.rsplit("-", 1)[-1]
    ts = TRUTH_STRENGTH.get(effect, (None, None))[0 if level == "weak" else 1] if effect else None
    best = next((r for r in j.get("ranking") or [] if r["effect"] == j["effect"]), None)
    return {"twin": name, "truth": effect, "truth_strength": ts, "verdict": j["verdict"], "effect": j["effect"],
            "strength": best["strength"] if best else None,
            "interval": best["strength_interval"] if best else None,
            "held_out_shrink": j["held_out_shrink"], "device": j["device"]}


def outcome(r):
    return r["effect"] if r["verdict"] == "effect" else r["verdict"]


def confusion(rows):
    truths = list(dict.fromkeys(r["truth"] or "none" for r in rows))
    cols = list(dict.fromkeys([t for t in truths if t != "none"] + [outcome(r) for r in rows]))
    cols = [c for c in cols if c not in ("no_gap", "unexplained")] + ["no_gap", "unexplained"]
    md = ["Confusion matrix (rows: the withheld truth; columns: the diagnosis's outcome)", "",
          "| truth \\ outcome | " + " | ".join(cols) + " |", "|---" * (len(cols) + 1) + "|"]
    for t in truths:
        n = [sum(1 for r in rows if (r["truth"] or "none") == t and outcome(r) == c) for c in cols]
        md.append(f"| {t} | " + " | ".join(str(x) if x else "" for x in n) + " |")
    return md


def plot(rows, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    truths = list(dict.fromkeys(r["truth"] or "none" for r in rows))
    cols = [t for t in truths if t != "none"] + ["no_gap", "unexplained"]
    cols += [c for c in dict.fromkeys(outcome(r) for r in rows) if c not in cols]
    m = [[sum(1 for r in rows if (r["truth"] or "none") == t and outcome(r) == c) for c in cols] for t in truths]
    fig, ax = plt.subplots(figsize=(1.1 * len(cols) + 2, 0.6 * len(truths) + 1.8))
    top = max(2, max(max(x) for x in m))
    ax.imshow(m, cmap="Blues", vmin=0, vmax=top)
    for i, row in enumerate(m):
        for k, x in enumerate(row):
            if x:
                ax.text(k, i, str(x), ha="center", va="center", color="white" if x > top / 2 else "black",
                        fontsize=12)
            if truths[i] == cols[k] or (truths[i] == "none" and cols[k] in ("no_gap", "unexplained")):
                ax.add_patch(plt.Rectangle((k - 0.5, i - 0.5), 1, 1, fill=False, ec="tab:green", lw=2))
    ax.set_xticks(range(len(cols)), cols, rotation=30, ha="right")
    ax.set_yticks(range(len(truths)), truths)
    ax.set_xlabel("diagnosis outcome")
    ax.set_ylabel("withheld truth (twin)")
    ax.set_title("Twin matrix: withheld effect vs diagnosis (green: a right answer)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--wetdem", default="build/host/wetdem")
    ap.add_argument("--out", required=True)
    ap.add_argument("--diagnosis", required=True, help="diagnosis file (its effects are the candidates)")
    ap.add_argument("--twin-base", required=True, help="a null twin file: case, conditions, seeds, noise")
    ap.add_argument("--effects", nargs="*", help="truth effects (default: the diagnosis file's)")
    ap.add_argument("--nulls", type=int, default=2)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--store", help="run store (default OUT/store); share one across matrices to reuse runs")
    ap.add_argument("--summarize", action="store_true",
                    help="only (re)write matrix.json/.md/.png from the twin folders already in --out")
    ap.add_argument("--perturb", action="append", default=[],
                    help="a truth key every twin also differs in, e.g. 'psd.tails = \"lognormal\"' or "
                         "'scaling = 4.5' (diagnosis.md §5: a real system differs in more than one way)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    store = a.store or os.path.join(a.out, "store")
    base = open(a.twin_base).read()
    base_dir = os.path.dirname(os.path.abspath(a.twin_base))
    base = re.sub(r'^case\s*=\s*"([^"]+)"', lambda m: f'case = "{os.path.join(base_dir, m.group(1))}"', base,
                  flags=re.M)
    effects = a.effects or re.findall(r'"(\w+)"', re.search(r"^effects\s*=\s*\[(.*)\]", open(a.diagnosis).read(),
                                                                      re.M).group(1))
    twins = []
    for e in effects:
        for level, truth in zip(("weak", "strong"), TRUTHS[e]):
            twins.append((f"{e}-{level}", e, truth))
    for k in range(a.nulls):
        twins.append((f"null-{k + 1}", None, ""))
    t0 = time.time()
    rows = []
    for i, (name, effect, truth) in enumerate(twins):
        d = os.path.join(a.out, name)
        if a.summarize:
            if os.path.exists(os.path.join(d, "diagnosis", "diagnosis.json")):
                rows.append(row_of(d, name, effect, truth, twins))
            continue
        os.makedirs(d, exist_ok=True)
        text = re.sub(r"^seeds\s*=.*$", f"seeds = [{1000 + 10 * i}, {1001 + 10 * i}]", base, flags=re.M)
        text = re.sub(r"^noise_seed\s*=.*$", f"noise_seed = {500 + i}", text, flags=re.M)
        text = re.sub(r"^\[truth\][^\[]*", "", text, flags=re.M)
        if truth or a.perturb:
            text += "\n[truth]\n" + "\n".join([truth] + a.perturb if truth else a.perturb) + "\n"
        tf = os.path.join(d, "twin.toml")
        open(tf, "w").write(text)
        run([a.wetdem, "twin", tf, "--out", os.path.join(d, "twin"), "--store", store, "--jobs", str(a.jobs),
             "--quiet"], os.path.join(d, "twin.log"))
        # The diagnosis sees the observations only (truth.json stays in the twin folder).
        run([a.wetdem, "diagnose", a.diagnosis, "--observations", os.path.join(d, "twin", "observations.csv"),
             "--out", os.path.join(d, "diagnosis"), "--store", store, "--jobs", str(a.jobs), "--quiet",
             "--no-figures"], os.path.join(d, "diagnose.log"))
        rows.append(row_of(d, name, effect, truth, twins))
        print(f"{name}: {rows[-1]['verdict']} {rows[-1]['effect'] or ''}", flush=True)
    wall = time.time() - t0
    if a.summarize:
        old = os.path.join(a.out, "matrix.json")
        wall = json.load(open(old))["wall_s"] if os.path.exists(old) else float("nan")
    eff = [r for r in rows if r["truth"]]
    hits = sum(1 for r in eff if r["verdict"] == "effect" and r["effect"] == r["truth"])
    shrinks = [r["held_out_shrink"] for r in rows if r["verdict"] == "effect" and r["held_out_shrink"] is not None]
    nulls = [r for r in rows if not r["truth"]]
    out = {"perturb": a.perturb, "rows": rows, "top1_rate": hits / len(eff) if eff else None,
           "median_held_out_shrink": statistics.median(shrinks) if shrinks else None,
           "nulls_ok": sum(1 for r in nulls if r["verdict"] != "effect"), "nulls": len(nulls),
           "device": next((r["device"] for r in rows if r["device"]), ""), "wall_s": wall}
    json.dump(out, open(os.path.join(a.out, "matrix.json"), "w"), indent=2)
    md = ["| twin | truth | truth strength | verdict | chosen | fitted strength [interval] | held-out shrink |",
          "|---|---|---|---|---|---|---|"]
    for r in rows:
        s = r["held_out_shrink"]
        fit = "" if r["strength"] is None else f"{r['strength']:.3g} [{r['interval'][0]:.3g}, {r['interval'][1]:.3g}]"
        ts = "" if r["truth_strength"] is None else f"{r['truth_strength']:.3g}"
        md.append(f"| {r['twin']} | {r['truth'] or 'none'} | {ts} | {r['verdict']} | {r['effect'] or '-'} | {fit} | "
                  f"{'' if s is None else f'{100 * s:.0f} %'} |")
    md.append("")
    md += confusion(rows)
    md.append("")
    md.append(f"Top-1 identification: {hits}/{len(eff)}; median held-out shrink where `effect`: "
              f"{'-' if not shrinks else f'{100 * statistics.median(shrinks):.0f} %'}; nulls without an effect: "
              f"{out['nulls_ok']}/{len(nulls)}; device {out['device']}; wall {wall:.0f} s."
              + (f" Every truth also differs in: {'; '.join(a.perturb)}." if a.perturb else ""))
    open(os.path.join(a.out, "matrix.md"), "w").write("\n".join(md) + "\n")
    plot(rows, os.path.join(a.out, "matrix.png"))
    print("\n".join(md))


if __name__ == "__main__":
    main()
