#!/usr/bin/python3
"""scripts/twin_matrix.py --script: the twin files and a bash script of the same calls, for a machine without
Python 3.11 (a lent GPU). Run here with a stand-in for wetdem that records its arguments and writes the files a
twin and a diagnosis leave: every twin is run once with the options given, paths are relative to the project
root, cost.json is written as record_cost writes it, a second run of the script skips the finished twins, a
failing call stops the script with the twin's name, and --summarize reads what the script left.
usage: twin_matrix_script.py SOURCE_DIR"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

src = sys.argv[1]
root = tempfile.mkdtemp(prefix="wetdem-matrix-script-")
os.makedirs(os.path.join(root, "m"))
open(os.path.join(root, "m", "twin_base.toml"), "w").write('case = "model.toml"\nseeds = [1, 2]\nnoise_seed = 7\n')
open(os.path.join(root, "m", "diagnose.toml"), "w").write('name = "d"\n')
open(os.path.join(root, "m", "matrix.toml"), "w").write('''diagnosis = "diagnose.toml"
twin_base = "twin_base.toml"
[[twin]]
name = "cohesion-strong"
effect = "cohesion"
strength = 0.02
truth = { "effects.cohesion.energy" = "0.02 J/m^2" }
[[twin]]
name = "null-1"
''')
# The stand-in: `wetdem twin ... --out D` writes D/observations.csv, `wetdem diagnose ... --out D` writes
# D/diagnosis.json; every call is logged; FAIL_ON=<text> fails a call whose arguments hold that text.
fake = os.path.join(root, "fake-wetdem")
open(fake, "w").write(r'''#!/bin/bash
echo "$*" >>calls.log
[[ -n ${FAIL_ON:-} && "$*" == *"$FAIL_ON"* ]] && { echo "wetdem: error: $FAIL_ON"; exit 3; }
[[ " $* " == *" --check "* ]] && exit 0
out=""; prev=""
for a in "$@"; do [[ $prev == --out ]] && out=$a; prev=$a; done
mkdir -p "$out"
case $1 in
  twin) echo "condition,observable,mean,sigma" >"$out/observations.csv" ;;
  diagnose) cat >"$out/diagnosis.json" <<'J'
{"verdict": "effect", "effect": "cohesion", "tied": [], "held_out_shrink": 0.9, "held_out_gap_shrink": null,
 "runs_computed": 7, "wall_s": 1.0, "device": "stand-in", "cells": [],
 "ranking": [{"effect": "cohesion", "strength": 0.021, "strength_interval": [0.015, 0.03],
              "strength_interval_open": [false, false]}]}
J
  ;;
esac
''')
os.chmod(fake, 0o755)


def fail(msg):
    sys.exit(f"FAIL: {msg}")


def sh(cmd, env=None, ok=True):
    r = subprocess.run(cmd, cwd=root, capture_output=True, text=True, env=dict(os.environ, **(env or {})))
    if ok and r.returncode != 0:
        fail(f"{cmd}: exit {r.returncode}\n{r.stdout}\n{r.stderr}")
    return r


matrix = [sys.executable, os.path.join(src, "scripts", "twin_matrix.py"), os.path.join(root, "m", "matrix.toml")]
sh(matrix + ["--out", os.path.join(root, "out"), "--script", "run.sh", "--replicates", "4", "--jobs", "3",
             "--batch", "20"])
text = open(os.path.join(root, "run.sh")).read()
if root in text:
    fail("the script holds an absolute path of this machine")
twin_file = open(os.path.join(root, "out", "cohesion-strong", "twin.toml")).read()
case = re.search(r'^case = "([^"]+)"', twin_file, re.M)
# wetdem reads a twin file's case relative to the twin file (diagnose/files.cpp, rel_path).
if not case or case.group(1).startswith("/") or os.path.normpath(
        os.path.join(root, "out", "cohesion-strong", case.group(1))) != os.path.join(root, "m", "model.toml"):
    fail(f"twin.toml: the case relative to the twin file expected:\n{twin_file}")
if '"effects.cohesion.energy" = "0.02 J/m^2"' not in twin_file:
    fail(f"twin.toml: the truth expected:\n{twin_file}")
sh(["bash", "-n", "run.sh"])
if os.path.exists(os.path.join(root, "out", "null-1", "diagnosis")):
    fail("--script ran something")

# Every twin is checked (wetdem twin --check) before the first run: one that cannot run stops the script
# before anything runs, naming the twin.
r = sh(["bash", "run.sh"], {"WETDEM": fake, "FAIL_ON": "null-1/twin.toml"}, ok=False)
if r.returncode == 0 or "null-1: wetdem twin --check failed" not in r.stdout:
    fail(f"a twin that does not check: exit {r.returncode}, output {r.stdout!r}")
if os.path.exists(os.path.join(root, "out", "cohesion-strong", "diagnosis")):
    fail("a twin that does not check: the twins before it ran")
# A failing call stops the script and names the twin.
r = sh(["bash", "run.sh"], {"WETDEM": fake, "FAIL_ON": "out/null-1/twin --store"}, ok=False)
if r.returncode == 0 or "null-1: wetdem twin failed" not in r.stdout:
    fail(f"a failing twin call: exit {r.returncode}, output {r.stdout!r}")
# Run to the end: the first twin is skipped (and not checked again), the second run.
sh(["bash", "run.sh"], {"WETDEM": fake})
calls = open(os.path.join(root, "calls.log")).read().splitlines()
# the two checks, the second failing; the two checks, cohesion's twin + diagnose, null-1's failed twin; null-1's
# check, twin + diagnose
if len(calls) != 10 or sum(" --check" in c for c in calls) != 5:
    fail(f"calls: {calls}")
diag = [c for c in calls if c.startswith("diagnose ")]
for c in diag:
    for want in ["m/diagnose.toml", "--replicates 4", "--jobs 3", "--batch 20", "--store out/store", "--quiet"]:
        if want not in c:
            fail(f"diagnose call lacks {want!r}: {c}")
cost = json.load(open(os.path.join(root, "out", "null-1", "cost.json")))
if cost["runs_computed"] != 7 or cost["wall_s"] < 0:
    fail(f"cost.json: {cost}")
# Once more: nothing left to run (or check).
r = sh(["bash", "run.sh"], {"WETDEM": fake})
if len(open(os.path.join(root, "calls.log")).read().splitlines()) != 10 or r.stdout.count("done before") != 2:
    fail(f"a second run of the script ran again: {r.stdout}")
sh(matrix + ["--out", os.path.join(root, "out"), "--summarize"])
m = json.load(open(os.path.join(root, "out", "matrix.json")))
if m.get("top1") != 1 or m.get("confident_wrong") != 1:
    fail(f"matrix.json from the script's folders: {m}")

# Without --script the same check comes first: a twin that cannot run stops the matrix with its reason, and
# nothing has run.
r = sh(matrix + ["--out", os.path.join(root, "out6"), "--wetdem", fake], {"FAIL_ON": "null-1/twin.toml"}, ok=False)
if r.returncode == 0 or "null-1: the twin cannot run (wetdem: error: null-1/twin.toml" not in r.stderr or \
        "nothing was run" not in r.stderr or os.path.exists(os.path.join(root, "out6", "cohesion-strong", "twin")):
    fail(f"a twin that does not check, without --script: exit {r.returncode}, {r.stderr!r}")
sh(matrix + ["--out", os.path.join(root, "out6"), "--wetdem", fake])
if not os.path.exists(os.path.join(root, "out6", "null-1", "diagnosis", "diagnosis.json")) or \
        json.load(open(os.path.join(root, "out6", "matrix.json"))).get("top1") != 1:
    fail("the matrix without --script, after its checks: the twins' diagnoses and matrix.json expected")

# --twin-base: another table for every twin (its conditions, its case relative to it), the truth still applied.
os.makedirs(os.path.join(root, "fast"))
open(os.path.join(root, "fast", "base.toml"), "w").write(
    'case = "../m/model.toml"\nseeds = [1, 2]\nnoise_seed = 7\n[[points]]\n"drum.rpm" = 120\n')
sh(matrix + ["--out", os.path.join(root, "out2"), "--script", "run2.sh", "--twin-base", "fast/base.toml"])
twin_file = open(os.path.join(root, "out2", "cohesion-strong", "twin.toml")).read()
case = re.search(r'^case = "([^"]+)"', twin_file, re.M)
if '"drum.rpm" = 120' not in twin_file or '"effects.cohesion.energy" = "0.02 J/m^2"' not in twin_file or not case or \
        os.path.normpath(os.path.join(root, "out2", "cohesion-strong", case.group(1))) != \
        os.path.join(root, "m", "model.toml"):
    fail(f"twin.toml from --twin-base: its rows, the truth and its case expected:\n{twin_file}")
r = sh(matrix + ["--out", os.path.join(root, "out3"), "--script", "run3.sh", "--twin-base", "nope.toml"], ok=False)
if r.returncode == 0 or "nope.toml" not in r.stderr:
    fail(f"a missing --twin-base: exit {r.returncode}, {r.stderr!r}")

# Default seeds: the i-th twin gets truth seeds 1000 + 10 i, + 1 and noise seed 500 + i. truth_seeds_from and
# noise_seed_from move them (a second matrix of unseen twins); anything but a non-negative integer is refused.
def seeds_of(out, name):
    t = open(os.path.join(root, out, name, "twin.toml")).read()
    return re.search(r"^seeds = \[(.*)\]$", t, re.M).group(1), re.search(r"^noise_seed = (\d+)$", t, re.M).group(1)


if seeds_of("out", "null-1") != ("1010, 1011", "501"):
    fail(f"default seeds of the second twin: {seeds_of('out', 'null-1')}")
base_matrix = open(os.path.join(root, "m", "matrix.toml")).read()
open(os.path.join(root, "m", "m2.toml"), "w").write("truth_seeds_from = 3000\nnoise_seed_from = 70\n" + base_matrix)
m2 = [sys.executable, os.path.join(src, "scripts", "twin_matrix.py"), os.path.join(root, "m", "m2.toml")]
sh(m2 + ["--out", os.path.join(root, "out4"), "--script", "run4.sh"])
if seeds_of("out4", "cohesion-strong") != ("3000, 3001", "70") or seeds_of("out4", "null-1") != ("3010, 3011", "71"):
    fail(f"seeds from the matrix's keys: {seeds_of('out4', 'cohesion-strong')}, {seeds_of('out4', 'null-1')}")
for bad, why in (("truth_seeds_from = -1\n", "truth_seeds_from"), ("noise_seed_from = 1.5\n", "noise_seed_from"),
                 ("seed_from = 3\n", "unknown key seed_from")):
    open(os.path.join(root, "m", "m3.toml"), "w").write(bad + base_matrix)
    r = sh([sys.executable, os.path.join(src, "scripts", "twin_matrix.py"), os.path.join(root, "m", "m3.toml"),
            "--out", os.path.join(root, "out5"), "--script", "run5.sh"], ok=False)
    if r.returncode == 0 or why not in r.stderr:
        fail(f"{bad.strip()}: exit {r.returncode}, {r.stderr!r}")
shutil.rmtree(root)
print("twin matrix script: OK")
