#!/usr/bin/env bash
# End to end on the micro drum, through the CLI: sequential replication (escalate_replicates, driver.cpp) and
# the outlook of more seeds (more_seeds.h). A twin with slow evaporation withheld, diagnosed at one seed per
# condition, ties the two liquid sinks; the diagnosis then runs again at two seeds, reusing the first pass's
# runs, and the report says so. The sinks' fitted models are the same on this table (f_wet 0.9032 and 0.9027 at
# 10 %, noise 0.02), so the outlook expects no decision from more seeds: with `escalate_when = "decidable"` the
# diagnosis does not run again and says why. The truth is in the reported set either way.
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
expect "$D/d/diagnosis.json" 'j["escalation"]["outlook"]["to_replicates"] == 2 and j["escalation"]["outlook"]["worth"] is False' \
  "the first pass's outlook is not kept"
expect_text "$D/d/report.md" "gave more seeds too little to separate them by" "the paragraph does not give the outlook"
# Only where more seeds could decide: the outlook holds the second pass back, and the report says why.
echo 'escalate_when = "decidable"' >"$D/decidable.toml"  # a top-level key: before the file's tables
sed -e 's#"../../assets/#"'"$SRC"'/assets/#' "$SRC/tests/diagnose/micro_escalate_ci.toml" >>"$D/decidable.toml"
wd diagnose "$D/decidable.toml" --observations "$D/t/observations.csv" --out "$D/o" --store "$S" --quiet \
  --no-figures
echo "outlook: $(J "$D/o/diagnosis.json" 'j["more_seeds"], j["verdict"], j["effect"], j["tied"]')"
expect "$D/o/diagnosis.json" 'j["escalation"] is None and j["replicates"] == 1' \
  "it ran again although the outlook expected no decision" "$D/o/report.md"
expect "$D/o/diagnosis.json" 'j["more_seeds"]["to_replicates"] == 2 and not j["more_seeds"]["worth"]' \
  "the outlook at two seeds is missing or expects a decision" "$D/o/report.md"
expect "$D/o/diagnosis.json" 'len(j["more_seeds"]["ties"]) == len(j["tied"]) >= 1 and all(t["estimated"] and t["separation_chi2"] < t["margin_chi2"] for t in j["more_seeds"]["ties"])' \
  "the outlook does not estimate every tie below its margin" "$D/o/report.md"
expect "$D/o/diagnosis.json" '"evaporation" in [j["effect"]] + j["tied"]' "the truth is not in the reported set" \
  "$D/o/report.md"
expect_text "$D/o/report.md" "More seeds alone are unlikely to decide the tie:\*\*" "the paragraph does not say why"
expect_text "$D/o/report.md" "did not run again at 2 seeds" "the paragraph does not say it did not run again"
# A bad value is refused before any run.
echo 'escalate_when = "sometimes"' >"$D/bad.toml"
sed -e '/escalate_when/d' "$D/decidable.toml" >>"$D/bad.toml"
if "$W" diagnose "$D/bad.toml" --observations "$D/t/observations.csv" --out "$D/bad" --store "$S" >"$D/bad.log" 2>&1; then
  echo "FAIL: escalate_when = \"sometimes\" was accepted"; exit 1
fi
expect_text "$D/bad.log" 'escalate_when: "undecided"' "the error does not name the key and its values"
[ ! -e "$D/bad" ] || { echo "FAIL: a refused diagnosis left output"; exit 1; }
# Bad input before any run: an escalation that adds no seed.
if "$W" diagnose "$SRC/tests/diagnose/micro_escalate_ci.toml" --observations "$D/t/observations.csv" \
  --out "$D/bad" --store "$S" --escalate-replicates 1 >"$D/bad.log" 2>&1; then
  echo "FAIL: --escalate-replicates 1 at replicates 1 was accepted"; exit 1
fi
grep -q "escalate-replicates: 1 is not more than the replicates (1)" "$D/bad.log" ||
  { echo "FAIL: the error does not name the option"; cat "$D/bad.log"; exit 1; }
[ ! -e "$D/bad" ] || { echo "FAIL: a refused diagnosis left output"; exit 1; }
echo "escalation e2e: $(($(date +%s) - t0)) s"
