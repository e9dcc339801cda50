#!/usr/bin/env bash
# End to end on the micro drum, through the CLI, with a re-fitted parameter: a twin whose only difference from
# the model is V_max = 2 % instead of the calibrated 1 % (twin_vmax.toml, no effect withheld). Diagnosed with
# V_max re-fitted (micro_refit_ci.toml), the verdict is `refit`: the null at V_max = 2 % leaves no cell
# significant, and no effect is chosen. The twin's truth.json is moved away before the diagnosis.
# usage: micro_refit_e2e.sh WETDEM SOURCE_DIR [STORE]
source "$(dirname "$0")/lib.sh" "$@"

wd twin "$SRC/assets/diagnosis/micro/twin_vmax.toml" --out "$D/tv" --store "$S" --quiet
mv "$D/tv/truth.json" "$D/truth-vmax.json"
wd diagnose "$SRC/tests/diagnose/micro_refit_ci.toml" --observations "$D/tv/observations.csv" --out "$D/dv" \
  --store "$S" --quiet --no-figures --replicates 2
R="$D/dv/diagnosis.json"
expect "$R" 'j["replicates"] == 2' "--replicates 2 did not replace the file's replicates = 1"
echo "V_max twin: $(J "$R" 'j["verdict"], j["effect"], j["null_refit"]["label"], j["runs"]')"
expect "$R" 'sum(c["significant"] for c in j["cells"]) > 0' \
  "no gap against the calibrated model (the twin does not test refit)"
expect "$R" 'j["verdict"] == "refit"' "verdict is not refit" "$D/dv/report.md"
expect "$R" 'j["null_refit"]["values"]["liquid.v_max"] == 0.02' "the null's V_max is not 2 %"
expect "$R" 'len(j["refit"]["settings"]) == 2 and all("refit" in r for r in j["ranking"])' \
  "refit settings not reported"
grep -q "Gap closed by re-fitting" "$D/dv/report.md" || { echo "FAIL: report paragraph"; exit 1; }
echo "micro refit e2e: $(($(date +%s) - t0)) s"
