#!/usr/bin/python3
"""Validation matrix of the sim-to-real diagnosis (diagnosis.md §5; docs/diagnosis.md, "Validation matrix").

A matrix file (TOML) names the diagnosis, a base twin (case, conditions, noise) and the twins: each with its
withheld truth (case overrides), the truth's strength in the diagnosis's units (for the strength and interval
scores), and optionally something else the truth differs in (coarse-graining, PSD tails) or an effect outside
the candidates. When that other difference is itself a candidate (l = 4 is `scale` at 0.2), `also_effect` and
`also_strength` name it: the twin then withholds two candidates, and a diagnosis that names the other one is
counted apart (neither a hit on the named truth nor a confident wrong answer). For every twin the script
writes a twin file with truth seeds and a noise seed of its own (the i-th twin: seeds truth_seeds_from + 10 i
and + 10 i + 1, noise seed noise_seed_from + i; top-level keys, 1000 and 500 by default, so a second matrix of
unseen twins draws other seeds), runs `wetdem twin` and `wetdem diagnose`
(the diagnosis never sees truth.json), all through one shared run store, and writes OUT/matrix.json, OUT/matrix.md and OUT/matrix.png:
  - the confusion matrix (truth -> outcome: the chosen effect for `effect`/`partial`, else the verdict);
  - identified (top-1): the truth is named (`effect` or `partial`; first, or as the second effect fitted on
    top) and nothing the twin did not withhold is named, over the effect twins; apart, over the twins whose
    truth the table can show at all (signal: the noiseless truth moves some cell by >= 3 sigma);
  - the median held-out shrink over the correctly identified twins;
  - strength: the fitted strength within +-25 % of the truth, and the interval covering it (the reported 1-SE one,
    and apart the one at 2 SE), over those twins;
  - nulls and outside effects: any `effect` verdict is a confident wrong answer (`partial` is hedged);
  - the device and the wall time: each twin's cost is that of the call that computed its runs (OUT/<twin>/
    cost.json: wall, twin runs included, runs computed, the diagnosis's stages; each --measure-next round's in
    cost_m<k>.json, its measurements included), so a re-evaluation from the store (seconds) does not overwrite
    it; a twin's cost sums its rounds up to the one reported, and the matrix's wall is the twins' sum.

  /usr/bin/python3 scripts/twin_matrix.py assets/diagnosis/flowing/matrix.toml --out matrix --jobs 2 --batch 4

Where Python 3.11 is missing (a lent GPU machine), `--script FILE` writes the twin files and a bash script of the
same `wetdem twin` / `wetdem diagnose` calls instead of running them (paths relative to the project root; the
binary from $WETDEM; a twin whose diagnosis.json exists is skipped, so a cut script resumes through the store).
Bring OUT back and run `--summarize` here.
"""
import argparse
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import time
import tomllib


def load_json(path):
    with open(path) as f:
        return json.load(f)


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)} (see {log})")


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    return json.dumps(str(v))


def twin_text(base, base_dir, seeds, noise_seed, overrides):
    text = re.sub(r'^case\s*=\s*"([^"]+)"', lambda m: f'case = "{os.path.join(base_dir, m.group(1))}"', base,
                  flags=re.M)
    text = re.sub(r"^seeds\s*=.*$", f"seeds = [{', '.join(str(s) for s in seeds)}]", text, flags=re.M)
    text = re.sub(r"^noise_seed\s*=.*$", f"noise_seed = {noise_seed}", text, flags=re.M)
    text = re.sub(r"^\[truth\][^\[]*", "", text, flags=re.M)
    if overrides:
        text += "\n[truth]\n" + "".join(f'"{k}" = {toml_value(v)}\n' for k, v in overrides.items())
    return text


def signal(d, j):
    """How visible the withheld truth is in this table, before any noise: the noiseless truth (truth.json) against
    the diagnosis's baseline model, z = (truth - model) / sqrt(sigma^2 + model_se^2) per cell. A twin whose
    largest |z| is under 3 carries no cell a lab would call significant even without noise: no method can be
    asked to find its effect there (the issue's "weak": just detectable, ~3 sigma at one condition)."""
    path = os.path.join(d, "twin", "truth.json")
    if not os.path.exists(path):
        return None
    noiseless = {(n["condition"], n["observable"]): n["mean"] for n in load_json(path).get("noiseless", [])}
    zs = []
    for c in j.get("cells") or []:
        m = noiseless.get((c["condition"], c["observable"]))
        if m is None or c.get("sigma") is None or c.get("model") is None:
            continue
        zs.append(((m - c["model"]) / (c["sigma"] ** 2 + (c.get("model_se") or 0) ** 2) ** 0.5,
                   f"{c['observable']} at {c['condition']}"))
    if not zs:
        return None
    z, where = max(zs, key=lambda x: abs(x[0]))
    return {"max_abs_z": abs(z), "where": where, "chi2": sum(x * x for x, _ in zs), "cells": len(zs)}


def last_diagnosis(d):
    """The diagnosis folder the matrix reports: the last round of --measure-next (diagnosis_m1, _m2, ...) when there
    is one, else the first diagnosis."""
    rounds = sorted((int(m.group(1)), m.group(0)) for m in
                    (re.fullmatch(r"diagnosis_m(\d+)", x) for x in os.listdir(d)) if m
                    and os.path.exists(os.path.join(d, m.group(0), "diagnosis.json")))
    return rounds[-1][1] if rounds else "diagnosis"


# The case key of each candidate's second parameter (host/diagnose/effects.cpp), to find a truth's own rate.
SHAPE_KEYS = {"absorption": "absorption.rate"}


def row_of(d, t):
    sub = last_diagnosis(d)
    j = load_json(os.path.join(d, sub, "diagnosis.json"))
    first = j if sub == "diagnosis" else load_json(os.path.join(d, "diagnosis", "diagnosis.json"))
    # What was measured up to the reported round (measured.json: one entry per round's table).
    rounds = load_json(os.path.join(d, "measured.json")) if sub != "diagnosis" else []
    upto = int(sub[len("diagnosis_m"):]) if sub != "diagnosis" else 0
    measured = [m for e in rounds if int(re.search(r"_m(\d+)", e["table"]).group(1)) <= upto for m in e["measured"]]
    best = next((r for r in j.get("ranking") or [] if r["effect"] == j["effect"]), None)
    # The second effect's own fit in its round's ranking (empty when there is none).
    second = j.get("second") or {}
    second_fit = next((x for x in second.get("ranking") or [] if x["effect"] == second.get("effect")), {})
    # After a no_gap: what the table rules out of the truth's candidate (diagnosis.md, stage 8b).
    # The default shape's row comes first. A sink whose truth rate was run is judged against that rate's row
    # (the report claims it); at another rate, against the limit with the rate free (limits_free_shape: ruled
    # out only where every rate run rules it out).
    lims = [x for x in j.get("limits") or [] if x["effect"] == t.get("effect")]
    lim = lims[0] if lims else None
    free = next((x for x in j.get("limits_free_shape") or [] if x["effect"] == t.get("effect")), None)
    truth_shape = (t.get("truth") or {}).get(SHAPE_KEYS.get(t.get("effect"), ""))
    at_truth = next((x for x in lims if truth_shape is not None and x.get("shape")
                     and abs(x["shape"] / float(truth_shape) - 1) < 1e-9), None)
    truth_limit = None if not lim else {k: (at_truth or lim)[k] for k in ("ruled_out_from", "allowed_to", "about")}
    if truth_limit and at_truth and free:
        truth_limit["at_shape"] = at_truth["shape"]
    elif truth_limit and free:
        truth_limit.update(ruled_out_from=free["ruled_out_from"], free_shape=True)
    return {"truth_limit": truth_limit,
            "twin": t["name"], "truth": t.get("effect"), "truth_strength": t.get("strength"),
            "perturbed": bool(t.get("perturb")), "also": t.get("also_effect"),
            "also_strength": t.get("also_strength"), "verdict": j["verdict"], "effect": j["effect"],
            "tied": j.get("tied") or [],
            # A second effect fitted on top of the first when that one explained the gap only in part
            # (diagnosis.md, "A second effect"): named by `effect` and `partial` verdicts.
            "second": second.get("effect"),
            "second_strength": second.get("strength"),
            "second_interval": second_fit.get("strength_interval"),
            "second_interval_open": second_fit.get("strength_interval_open"),
            "second_interval_2se": second_fit.get("strength_interval_2se"),
            "second_interval_2se_open": second_fit.get("strength_interval_2se_open"),
            # The pair's share of the null's held-out chi2 (the first effect's shrink and the second's on top).
            "second_shrink_total": second.get("held_out_shrink_total"),
            "strength": best["strength"] if best else None,
            "interval": best["strength_interval"] if best else None,
            "interval_open": best.get("strength_interval_open") if best else None,
            # The interval at two standard errors (absent from a diagnosis.json before 7 Dec 2026).
            "interval_2se": best.get("strength_interval_2se") if best else None,
            "interval_2se_open": best.get("strength_interval_2se_open") if best else None,
            "held_out_shrink": j["held_out_shrink"], "held_out_gap_shrink": j.get("held_out_gap_shrink"),
            "runs_computed": j.get("runs_computed"), "signal": signal(d, first),  # the twin's own table
            # --measure-next: the measurements made on the twin at the reports' request, and the first verdict.
            "measured": measured, "first_verdict": first["verdict"], "first_effect": first["effect"],
            "first_tied": first.get("tied") or [],
            # An undecided verdict: whether more seeds could decide it (diagnosis.md, stage 6c).
            "more_seeds": more_seeds_text(j.get("more_seeds")),
            "wall_s": cost_of(d, j, upto)["wall_s"], "device": j["device"]}


def more_seeds_text(m):
    """The outlook of more seeds (diagnosis.json's more_seeds) in a few words, or "" when decided."""
    if not m:
        return ""
    if m.get("worth"):
        return f"more seeds could decide it ({m['to_replicates']})"
    need = [t.get("seeds_needed") for t in m.get("ties") or [] if t.get("estimated")]
    if need and all(n is None for n in need):
        return "more seeds unlikely to decide it"
    return f"more seeds unlikely at {m['to_replicates']}" + (
        f", from about {min(n for n in need if n is not None)}" if any(n is not None for n in need) else "")


def cost_of(d, j, upto=0):
    """What the twin cost when its runs were computed: OUT/<twin>/cost.json, kept from the call that computed the
    most runs (a re-evaluation from the store computes none and reads ~0 s), else this diagnosis's wall; plus
    each --measure-next round up to the reported one (cost_m<k>.json: its measurements and its diagnosis)."""
    path = os.path.join(d, "cost.json")
    c = load_json(path) if os.path.exists(path) else {"wall_s": j.get("wall_s"),
                                                      "runs_computed": j.get("runs_computed")}
    for k in range(1, upto + 1):
        pk = os.path.join(d, f"cost_m{k}.json")
        if os.path.exists(pk):
            r = load_json(pk)
            c["wall_s"] = (c.get("wall_s") or 0) + (r.get("wall_s") or 0)
            c["runs_computed"] = (c.get("runs_computed") or 0) + (r.get("runs_computed") or 0)
    return c


def record_cost(d, wall_s, k=0):
    """After a call that ran the twin and the diagnosis (k = 0: cost.json), or round k of --measure-next
    (cost_m<k>.json): its wall time (the twin's runs or the measurements included) and the runs the diagnosis
    computed, unless an earlier call computed more."""
    sub = "diagnosis" if k == 0 else f"diagnosis_m{k}"
    j = load_json(os.path.join(d, sub, "diagnosis.json"))
    new = {"wall_s": wall_s, "runs_computed": j.get("runs_computed") or 0, "stages": j.get("stages"),
           "device": j.get("device")}
    path = os.path.join(d, "cost.json" if k == 0 else f"cost_m{k}.json")
    if os.path.exists(path) and (load_json(path).get("runs_computed") or 0) >= new["runs_computed"]:
        return
    with open(path, "w") as f:
        json.dump(new, f, indent=1)


def script_rounds(a, i, name, d, twin_file, diag_cmd, store):
    """--script with --measure-next: the rounds in bash (python3 runs twin_measure.py there: it needs no tomllib);
    a round whose diagnosis is there is skipped, and the first round that finds nothing to measure ends them."""
    q = lambda cmd: " ".join(['"$WETDEM"'] + [shlex.quote(c) for c in cmd[1:]])
    qm = lambda cmd: " ".join(shlex.quote(c) for c in cmd).replace(shlex.quote("$WETDEM"), '"$WETDEM"')
    obs, last, out = diag_cmd[diag_cmd.index("--observations") + 1], os.path.join(d, "diagnosis"), ["more=1"]
    for k in range(1, a.measure_next + 1):
        m = measure_cmd(a, i, d, k, twin_file, obs, last, store, "$WETDEM", True)
        diag = os.path.join(d, f"diagnosis_m{k}", "diagnosis.json")
        out.append(f"""if ((more)) && [[ ! -f {shlex.quote(diag)} ]]; then
  t0=$(date +%s)
  {qm(m)} >{shlex.quote(os.path.join(d, f"measure_m{k}.log"))} 2>&1
  rc=$?
  if ((rc == 3)); then more=0
  elif ((rc != 0)); then fail {name} measure
  else {q(round_diag_cmd(diag_cmd, d, k))} >{shlex.quote(os.path.join(d, f"diagnose_m{k}.log"))} 2>&1 || fail {name} diagnose
    cost {shlex.quote(d)} $(($(date +%s) - t0)) {k}
  fi
fi""")
        obs, last = os.path.join(d, f"observations_m{k}.csv"), os.path.join(d, f"diagnosis_m{k}")
    return "\n".join(out) + "\n"


def script_twin(name, d, twin_cmd, diag_cmd):
    """One twin of a --script: skipped when its diagnosis is there; its cost.json as record_cost writes it (the
    wall of the call, the runs the diagnosis computed), unless an earlier call computed more."""
    q = lambda cmd: " ".join(['"$WETDEM"'] + [shlex.quote(c) for c in cmd[1:]])
    return f"""
if [[ -f {shlex.quote(os.path.join(d, "diagnosis", "diagnosis.json"))} ]]; then
  echo "{name}: done before"
else
  t0=$(date +%s)
  {q(twin_cmd)} >{shlex.quote(os.path.join(d, "twin.log"))} 2>&1 || fail {name} twin
  {q(diag_cmd)} >{shlex.quote(os.path.join(d, "diagnose.log"))} 2>&1 || fail {name} diagnose
  cost {shlex.quote(d)} $(($(date +%s) - t0))
  echo "{name}: $(grep -m1 -o '"verdict": *"[a-z_]*"' {shlex.quote(os.path.join(d, "diagnosis", "diagnosis.json"))}) \
($(($(date +%s) - start)) s)"
fi
"""


def check_twin(wetdem, name, twin_file, log):
    """wetdem twin --check: the twin's file and the case at each of its conditions, nothing run."""
    with open(log, "w") as f:
        r = subprocess.run([wetdem, "twin", twin_file, "--check"], stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        why = [ln for ln in open(log).read().splitlines() if ln.strip()]
        sys.exit(f"{name}: the twin cannot run ({why[-1] if why else f'exit {r.returncode}'}; {log}); "
                 "nothing was run")


def script_checks(todo):
    """The script's first block: every twin not done before checked (wetdem twin --check) before any runs."""
    q = lambda c: shlex.quote(c)
    out = ["\n# Every twin's file and the case at each of its conditions checked before the first run.\n"]
    for _, t, d, tf, _, _ in todo:
        out.append(f"[[ -f {q(os.path.join(d, 'diagnosis', 'diagnosis.json'))} ]] || "
                   f"\"$WETDEM\" twin {q(tf)} --check >{q(os.path.join(d, 'check.log'))} 2>&1 || "
                   f"fail {t['name']} 'twin --check'\n")
    return "".join(out)


def write_script(path, twins, checks=""):
    head = """#!/bin/bash
# Written by scripts/twin_matrix.py --script: the twins of a validation matrix, run from the project root with
# the wetdem binary in $WETDEM. A twin whose diagnosis.json exists is skipped (runs resume through the store).
set -uo pipefail
WETDEM=${WETDEM:-build/host/wetdem}
start=$(date +%s)
fail() { echo "$1: wetdem $2 failed (see its log)"; exit 1; }
# cost DIR WALL [K]: DIR/cost.json (round K of --measure-next: DIR/cost_mK.json from DIR/diagnosis_mK) as
# twin_matrix.py's record_cost writes it.
cost() {
  local n old=-1 sub=diagnosis c=cost.json
  [[ -n ${3:-} ]] && sub=diagnosis_m$3 c=cost_m$3.json
  n=$(grep -m1 -o '"runs_computed": *[0-9]*' "$1/$sub/diagnosis.json" | grep -o '[0-9]*$' || echo 0)
  [[ -f $1/$c ]] && old=$(grep -m1 -o '"runs_computed": *[0-9]*' "$1/$c" | grep -o '[0-9]*$' || echo 0)
  ((old >= n)) && return 0
  printf '{"wall_s": %s, "runs_computed": %s, "stages": null, "device": null}\\n' "$2" "$n" >"$1/$c"
}
"""
    with open(path, "w") as f:
        f.write(head + checks + "".join(twins))
    os.chmod(path, 0o755)


def after_measuring(r):
    """The verdict cell's note for a twin that was measured again at its reports' request (--measure-next)."""
    if not r.get("measured"):
        return ""
    first = r["first_effect"] or "-"
    if r["first_tied"]:
        first += f" (tied: {', '.join(r['first_tied'])})"
    return (f" after measuring {'; '.join(r['measured'])} (first: {r['first_verdict']} {first})")


def identified(r):
    """The truth named (first, or as the second effect on top) and nothing the twin did not withhold."""
    return (r["verdict"] in ("effect", "partial") and r["truth"] in (r["effect"], r.get("second"))
            and {r["effect"], r.get("second")} - {None} <= {r["truth"], r.get("also")})


def outcome(r):
    """The confusion matrix's column: the truth when identified (a withheld pair named in either order counts
    under the twin's named truth), else the chosen effect, else the verdict."""
    if r["verdict"] not in ("effect", "partial"):
        return r["verdict"]
    return r["truth"] if identified(r) else r["effect"]


def is_effect_twin(r):
    return r["truth"] not in (None, "outside")


def confusion(rows):
    truths = list(dict.fromkeys(r["truth"] or "none" for r in rows))
    cols = list(dict.fromkeys([t for t in truths if t not in ("none", "outside")] + [outcome(r) for r in rows]))
    cols = [c for c in cols if c not in ("no_gap", "refit", "unexplained")] + ["refit", "no_gap", "unexplained"]
    cols = [c for c in cols if c != "refit" or any(outcome(r) == "refit" for r in rows)]
    md = ["Confusion matrix (rows: the withheld truth; columns: the diagnosis's outcome)", "",
          "| truth \\ outcome | " + " | ".join(cols) + " |", "|---" * (len(cols) + 1) + "|"]
    for t in truths:
        n = [sum(1 for r in rows if (r["truth"] or "none") == t and outcome(r) == c) for c in cols]
        md.append(f"| {t} | " + " | ".join(str(x) if x else "" for x in n) + " |")
    return md, truths, cols


def cell_marks(rows, truths, cols):
    """The plot's marks, {(truth index, column index): set of marks}, decided once for the cells and the title:
    "right" (the truth named, or no_gap/unexplained for a null or an outside effect), "other" (the twin's other
    withheld difference, itself a candidate, named: right about the data, not about the effect the twin was
    built for; counted apart in the summary) and "tied" (another candidate named first and the truth tied with
    it: in the reported set, not first)."""
    marks = {}
    for i, t in enumerate(truths):
        for k, c in enumerate(cols):
            if t == c or (t in ("none", "outside") and c in ("no_gap", "unexplained")):
                marks.setdefault((i, k), set()).add("right")
    for r in rows:
        i, k = truths.index(r["truth"] or "none"), cols.index(outcome(r))
        if r.get("also") and outcome(r) == r["also"] and "right" not in marks.get((i, k), ()):
            marks.setdefault((i, k), set()).add("other")
        if r["truth"] and r["truth"] != outcome(r) and r["truth"] in r["tied"]:
            marks.setdefault((i, k), set()).add("tied")
    return marks


def plot(rows, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(f"note: matplotlib is not installed for {sys.executable}: {path} not written", file=sys.stderr)
        return
    if not rows:
        return
    _, truths, cols = confusion(rows)
    m = [[sum(1 for r in rows if (r["truth"] or "none") == t and outcome(r) == c) for c in cols] for t in truths]
    marks = cell_marks(rows, truths, cols)
    fig, ax = plt.subplots(figsize=(1.1 * len(cols) + 2, 0.6 * len(truths) + 1.8))
    top = max(2, max(max(x) for x in m))
    ax.imshow(m, cmap="Blues", vmin=0, vmax=top)
    for i, row in enumerate(m):
        for k, x in enumerate(row):
            if x:
                ax.text(k, i, str(x), ha="center", va="center", color="white" if x > top / 2 else "black",
                        fontsize=12)
    for (i, k), kinds in marks.items():
        if "right" in kinds:
            ax.add_patch(plt.Rectangle((k - 0.5, i - 0.5), 1, 1, fill=False, ec="tab:green", lw=2))
        if "other" in kinds:
            ax.add_patch(plt.Rectangle((k - 0.45, i - 0.45), 0.9, 0.9, fill=False, ec="tab:orange", lw=2, ls="--"))
        if "tied" in kinds:
            ax.add_patch(plt.Rectangle((k - 0.4, i - 0.4), 0.8, 0.8, fill=False, ec="tab:green", lw=1.5, ls=":"))
    ax.set_xticks(range(len(cols)), cols, rotation=30, ha="right")
    ax.set_yticks(range(len(truths)), truths)
    ax.set_xlabel("diagnosis outcome (the chosen effect for effect/partial)")
    ax.set_ylabel("withheld truth (twin)")
    kinds = set().union(*marks.values()) if marks else set()
    notes = (["dashed orange: the twin's other withheld difference, itself a candidate, named"]
             if "other" in kinds else []) + (
        ["dotted green: the truth tied with the effect named first"] if "tied" in kinds else [])
    ax.set_title("Twin matrix: withheld effect vs diagnosis (green: a right answer"
                 + "".join(";\n" + n for n in notes) + ")")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def bracket(interval, open_ends):
    """An interval as the tables write it: [lo, hi], with "≤" on a side open past the probed range."""
    (lo, hi), op = interval, open_ends or [False, False]
    return f"[{'≤ ' if op[0] else ''}{lo:.3g}, {hi:.3g}{' ≤' if op[1] else ''}]"


def summarize(rows, wall, device, out_dir, spec_path):
    eff = [r for r in rows if is_effect_twin(r)]
    # Identified: the truth is named (first, or as the second effect on top) and nothing the twin did not
    # withhold is named. A twin that withholds two candidates (l = 4 is `scale` 0.2 plus its effect) is
    # identified by naming both, in either order; naming its other difference alone is counted apart.
    right = [r for r in eff if identified(r)]
    first = [r for r in eff if r["verdict"] in ("effect", "partial") and r["effect"] == r["truth"]]
    # Twins whose truth the table can show at all (signal: the noiseless truth moves a cell by >= 3 sigma).
    visible = [r for r in eff if (r.get("signal") or {}).get("max_abs_z", 0) >= 3]
    right_visible = [r for r in right if r in visible]
    for r in right:  # the fitted strength of the truth, whether it was named first or second
        if r["effect"] != r["truth"]:
            r["strength"], r["interval"] = r.get("second_strength"), r.get("second_interval")
            r["interval_open"] = r.get("second_interval_open")
            r["interval_2se"], r["interval_2se_open"] = r.get("second_interval_2se"), r.get("second_interval_2se_open")
        if r.get("second") and r.get("second_shrink_total") is not None:  # the named pair's shrink
            r["held_out_shrink"] = r["second_shrink_total"]
    shrinks = [r["held_out_shrink"] for r in right if r["held_out_shrink"] is not None]
    # The share of the gap (the null's held-out χ² above its noise floor) the chosen effect removes, at most all
    # of it: above 1 the held-out χ² fell below the floor, which is estimated from the baseline's cells
    # (verdict.h); those are counted apart.
    gap_raw = [r["held_out_gap_shrink"] for r in right if r.get("held_out_gap_shrink") is not None]
    gap_shrinks = [min(1.0, g) for g in gap_raw]
    below_floor = sum(1 for g in gap_raw if g >= 1.0)
    within = [r for r in right if r["strength"] and r["truth_strength"]
              and abs(r["strength"] / r["truth_strength"] - 1) <= 0.25]
    def covers(iv, r):
        return iv and r["truth_strength"] and iv[0] * (1 - 1e-9) <= r["truth_strength"] <= iv[1] * (1 + 1e-9)

    covered = [r for r in right if covers(r["interval"], r)]
    with_2se = [r for r in right if r.get("interval_2se")]
    covered_2se = [r for r in with_2se if covers(r["interval_2se"], r)]
    # The twin's other withheld difference, itself a candidate, found instead of the named truth.
    other = [r for r in eff if r not in right and r.get("also") and r["verdict"] in ("effect", "partial")
             and r["effect"] == r["also"]]
    other_within = [r for r in other if r["strength"] and r.get("also_strength")
                    and abs(r["strength"] / r["also_strength"] - 1) <= 0.25]
    # The truth named first or as the second effect; both withheld differences named (two-difference twins).
    named = [r for r in eff if r["verdict"] in ("effect", "partial") and r["truth"] in (r["effect"], r.get("second"))]
    both = [r for r in eff if r.get("also") and r["verdict"] in ("effect", "partial")
            and {r["truth"], r["also"]} == {r["effect"], r.get("second")}]
    # A no_gap twin whose truth its table's limits rule out: a confident wrong exclusion (a sink's limit with
    # its rate free where the diagnosis ran other rates, else at the candidate's default rate).
    no_gap_eff = [r for r in eff if r["verdict"] == "no_gap" and r.get("truth_limit")]
    wrongly_out = [r for r in no_gap_eff if 0 < r["truth_limit"]["ruled_out_from"] <= (r["truth_strength"] or 0)]
    quiet = [r for r in rows if not is_effect_twin(r)]
    confident_wrong = [r for r in quiet if r["verdict"] == "effect"]
    out = {"matrix": spec_path, "rows": rows, "effect_twins": len(eff), "top1": len(right),
           "top1_rate": len(right) / len(eff) if eff else None, "truth_chosen_first": len(first),
           "visible_effect_twins": len(visible), "top1_visible": len(right_visible),
           "in_reported_set": sum(1 for r in eff if r["effect"] == r["truth"] or r["truth"] in r["tied"]),
           "median_held_out_shrink": statistics.median(shrinks) if shrinks else None,
           "median_held_out_gap_shrink": statistics.median(gap_shrinks) if gap_shrinks else None,
           "held_out_below_floor": below_floor,
           "strength_within_25pc": len(within), "interval_covers_truth": len(covered),
           "interval_2se_reported": len(with_2se), "interval_2se_covers_truth": len(covered_2se),
           "named_first_or_second": len(named), "both_withheld_named": len(both),
           "found_other_candidate": len(other), "other_candidate_within_25pc": len(other_within),
           "nulls_and_outside": len(quiet), "confident_wrong": len(confident_wrong),
           "no_gap_effect_twins_with_limits": len(no_gap_eff), "truth_ruled_out": len(wrongly_out),
           "device": device, "wall_s": wall}
    json.dump(out, open(os.path.join(out_dir, "matrix.json"), "w"), indent=2)
    md = ["| twin | truth | truth strength | also differs | signal max z | verdict | chosen (tied) | "
          "fitted strength [interval] | held-out shrink | wall |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        s = r["held_out_shrink"]
        fit = ""
        if r["strength"] is not None and r["interval"]:
            fit = f"{r['strength']:.3g} {bracket(r['interval'], r['interval_open'])}"
            if r.get("interval_2se") and list(r["interval_2se"]) != list(r["interval"]):
                fit += f" (2 SE {bracket(r['interval_2se'], r.get('interval_2se_open'))})"
        ts = "" if r["truth_strength"] is None else f"{r['truth_strength']:.3g}"
        chosen = (r["effect"] or "-") + (f" ({', '.join(r['tied'])})" if r["tied"] else "")
        if r.get("second"):
            chosen += f" + `{r['second']}`" + (f" {r['second_strength']:.3g}" if r.get("second_strength") else "")
        also = "yes" if r["perturbed"] else ""
        if r.get("also"):
            also = f"yes (`{r['also']}` {r['also_strength']:.3g})"
        sig = r.get("signal")
        lim, limit = r.get("truth_limit"), ""
        if r["verdict"] == "no_gap" and lim:
            free = (", rate free" if lim.get("free_shape")
                    else f", at rate {lim['at_shape']:g}" if lim.get("at_shape") else "")
            limit = (f" (out from {lim['ruled_out_from']:.3g}{free})" if lim["ruled_out_from"] > 0
                     else f" (not ruled out{free})" if free else f" (allowed to {lim['allowed_to']:.3g})")
        md.append(f"| {r['twin']} | {r['truth'] or 'none'} | {ts} | {also} | "
                  f"{'' if not sig else '%.1f' % sig['max_abs_z']} | "
                  f"{r['verdict']}{limit}{after_measuring(r)}"
                  f"{'; ' + r['more_seeds'] if r.get('more_seeds') else ''} | {chosen} | {fit} | {'' if s is None else f'{100 * s:.0f} %'} | "
                  f"{'' if r['wall_s'] is None else '%.0f s' % r['wall_s']} |")
    md.append("")
    md += confusion(rows)[0]
    md.append("")
    n = len(right)
    md.append(
        f"Identified {len(right)}/{len(eff)} ({100 * (out['top1_rate'] or 0):.0f} %) of the effect twins "
        f"(the truth named, first or as a second effect, and nothing not withheld; chosen first: {len(first)}; in the "
        f"reported set, chosen or tied: {out['in_reported_set']}), {len(right_visible)}/{len(visible)} of those "
        f"whose truth moves a cell by >= 3 sigma without noise (signal max z); median held-out "
        f"shrink {'-' if not shrinks else f'{100 * statistics.median(shrinks):.0f} %'} over the {n} identified "
        f"(of the gap above the noise floor: {'-' if not gap_shrinks else f'{100 * statistics.median(gap_shrinks):.0f} %'}"
        + (f", all of it for {below_floor}" if below_floor else "") + "); "
        f"fitted strength within ±25 % of the truth for {len(within)}/{n}, interval covering the truth for "
        f"{len(covered)}/{n}"
        + (f" (at 2 SE: {len(covered_2se)}/{len(with_2se)})" if with_2se else "") + "; "
        + (f"the twin's other withheld difference, itself a candidate, named instead: {len(other)}/"
           f"{sum(1 for r in eff if r.get('also'))} (its strength within ±25 % for {len(other_within)}), both "
           f"withheld differences named: {len(both)}; "
           if any(r.get("also") for r in eff) else "")
        + (f"effect twins with no gap whose truth the table's limits rule out: {len(wrongly_out)}/{len(no_gap_eff)}; "
           if no_gap_eff else "")
        + f"nulls and outside effects given an `effect` verdict (a confident wrong answer): "
        f"{len(confident_wrong)}/{len(quiet)}. Device {device}; wall {wall:.0f} s (the twins' computing calls, twin runs included, summed).")
    open(os.path.join(out_dir, "matrix.md"), "w").write("\n".join(md) + "\n")
    plot(rows, os.path.join(out_dir, "matrix.png"))
    print("\n".join(md))


def measure_cmd(a, i, d, k, twin_file, obs, last, store, wetdem, script):
    """The twin_measure.py call of round k (its output table OUT/<twin>/observations_m<k>.csv)."""
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "twin_measure.py")
    return ([sys.executable, here] if not script else ["python3", os.path.relpath(here)]) + [
        twin_file, obs, last, "--out", os.path.join(d, f"observations_m{k}.csv"), "--store", store,
        "--wetdem", wetdem, "--noise-seed", str(900 + 10 * i + k), "--record", os.path.join(d, "measured.json"),
        ] + (["--jobs", str(a.jobs)] if a.jobs else []) + (["--batch", str(a.batch)] if a.batch else [])


def round_diag_cmd(diag_cmd, d, k):
    """The diagnosis of round k: the same call on the table with round k's measurements."""
    cmd = list(diag_cmd)
    cmd[cmd.index("--observations") + 1] = os.path.join(d, f"observations_m{k}.csv")
    cmd[cmd.index("--out") + 1] = os.path.join(d, f"diagnosis_m{k}")
    return cmd


def measure_rounds(a, i, d, twin_file, diag_cmd, store):
    """--measure-next: up to N rounds of measuring on the twin what the last report asks for, then diagnosing the
    table with those rows; OUT/<twin>/diagnosis_m<k>/, OUT/<twin>/measured.json (what was measured)."""
    obs, last = diag_cmd[diag_cmd.index("--observations") + 1], os.path.join(d, "diagnosis")
    for k in range(1, a.measure_next + 1):
        t_round = time.time()
        cmd = measure_cmd(a, i, d, k, twin_file, obs, last, store, a.wetdem, False)
        log = os.path.join(d, f"measure_m{k}.log")
        with open(log, "w") as f:
            r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
        if r.returncode == 3:
            break
        if r.returncode != 0:
            sys.exit(f"failed ({r.returncode}): {' '.join(cmd)} (see {log})")
        run(round_diag_cmd(diag_cmd, d, k), os.path.join(d, f"diagnose_m{k}.log"))
        record_cost(d, time.time() - t_round, k)
        obs, last = os.path.join(d, f"observations_m{k}.csv"), os.path.join(d, f"diagnosis_m{k}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("matrix", help="matrix file (TOML): diagnosis, twin_base, [[twin]]")
    ap.add_argument("--wetdem", default="build/host/wetdem")
    ap.add_argument("--out", required=True)
    ap.add_argument("--jobs", type=int, default=None,
                    help="runs at a time per call (default: wetdem's, one per core on lavapipe, 1 on a GPU)")
    ap.add_argument("--batch", type=int, help="runs per process (wetdem's default when not given: 1 on a CPU "
                    "device, 16 on a GPU)")
    ap.add_argument("--only", nargs="*", help="run only these twins (names)")
    ap.add_argument("--replicates", type=int,
                    help="seeds per condition for every diagnosis instead of the diagnosis file's (wetdem diagnose "
                         "--replicates)")
    ap.add_argument("--probe-seeds", type=int,
                    help="seeds per probe knot for every diagnosis instead of the diagnosis file's (wetdem diagnose "
                         "--probe-seeds)")
    ap.add_argument("--twin-base", metavar="FILE",
                    help="base twin for every twin instead of the matrix's twin_base: another table of conditions "
                         "and noise (assets/diagnosis/flowing/twin_null_fast.toml adds 120 rpm rows)")
    ap.add_argument("--store", help="run store (default OUT/store); share one across matrices to reuse runs")
    ap.add_argument("--script", metavar="FILE",
                    help="write the twin files and a bash script of the calls to FILE instead of running them")
    ap.add_argument("--measure-next", type=int, default=0, metavar="N",
                    help="after each diagnosis, make on the twin the measurements its report asks for next "
                         "(scripts/twin_measure.py) and diagnose again, up to N rounds; the matrix reports the last")
    ap.add_argument("--summarize", action="store_true",
                    help="only (re)write matrix.json/.md/.png from the twin folders already in --out")
    a = ap.parse_args()
    spec = tomllib.load(open(a.matrix, "rb"))
    mdir = os.path.dirname(os.path.abspath(a.matrix))
    for k in ("diagnosis", "twin_base", "twin"):
        if k not in spec:
            sys.exit(f"{a.matrix}: {k}: required")
    diagnosis = os.path.join(mdir, spec["diagnosis"])
    base_path = os.path.abspath(a.twin_base) if a.twin_base else os.path.join(mdir, spec["twin_base"])
    if not os.path.isfile(base_path):
        sys.exit(f"{a.twin_base or a.matrix}: twin_base: no such file {base_path}")
    base, base_dir = open(base_path).read(), os.path.dirname(base_path)
    for k in spec:
        if k not in ("diagnosis", "twin_base", "twin", "truth_seeds_from", "noise_seed_from"):
            sys.exit(f"{a.matrix}: unknown key {k} (diagnosis, twin_base, truth_seeds_from, noise_seed_from, "
                     "[[twin]])")
    seed_from = {}
    for k, default in (("truth_seeds_from", 1000), ("noise_seed_from", 500)):
        v = spec.get(k, default)
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            sys.exit(f"{a.matrix}: {k}: a non-negative integer, not {v!r}")
        seed_from[k] = v
    names = [t["name"] for t in spec["twin"]]
    if len(set(names)) != len(names):
        sys.exit(f"{a.matrix}: twin names must be unique")
    for t in spec["twin"]:
        for k in t:
            if k not in ("name", "effect", "strength", "truth", "perturb", "also_effect", "also_strength"):
                sys.exit(f"{a.matrix}: twin {t['name']}: unknown key {k}")
    if a.script and a.summarize:
        sys.exit("--script and --summarize: one or the other")
    if a.script:
        # The script runs from the project root on another machine: every path in it relative to here, and the
        # twin files' case relative to the twin file (as wetdem reads it).
        a.out, diagnosis = os.path.relpath(a.out), os.path.relpath(diagnosis)
        if a.store:
            a.store = os.path.relpath(a.store)
    os.makedirs(a.out, exist_ok=True)
    store = a.store or os.path.join(a.out, "store")
    t0 = time.time()
    rows = []
    lines = []
    todo = []  # (i, twin, its folder, its file, the twin call, the diagnosis call), checked before any runs
    for i, t in enumerate(spec["twin"]):
        d = os.path.join(a.out, t["name"])
        if a.summarize or (a.only and t["name"] not in a.only):
            if not a.script and os.path.exists(os.path.join(d, "diagnosis", "diagnosis.json")):
                rows.append((i, row_of(d, t)))
            continue
        os.makedirs(d, exist_ok=True)
        overrides = dict(t.get("truth", {}))
        overrides.update(t.get("perturb", {}))
        tf = os.path.join(d, "twin.toml")
        bd = os.path.relpath(base_dir, d) if a.script else base_dir
        open(tf, "w").write(twin_text(base, bd, [seed_from["truth_seeds_from"] + 10 * i,
                                                      seed_from["truth_seeds_from"] + 10 * i + 1],
                                        seed_from["noise_seed_from"] + i, overrides))
        common = (["--store", store, "--quiet"] + (["--jobs", str(a.jobs)] if a.jobs else [])
                  + (["--batch", str(a.batch)] if a.batch else []))
        twin_cmd = [a.wetdem, "twin", tf, "--out", os.path.join(d, "twin")] + common
        # The diagnosis sees the observations only (truth.json stays in the twin folder).
        rep = ["--replicates", str(a.replicates)] if a.replicates else []
        rep += ["--probe-seeds", str(a.probe_seeds)] if a.probe_seeds else []
        diag_cmd = [a.wetdem, "diagnose", diagnosis, "--observations", os.path.join(d, "twin", "observations.csv"),
                    "--out", os.path.join(d, "diagnosis")] + rep + common
        todo.append((i, t, d, tf, twin_cmd, diag_cmd))
    if a.script:
        for i, t, d, tf, twin_cmd, diag_cmd in todo:
            lines.append(script_twin(t["name"], d, twin_cmd, diag_cmd))
            if a.measure_next:  # the rounds go with their twin's block
                lines[-1] += script_rounds(a, i, t["name"], d, tf, diag_cmd, store)
        write_script(a.script, lines, script_checks(todo))
        print(f"{a.script}: {len(lines)} twins; run it from the project root (WETDEM=path/to/wetdem bash "
              f"{a.script}), then: {sys.argv[0]} {a.matrix} --out {a.out} --summarize")
        return
    # Every twin's file and the case at each of its conditions are checked before the first run: a twin that
    # cannot run stops the matrix now, not hours into it.
    for i, t, d, tf, twin_cmd, diag_cmd in todo:
        check_twin(a.wetdem, t["name"], tf, os.path.join(d, "check.log"))
    for i, t, d, tf, twin_cmd, diag_cmd in todo:
        t_twin = time.time()
        run(twin_cmd, os.path.join(d, "twin.log"))
        run(diag_cmd, os.path.join(d, "diagnose.log"))
        record_cost(d, time.time() - t_twin)
        measure_rounds(a, i, d, tf, diag_cmd, store)
        rows.append((i, row_of(d, t)))
        r = rows[-1][1]
        print(f"{t['name']}: {r['verdict']} {r['effect'] or ''} ({time.time() - t0:.0f} s)", flush=True)
    rows = [r for _, r in sorted(rows, key=lambda x: x[0])]  # the matrix file's order
    # The matrix's cost: the twins' computing calls summed (cost.json), not this call's, which may only have
    # re-read the store.
    wall = sum(r["wall_s"] or 0 for r in rows)
    device = next((r["device"] for r in rows if r["device"]), "")
    summarize(rows, wall, device, a.out, os.path.relpath(a.matrix))


if __name__ == "__main__":
    main()
