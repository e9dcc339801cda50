#!/usr/bin/env bash
# Robust runs end to end on the micro drum (issue: "a probe never aborts a diagnosis"): the spread twin's table
# diagnosed with the viscous candidate probed far past what the bed or the budget allows.
#  1. run.dt given (not lowered to the damper's limit): viscous probes blow the bed up; their runs fail, are
#     listed in the report and cut the range; the diagnosis completes with the withheld effect found.
#  2. The same diagnosis again on the same store: the failed runs are not run again and do not poison it.
#  3. dt lowered to the damper's limit (default) with max_cost = 3: the costly strengths are not run, the range
#     is cut there, the diagnosis completes.
# usage: robust_e2e.sh WETDEM SOURCE_DIR
set -euo pipefail
W=$1
SRC=$2
D=$(mktemp -d)
trap 'rm -rf "$D"' EXIT
J() { /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
t0=$(date +%s)
"$W" twin "$SRC/assets/diagnosis/micro/twin_spread.toml" --out "$D/ts" --store "$D/store" --quiet

"$W" diagnose "$SRC/tests/diagnose/robust_dt.toml" --observations "$D/ts/observations.csv" --out "$D/d1" \
  --store "$D/store" --quiet --no-figures
echo "explicit dt: $(J "$D/d1/diagnosis.json" 'j["verdict"], j["effect"], len(j["notes"])')"
[ "$(J "$D/d1/diagnosis.json" 'j["effect"]')" = spread ] || { echo "FAIL: effect"; cat "$D/d1/report.md"; exit 1; }
[ "$(J "$D/d1/diagnosis.json" 'any("failed" in n and "viscous" in n for n in j["notes"])')" = True ] ||
  { echo "FAIL: the failed viscous runs are not listed"; cat "$D/d1/report.md"; exit 1; }
grep -q "Runs that could not be made" "$D/d1/report.md" || { echo "FAIL: report section"; exit 1; }

"$W" diagnose "$SRC/tests/diagnose/robust_dt.toml" --observations "$D/ts/observations.csv" --out "$D/d2" \
  --store "$D/store" --quiet --no-figures
[ "$(J "$D/d2/diagnosis.json" 'j["runs_computed"]')" = 0 ] || { echo "FAIL: reran"; exit 1; }
[ "$(J "$D/d2/diagnosis.json" 'j["verdict"] == json.load(open(sys.argv[1].replace("d2", "d1")))["verdict"]')" = True ] ||
  { echo "FAIL: the second diagnosis on the same store differs"; exit 1; }

"$W" diagnose "$SRC/tests/diagnose/robust_cost.toml" --observations "$D/ts/observations.csv" --out "$D/d3" \
  --store "$D/store" --quiet --no-figures
echo "cost cut: $(J "$D/d3/diagnosis.json" 'j["verdict"], j["effect"], [n for n in j["notes"] if "viscous" in n][:2]')"
[ "$(J "$D/d3/diagnosis.json" 'j["effect"]')" = spread ] || { echo "FAIL: effect (cost)"; cat "$D/d3/report.md"; exit 1; }
[ "$(J "$D/d3/diagnosis.json" 'any("not run" in n and "max_cost" in n for n in j["notes"])')" = True ] ||
  { echo "FAIL: the costly strength is not listed"; cat "$D/d3/report.md"; exit 1; }
[ "$(J "$D/d3/diagnosis.json" 'not any("failed" in n for n in j["notes"] if "viscous@0.01" in n or "viscous@0.003" in n)')" = True ] ||
  { echo "FAIL: a viscous run at the damper's limit failed"; cat "$D/d3/report.md"; exit 1; }
echo "robust runs e2e: $(( $(date +%s) - t0 )) s"
