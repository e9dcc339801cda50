#!/usr/bin/env bash
# Robust runs end to end on the micro drum (issue: "a probe never aborts a diagnosis"): the spread twin's table
# diagnosed with the viscous candidate probed far past what the bed or the budget allows.
#  1. run.dt given (not lowered to the damper's limit): viscous probes blow the bed up; their runs fail, are
#     listed in the report and cut the range; the diagnosis completes with the withheld effect found.
#  2. The same diagnosis again on the same store: the failed runs are not run again and do not poison it (not
#     quiet: its progress lines name each stage).
#  3. dt lowered to the damper's limit (default) with max_cost = 3: the costly strengths are not run, the range
#     is cut there, the diagnosis completes.
#  4. The reach past the file's probes meets the same guard (robust_reach_cost.toml): viscous, unseen at 0.01 Pa s,
#     is stepped to 0.0333; the next step and its geometric middle cost more than max_cost and are not run; the
#     reach says it stopped at "the strongest max_cost lets run", and the diagnosis completes.
# One replicate (the command line wins over the files' 2): what is tested is the listing and cutting of runs, not
# the strength (27 Nov 2026: the three diagnoses 186 s -> 132 s, the same verdicts).
# usage: robust_e2e.sh WETDEM SOURCE_DIR [STORE]
source "$(dirname "$0")/lib.sh" "$@"
wd twin "$SRC/assets/diagnosis/micro/twin_spread.toml" --out "$D/ts" --store "$S" --quiet
diagnose() {  # diagnose SPEC OUT
  wd diagnose "$SRC/tests/diagnose/$1" --observations "$D/ts/observations.csv" --out "$D/$2" \
    --store "$S" --quiet --no-figures --replicates 1
}

diagnose robust_dt.toml d1
echo "explicit dt: $(J "$D/d1/diagnosis.json" 'j["verdict"], j["effect"], len(j["notes"])')"
expect "$D/d1/diagnosis.json" 'j["effect"] == "spread"' "effect" "$D/d1/report.md"
expect "$D/d1/diagnosis.json" 'any("failed" in n and "viscous" in n for n in j["notes"])' \
  "the failed viscous runs are not listed" "$D/d1/report.md"
grep -q "Runs that could not be made" "$D/d1/report.md" || { echo "FAIL: report section"; exit 1; }

# Not quiet: the progress lines name each stage as it ends, with its runs and what it found.
wd diagnose "$SRC/tests/diagnose/robust_dt.toml" --observations "$D/ts/observations.csv" --out "$D/d2" \
  --store "$S" --no-figures --replicates 1 > "$D/d2.log"
expect_text "$D/d2.log" "^diagnose robust-dt: where and screen done in .* cells significant; screen spread" \
  "no progress line for the screen"
expect_text "$D/d2.log" "^diagnose robust-dt: fit and verdict done in .*(0 runs computed; 0 in all, .*): effect (spread)" \
  "no progress line for the verdict"
[ "$(grep -c "^diagnose robust-dt: .* done in " "$D/d2.log")" -ge 6 ] || { echo "FAIL: stage lines"; cat "$D/d2.log"; exit 1; }
expect "$D/d2/diagnosis.json" 'j["runs_computed"] == 0' "reran"
expect "$D/d2/diagnosis.json" 'j["verdict"] == json.load(open(sys.argv[1].replace("d2", "d1")))["verdict"]' \
  "the second diagnosis on the same store differs"

diagnose robust_cost.toml d3
echo "cost cut: $(J "$D/d3/diagnosis.json" 'j["verdict"], j["effect"], [n for n in j["notes"] if "viscous" in n][:2]')"
expect "$D/d3/diagnosis.json" 'j["effect"] == "spread"' "effect (cost)" "$D/d3/report.md"
expect "$D/d3/diagnosis.json" 'any("not run" in n and "max_cost" in n for n in j["notes"])' \
  "the costly strength is not listed" "$D/d3/report.md"
expect "$D/d3/diagnosis.json" \
  'not any("failed" in n for n in j["notes"] if "viscous@0.01" in n or "viscous@0.003" in n)' \
  "a viscous run at the damper's limit failed" "$D/d3/report.md"
diagnose robust_reach_cost.toml d4
echo "reach cost cut: $(J "$D/d4/diagnosis.json" '[(r["effect"], r["strongest_probed"], r["extension_stop"]) for r in j["reach"]]')"
expect "$D/d4/diagnosis.json" 'j["effect"] == "spread"' "effect (reach cost)" "$D/d4/report.md"
expect "$D/d4/diagnosis.json" \
  'any(r["effect"] == "viscous" and not r["visible"] and r["extension_stop"] == "max_cost" and r["extended_from"] == 0.01 and r["strongest_probed"] > 0.01 for r in j["reach"])' \
  "viscous's reach was not stepped past its probes and then stopped by max_cost" "$D/d4/report.md"
expect "$D/d4/diagnosis.json" 'sum("reach: viscous@" in n and "not run" in n and "max_cost" in n for n in j["notes"]) == 2' \
  "the reach's refused step and its middle are not both listed" "$D/d4/report.md"
expect_text "$D/d4/report.md" "the strongest max_cost lets run" "the report does not say where the cost guard stopped the reach"
echo "robust runs e2e: $(($(date +%s) - t0)) s"
