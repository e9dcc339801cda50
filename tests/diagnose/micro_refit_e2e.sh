#!/usr/bin/env bash
# End to end on the micro drum, through the CLI, with a re-fitted parameter: a twin whose only difference from
# the model is V_max = 2 % instead of the calibrated 1 % (twin_vmax.toml, no effect withheld). Diagnosed with
# V_max re-fitted (micro_refit_ci.toml), the verdict is `refit`: the null at V_max = 2 % leaves no cell
# significant, and no effect is chosen. The twin's truth.json is moved away before the diagnosis.
# usage: micro_refit_e2e.sh WETDEM SOURCE_DIR
set -euo pipefail
W=$1
SRC=$2
D=$(mktemp -d)
trap 'rm -rf "$D"' EXIT
J() { /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

t0=$(date +%s)
"$W" twin "$SRC/assets/diagnosis/micro/twin_vmax.toml" --out "$D/tv" --store "$D/store" --quiet
mv "$D/tv/truth.json" "$D/truth-vmax.json"
"$W" diagnose "$SRC/tests/diagnose/micro_refit_ci.toml" --observations "$D/tv/observations.csv" --out "$D/dv" \
  --store "$D/store" --quiet --no-figures
echo "V_max twin: $(J "$D/dv/diagnosis.json" 'j["verdict"], j["effect"], j["null_refit"]["label"], j["runs"]')"
[ "$(J "$D/dv/diagnosis.json" 'sum(c["significant"] for c in j["cells"]) > 0')" = True ] ||
  { echo "FAIL: no gap against the calibrated model (the twin does not test refit)"; exit 1; }
[ "$(J "$D/dv/diagnosis.json" 'j["verdict"]')" = refit ] || { echo "FAIL: verdict is not refit"; cat "$D/dv/report.md"; exit 1; }
[ "$(J "$D/dv/diagnosis.json" 'j["null_refit"]["values"]["liquid.v_max"]')" = 0.02 ] ||
  { echo "FAIL: the null's V_max is not 2 %"; exit 1; }
[ "$(J "$D/dv/diagnosis.json" 'len(j["refit"]["settings"]) == 2 and all("refit" in r for r in j["ranking"])')" = True ] ||
  { echo "FAIL: refit settings not reported"; exit 1; }
grep -q "Gap closed by re-fitting" "$D/dv/report.md" || { echo "FAIL: report paragraph"; exit 1; }
echo "micro refit e2e: $(( $(date +%s) - t0 )) s"
