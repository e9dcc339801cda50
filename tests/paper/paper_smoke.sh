#!/bin/bash
# The paper pipeline end to end at smoke size (issue 19): scripts/paper.sh --smoke runs every stage (the PP2 l = 5
# grid, the extended range reusing it, PP2 l = 3, the calibration on a twin with withheld pore absorption and the
# diagnosis, PP1 l = 5) on a few 0.18 s runs, then draws the figures and computes the findings table. Checks that
# each stage left its outputs: complete runs, the calibration, the diagnosis, the figures, seven findings, each
# with a verdict. Machinery only: the verdicts of 0.18 s runs mean nothing.
# Usage: paper_smoke.sh WETDEM_BINARY SOURCE_DIR
set -eu
WETDEM=$1
SRC=$2
D=$(mktemp -d /tmp/wetdem_paper_XXXXXX)
trap 'rm -rf "$D"' EXIT
WETDEM=$WETDEM bash "$SRC/scripts/paper.sh" --smoke --out "$D/out" --budget 20
/usr/bin/python3 - "$D/out" <<'PY'
import json, os, sys
out = sys.argv[1]
def complete(study):
    ix = json.load(open(os.path.join(out, study, "index.json")))
    runs = [os.path.join(out, study, r["run_dir"], "summary.json") for r in ix["runs"]]
    done = [p for p in runs if os.path.exists(p)]
    assert len(done) == len(runs), "%s: %d of %d runs complete" % (study, len(done), len(runs))
    return len(runs)
n = {s: complete(s) for s in ("pp2_l5", "extended", "pp2_l3", "pp1_l5")}
ext = json.load(open(os.path.join(out, "extended", "index.json")))
assert "reused" in open(os.path.join(out, "extended.log")).read(), "the extended stage did not reuse pp2_l5's runs"
for f in ("twin/observations.csv", "pp2_l5/calibration/calibration.json", "diagnosis/diagnosis.json",
          "paper.md", "findings.json", "figures/pp2_l5_aor.png", "figures/pp2_l3_aor.png", "figures/pp1_l5_aor.png",
          "figures/fwet_extended.png", "figures/beds.png"):
    assert os.path.exists(os.path.join(out, f)), "missing " + f
find = json.load(open(os.path.join(out, "findings.json")))["findings"]
assert sorted(r["finding"] for r in find) == list(range(1, 8)), [r["finding"] for r in find]
for r in find:
    assert r["holds"] in ("yes", "no", "partly", "incomplete", "not checkable", "yes (twin)", "no (twin)"), r
md = open(os.path.join(out, "paper.md")).read()
assert "SMOKE TEST" in md and "| 7 |" in md, "paper.md lacks the smoke note or the findings table"
print("PASS: paper pipeline (smoke): runs %s, calibration, diagnosis, 5 figures, 7 findings" % n)
PY
