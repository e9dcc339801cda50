#!/usr/bin/python3
"""scripts/twin_measure.py and twin_matrix.py --measure-next, with a stand-in for wetdem: the measurements a
report's diagnosis.json lists in "measure_next" (which ones is wetdem's rule, tests/test_diagnose_asked.cpp) are
made: one made k times is entered as the mean, sigma/sqrt(k), n = k, replacing the row when the table has it;
which cannot be taken (a condition key the table lacks, a measurement the table has); the twin file the
measurement is made with (the twin's truth and seeds, the proposal's conditions and noise, a noise seed of its
own); the table written (the old rows, then the new, conditions quoted); exit status 3 and no table when nothing
can be measured; an error for a diagnosis.json without the list; and the matrix's rounds: a second diagnosis on
the new table, reported with what was measured.
usage: twin_measure_test.py SOURCE_DIR"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import tomllib

src = sys.argv[1]
root = tempfile.mkdtemp(prefix="wetdem-twin-measure-")


def fail(msg):
    sys.exit(f"FAIL: {msg}")


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    open(path, "w").write(text)


# The stand-in: `wetdem twin F --out D` copies F to $TWIN_COPY (when set) and writes D/observations.csv, one row per point
# and [noise] observable, value = 0.5 + liquid content (%) / 100, sigma the file's noise; `wetdem diagnose ...
# --out D` writes D/diagnosis.json from $DIAGNOSES (a JSON list, one per call, in order).
fake = os.path.join(root, "fake-wetdem")
write(fake, r'''#!/usr/bin/python3
import itertools, json, os, shutil, sys, tomllib
args = sys.argv[1:]
out = args[args.index("--out") + 1] if "--out" in args else "."
os.makedirs(out, exist_ok=True)
if args[0] == "twin":
    t = tomllib.load(open(args[1], "rb"))
    if os.environ.get("TWIN_COPY"):
        shutil.copy(args[1], os.environ["TWIN_COPY"])
    points = t.get("points") or [dict(zip(t["conditions"], v)) for v in itertools.product(*t["conditions"].values())]
    t["points"] = points
    keys = list(t["points"][0].keys())
    if any(set(p) != set(keys) for p in points):  # as wetdem twin refuses it
        sys.exit("wetdem: error: [[points]]: every point needs the same condition keys as the first")
    with open(os.path.join(out, "observations.csv"), "w") as f:
        f.write(",".join(keys) + ",observable,value,sigma,n,note\n")
        for p in t["points"]:
            for o, s in t["noise"].items():
                pct = float(str(p.get("liquid.content", "0")).split()[0])
                f.write(",".join(json.dumps(str(p[k])) for k in keys) + f",{o},{0.5 + pct / 100},{s},{len(t['seeds'])},twin\n")
elif args[0] == "check":
    print("# resolved\n[drum]\nrotation_rad_per_s = 3.141592653589793\n\n[run]\nduration_s = 3")
elif args[0] == "diagnose":
    n = len([x for x in os.listdir(os.environ["CALLS"])])
    open(os.path.join(os.environ["CALLS"], str(n)), "w").write(" ".join(args))
    json.dump(json.loads(os.environ["DIAGNOSES"])[n], open(os.path.join(out, "diagnosis.json"), "w"))
''')
os.chmod(fake, 0o755)

twin = os.path.join(root, "m", "twin.toml")
write(os.path.join(root, "m", "model.toml"), 'name = "m"\n')
write(twin, '''# a twin
name = "t"
case = "model.toml"
seeds = [11, 12]
noise_seed = 5

[conditions]
"liquid.content" = ["0 %", "5 %", "10 %"]
"drum.rpm" = [30]

[noise]
aor_deg_mean = 1.0
liquid_free_fraction = 0.02

[truth]
"absorption.capacity" = 0.05
''')
obs = os.path.join(root, "obs.csv")
write(obs, '''liquid.content,drum.rpm,observable,value,sigma,n,note
"0 %","30",aor_deg_mean,33.7,1.0,2,twin
"5 %","30",aor_deg_mean,33.3,1.0,2,twin
"5 %","30",liquid_free_fraction,0.58,0.02,2,twin
"10 %","30",aor_deg_mean,33.1,1.0,2,twin
"10 %","30",liquid_free_fraction,0.56,0.02,2,twin
''')


def asked(cond, obs_name, sigma=0.025, repeats=1, reason="tie"):
    """One entry of diagnosis.json's "measure_next" (report.h, AskedMeasurement)."""
    return {"reason": reason, "effect": "absorption or evaporation", "condition": cond, "observable": obs_name,
            "sigma": sigma, "repeats": repeats, "separation": 3.0, "in_table": False, "assay": False}


def diagnosis(*measure_next):
    return {"verdict": "effect", "effect": "absorption", "tied": ["evaporation"],
            "held_out_shrink": 0.9, "held_out_gap_shrink": None, "runs_computed": 1, "wall_s": 1.0,
            "device": "stand-in", "cells": [], "measure_next": list(measure_next),
            "ranking": [{"effect": "absorption", "strength": 0.05, "strength_interval": [0.04, 0.06],
                         "strength_interval_open": [False, False]}]}


def measure(d, name, expect_rc=0):
    dd = os.path.join(root, name)
    write(os.path.join(dd, "diagnosis.json"), json.dumps(d))
    out = os.path.join(root, name + ".csv")
    r = subprocess.run(["/usr/bin/python3", os.path.join(src, "scripts", "twin_measure.py"), twin, obs, dd,
                        "--out", out, "--store", os.path.join(root, "store"), "--wetdem", fake,
                        "--noise-seed", "77"], capture_output=True, text=True, cwd=root,
                       env=dict(os.environ, TWIN_COPY=os.path.join(root, name + ".twin.toml")))
    if r.returncode != expect_rc:
        fail(f"{name}: exit {r.returncode}, expected {expect_rc}:\n{r.stdout}{r.stderr}")
    return r.stdout + r.stderr, out


# 1. Two measurements (a tie's and a bound's), made at one call.
text, out = measure(diagnosis(asked("liquid.content=2.5 %", "liquid_free_fraction", 0.0256),
                              asked("liquid.content=20 %", "liquid_free_fraction", 0.0256, reason="bound")),
                    "tie-and-bound")
lines = open(out).read().splitlines()
if lines[:6] != open(obs).read().splitlines():
    fail("the old rows are not kept first and as they were")
if lines[6:] != ['"2.5 %","30",liquid_free_fraction,0.525,0.02,2,measured next',
                 '"20 %","30",liquid_free_fraction,0.7,0.02,2,measured next']:
    fail(f"new rows (the twin's own instrument noise, 0.02, not the report's 0.0256): {lines[6:]}")
made = tomllib.load(open(os.path.join(root, "tie-and-bound.twin.toml"), "rb"))
if made["seeds"] != [11, 12] or made["truth"] != {"absorption.capacity": 0.05} or made["noise_seed"] != 77:
    fail(f"the twin file does not keep the truth and seeds or take the noise seed: {made}")
if "conditions" in made or made["noise"] != {"liquid_free_fraction": 0.02}:
    fail(f"the twin file keeps the table's [conditions] or other noises: {made}")
if [p["liquid.content"] for p in made["points"]] != ["2.5 %", "20 %"] or made["points"][0]["drum.rpm"] != 30:
    fail(f"the twin file's points: {made['points']}")

# 2. Nothing that can be measured: a key the table lacks that is no drum speed or run length; a measurement the
# table has; an empty list.
text, out = measure(diagnosis(asked("liquid.content=10 %, liquid.gamma=30 mN/m", "aor_deg_mean")), "nothing", 3)
if os.path.exists(out) or "liquid.gamma" not in text:
    fail(f"nothing to measure, yet a table was written or the reason not given:\n{text}")
text, out = measure(diagnosis(asked("liquid.content=10 %", "liquid_free_fraction")), "in-table", 3)
if "already in the table" not in text:
    fail(f"a measurement the table has was not named as such:\n{text}")
measure(diagnosis(), "none", 3)
# A diagnosis.json from before the list: an error that says what to do, not a silent "nothing".
old = diagnosis()
del old["measure_next"]
text, out = measure(old, "old", 1)
if "measure_next" not in text or os.path.exists(out):
    fail(f"an old diagnosis.json:\n{text}")

# 3. A run length the table never varied: a new column, the model's value (wetdem check: 3 s) in the old rows.
text, out = measure(diagnosis(asked("liquid.content=10 %, run.duration=12 s", "aor_deg_mean")), "longer")
lines = open(out).read().splitlines()
if lines[0] != "liquid.content,drum.rpm,run.duration,observable,value,sigma,n,note" \
        or lines[1] != '"0 %","30","3 s",aor_deg_mean,33.7,1.0,2,twin' \
        or lines[-1] != '"10 %","30","12 s",aor_deg_mean,0.6,1.0,2,measured next':
    fail(f"the new column:\n{open(out).read()}")

# 3b. The same new column asked by a later measurement only: the earlier one is made at the model's 3 s too
# (stop 85: a tie's assay and a reach's 12 s run in one round made a twin whose points had different keys).
text, out = measure(diagnosis(asked("liquid.content=20 %", "liquid_free_fraction", 0.02),
                              asked("liquid.content=10 %, run.duration=12 s", "aor_deg_mean")), "mixed")
lines = open(out).read().splitlines()
if lines[0] != "liquid.content,drum.rpm,run.duration,observable,value,sigma,n,note" \
        or '"20 %","30","3 s",liquid_free_fraction,0.7,0.02,2,measured next' not in lines \
        or lines[-1] != '"10 %","30","12 s",aor_deg_mean,0.6,1.0,2,measured next':
    fail(f"a new column asked by the later measurement:\n{text}\n{open(out).read()}")

# 4. A measurement made 4 times: 4 times the truth's seeds (n = 8 runs), the instrument's noise / 2; in the table
# already, the row is replaced by the new mean.
text, out = measure(diagnosis(asked("liquid.content=20 %", "liquid_free_fraction", 0.02, 4, "bound")), "repeated")
lines = open(out).read().splitlines()
if lines[-1] != '"20 %","30",liquid_free_fraction,0.7,0.01,8,measured next' or "(4 times)" not in text:
    fail(f"a measurement made 4 times:\n{text}{open(out).read()}")
made = tomllib.load(open(os.path.join(root, "repeated.twin.toml"), "rb"))
if made["noise"] != {"liquid_free_fraction": 0.01}:
    fail(f"the twin draws the mean of 4 with sigma/2: {made['noise']}")
if made["seeds"] != [11, 12, 13, 14, 15, 16, 17, 18]:
    fail(f"4 measurements are 4 times the truth's seeds, new ones after the twin's: {made['seeds']}")
# An observable the twin has no noise for (an assay): the report's sigma.
text, out = measure(diagnosis(asked("liquid.content=20 %", "f_wet_mean", 0.03)), "assay")
if open(out).read().splitlines()[-1] != '"20 %","30",f_wet_mean,0.7,0.03,2,measured next':
    fail(f"an observable without the twin's noise takes the report's sigma:\n{text}{open(out).read()}")
# Measurements made once and twice, at one call of this script: one twin each (seeds and noise of their own).
text, out = measure(diagnosis(asked("liquid.content=2.5 %", "liquid_free_fraction", 0.02),
                              asked("liquid.content=20 %", "aor_deg_mean", 1.0, 2, "reach")), "mixed")
if open(out).read().splitlines()[6:] != ['"2.5 %","30",liquid_free_fraction,0.525,0.02,2,measured next',
                                         '"20 %","30",aor_deg_mean,0.7,0.7071067811865475,4,measured next']:
    fail(f"once and twice at one call:\n{text}{open(out).read()}")
text, out = measure(diagnosis(asked("liquid.content=10 %", "liquid_free_fraction", 0.02, 4, "bound")),
                    "repeated-in-table")
lines = open(out).read().splitlines()
if len(lines) != 6 or '"10 %","30",liquid_free_fraction,0.56,0.02,2,twin' in lines \
        or lines[-1] != '"10 %","30",liquid_free_fraction,0.6,0.01,8,measured next':
    fail(f"a row of the table made again 4 times replaces it:\n{open(out).read()}")
# Made 3 times with sigma 0.02: sigma / sqrt(3).
text, out = measure(diagnosis(asked("liquid.content=2.5 %", "liquid_free_fraction", 0.02, 3)), "tie-repeated")
if open(out).read().splitlines()[-1] != '"2.5 %","30",liquid_free_fraction,0.525,0.011547005383792516,6,measured next':
    fail(f"a measurement made 3 times:\n{text}{open(out).read()}")

# 5. twin_matrix.py --measure-next 2, run here and as a --script (a lent GPU): the first report asks for the 20 %
# row, the second for nothing; the matrix reports the second diagnosis, with what was measured and the first verdict.
mdir = os.path.join(root, "mx")
write(os.path.join(mdir, "model.toml"), 'name = "m"\n')
write(os.path.join(mdir, "twin_base.toml"), open(twin).read().replace("[truth]\n\"absorption.capacity\" = 0.05\n", ""))
write(os.path.join(mdir, "diagnose.toml"), 'name = "d"\n')
write(os.path.join(mdir, "matrix.toml"), '''diagnosis = "diagnose.toml"
twin_base = "twin_base.toml"
[[twin]]
name = "absorption-slow"
effect = "absorption"
strength = 0.05
truth = { "absorption.capacity" = 0.05 }
''')
first = diagnosis(asked("liquid.content=20 %", "liquid_free_fraction", 0.0256, reason="bound"))
second = diagnosis()
matrix = ["/usr/bin/python3", os.path.join(src, "scripts", "twin_matrix.py"), os.path.join(mdir, "matrix.toml")]
for mode in ("here", "script"):
    calls = os.path.join(root, "calls-" + mode)
    os.makedirs(calls)
    out = os.path.join(root, "mout-" + mode)
    env = dict(os.environ, CALLS=calls, DIAGNOSES=json.dumps([first, second, second]), WETDEM=fake)
    if mode == "here":
        r = subprocess.run(matrix + ["--out", out, "--wetdem", fake, "--measure-next", "2"], capture_output=True,
                           text=True, cwd=root, env=env)
    else:
        r = subprocess.run(matrix + ["--out", "mout-script", "--measure-next", "2", "--script", "run.sh"],
                           capture_output=True, text=True, cwd=root, env=env)
        if r.returncode == 0:
            r = subprocess.run(["bash", "run.sh"], capture_output=True, text=True, cwd=root, env=env)
        if r.returncode == 0:  # once more: every round is there, nothing runs
            r = subprocess.run(["bash", "run.sh"], capture_output=True, text=True, cwd=root, env=env)
        if r.returncode == 0:
            r = subprocess.run(matrix + ["--out", "mout-script", "--summarize"], capture_output=True, text=True,
                               cwd=root, env=env)
    if r.returncode != 0:
        fail(f"{mode}: twin_matrix.py --measure-next: {r.stdout}{r.stderr}")
    tw = os.path.join(out, "absorption-slow")
    if len(os.listdir(calls)) != 2 or not os.path.exists(os.path.join(tw, "diagnosis_m1", "diagnosis.json")) \
            or os.path.exists(os.path.join(tw, "diagnosis_m2")):
        fail(f"{mode}: expected two diagnoses (the first, then one on the table with the measured row): "
             f"{os.listdir(tw)}, {len(os.listdir(calls))} calls")
    second_call = open(os.path.join(calls, "1")).read()
    if "observations_m1.csv" not in second_call:
        fail(f"{mode}: the second diagnosis did not read the new table: {second_call}")
    rec = json.load(open(os.path.join(tw, "measured.json")))
    if rec != [{"table": "observations_m1.csv",
                "measured": ["liquid_free_fraction at liquid.content=20 %, drum.rpm=30"]}]:
        fail(f"{mode}: measured.json: {rec}")
    # The round's cost (its measurements and its diagnosis) is the twin's as well: cost_m1.json beside cost.json,
    # summed in the matrix's wall.
    costs = [os.path.join(tw, c) for c in ("cost.json", "cost_m1.json")]
    if not all(os.path.exists(c) for c in costs):
        fail(f"{mode}: no cost.json and cost_m1.json: {os.listdir(tw)}")
    c0, c1 = (json.load(open(c)) for c in costs)
    mj = json.load(open(os.path.join(out, "matrix.json")))
    if c1["runs_computed"] != 1 or abs(mj["wall_s"] - (c0["wall_s"] + c1["wall_s"])) > 1e-9:
        fail(f"{mode}: the matrix's wall {mj['wall_s']} is not the first call's {c0} and the round's {c1}")
    md = open(os.path.join(out, "matrix.md")).read()
    if "after measuring liquid_free_fraction at liquid.content=20 %" not in md:
        fail(f"{mode}: matrix.md does not say what was measured:\n{md}")
shutil.rmtree(root)  # kept on a failure, for the post-mortem
print("ok")
