#!/usr/bin/env bash
# End to end on the micro drum, through the CLI: sequential replication (escalate_replicates, driver.cpp). A twin
# with slow evaporation withheld, diagnosed at one seed per condition, ties the two liquid sinks; the diagnosis
# then runs again at two seeds, reusing the first pass's runs, and the report says so. The truth is in the
# reported set either way.
# usage: escalate_e2e.sh WETDEM SOURCE_DIR [STORE]
source "$(dirname "$0")/lib.sh" "$@"

wd twin "$SRC/tests/diagnose/twin_evaporation_ci.toml" --out "$D/t" --store "$S" --quiet
mv "$D/t/truth.json" "$D/truth.json"
wd diagnose "$SRC/tests/diagnose/micro_escalate_ci.toml" --observations "$D/t/observations.csv" --out "$D/d" \
  --store "$S" --quiet --no-figures
echo "escalated: $(J "$D/d/diagnosis.json" 'j["escalation"], j["verdict"], j["effect"], j["tied"]')"
expect "$D/d/diagnosis.json" 'j["escalation"] is not None and j["escalation"]["from_replicates"] == 1' \
  "the undecided first pass did not run again" "$D/d/report.md"
expect "$D/d/diagnosis.json" 'bool(j["escalation"]["tied"] or j["escalation"]["held_by_luck"] or j["escalation"]["baseline_only"])' \
  "it ran again although the first pass was decided"
expect "$D/d/diagnosis.json" 'j["replicates"] == 2 == j["escalation"]["to_replicates"]' "the report is not at 2 seeds"
# Every run is accounted for: the first pass's stages (prefixed) and the second's add to the runs computed.
expect "$D/d/diagnosis.json" 'sum(s["runs_computed"] for s in j["stages"]) == j["runs_computed"]' \
  "the stages of both passes do not account for the runs computed"
expect "$D/d/diagnosis.json" 'any(s["stage"].startswith("R = 1: ") for s in j["stages"])' "no first-pass stages"
expect "$D/d/diagnosis.json" '"evaporation" in [j["effect"]] + j["tied"]' "the truth is not in the reported set" \
  "$D/d/report.md"
grep -q "Run again with more seeds:\*\* at 1 seed per condition" "$D/d/report.md" ||
  { echo "FAIL: the paragraph does not say it ran again"; cat "$D/d/report.md"; exit 1; }
# Bad input before any run: an escalation that adds no seed.
if "$W" diagnose "$SRC/tests/diagnose/micro_escalate_ci.toml" --observations "$D/t/observations.csv" \
  --out "$D/bad" --store "$S" --escalate-replicates 1 >"$D/bad.log" 2>&1; then
  echo "FAIL: --escalate-replicates 1 at replicates 1 was accepted"; exit 1
fi
grep -q "escalate-replicates: 1 is not more than the replicates (1)" "$D/bad.log" ||
  { echo "FAIL: the error does not name the option"; cat "$D/bad.log"; exit 1; }
[ ! -e "$D/bad" ] || { echo "FAIL: a refused diagnosis left output"; exit 1; }
echo "escalation e2e: $(($(date +%s) - t0)) s"
