#!/usr/bin/env bash
# End to end on the micro drum, through the CLI: a twin whose liquid was poorly mixed in (40 % of the particles
# wetted, withheld) is diagnosed as `effect: spread` with a held-out shrink >= 50 %, and a null twin (noise only)
# gets no effect. Both share one run store, so the null's baseline and most screen runs are the first diagnosis's
# (the null's file probes cohesion only to 0.03, so that the reach steps past it: micro_null_ci.toml).
# The diagnosis runs with each twin's truth.json moved away (it must not need it).
# usage: micro_e2e.sh WETDEM SOURCE_DIR [STORE]
source "$(dirname "$0")/lib.sh" "$@"

wd twin "$SRC/assets/diagnosis/micro/twin_spread.toml" --out "$D/ts" --store "$S" --quiet
# A dry condition has no liquid_free_fraction: the twin writes no row for it and says so in truth.json.
expect "$D/ts/truth.json" '[x["observable"] for x in j["not_reported"]] == ["liquid_free_fraction"]' \
  "the dry liquid_free_fraction cell"
grep -q '"0 %",liquid_free_fraction' "$D/ts/observations.csv" && { echo "FAIL: a row for an unreported cell"; exit 1; }
mv "$D/ts/truth.json" "$D/truth-spread.json"
wd diagnose "$SRC/tests/diagnose/micro_ci.toml" --observations "$D/ts/observations.csv" --out "$D/ds" \
  --store "$S" --quiet --no-figures
echo "withheld spread: $(J "$D/ds/diagnosis.json" 'j["verdict"], j["effect"], round(j["held_out_shrink"] or 0, 3)')"
expect "$D/ds/diagnosis.json" 'j["verdict"] == "effect"' "verdict is not effect" "$D/ds/report.md"
expect "$D/ds/diagnosis.json" 'j["effect"] == "spread"' "wrong effect" "$D/ds/report.md"
expect "$D/ds/diagnosis.json" 'j["held_out_shrink"] >= 0.5' "shrink < 0.5"
# The interval at 2 SE (fit.h, set_two_se_interval) holds the reported one and the report's text quotes it.
expect "$D/ds/diagnosis.json" 'all(r["strength_interval_2se"][0] <= r["strength_interval"][0] <= r["strength"] <= r["strength_interval"][1] <= r["strength_interval_2se"][1] for r in j["ranking"]) and any("at 2 SE" in r["text"] for r in j["ranking"])' \
  "the 2-SE interval does not hold the reported one, or no text quotes it" "$D/ds/report.md"
# Where the time went (driver.cpp): the stages account for every run computed, and their walls add to at most
# the whole (the table reading before the first stage is the rest).
expect "$D/ds/diagnosis.json" 'sum(s["runs_computed"] for s in j["stages"]) == j["runs_computed"] > 0' \
  "the stages do not account for the runs computed"
expect "$D/ds/diagnosis.json" 'len(j["stages"]) >= 4 and 0 < sum(s["wall_s"] for s in j["stages"]) <= j["wall_s"]' \
  "the stages' wall times do not add up"
# What the table can see (power.h): every candidate is listed, and the one found is visible there.
expect "$D/ds/diagnosis.json" 'len(j["reach"]) == len(j["screen"])' "reach does not list every candidate"
expect "$D/ds/diagnosis.json" 'any(r["effect"] == "spread" and r["visible"] and r["max_abs_z"] >= 3 for r in j["reach"])' \
  "the effect found is not visible in its reach"

wd twin "$SRC/assets/diagnosis/micro/twin_null.toml" --out "$D/tn" --store "$S" --quiet
mv "$D/tn/truth.json" "$D/truth-null.json"
wd diagnose "$SRC/tests/diagnose/micro_null_ci.toml" --observations "$D/tn/observations.csv" --out "$D/dn" \
  --store "$S" --quiet --no-figures
echo "null: $(J "$D/dn/diagnosis.json" 'j["verdict"], j["effect"], j["runs_computed"]')"
expect "$D/dn/diagnosis.json" 'j["verdict"] != "effect"' "a null twin got an effect" "$D/dn/report.md"
# A candidate the table cannot see was run beyond the table (power.h, reach_conditions), and the verdict says so.
expect "$D/dn/diagnosis.json" 'all(r["visible"] or r["beyond_tried"] for r in j["reach"] if r["strongest_probed"] > 0)' \
  "a candidate the table cannot see was not tried beyond it" "$D/dn/report.md"
# One that does not show at the file's strongest probe is stepped past it (power.h, extend_reach) up to the
# end of the range it can run: a strength beyond the file's probes, or the reason it stopped, for each.
expect "$D/dn/diagnosis.json" 'all(r["visible"] or r["extension_stop"] for r in j["reach"] if r["strongest_probed"] > 0)' \
  "an unseen candidate's reach does not say why it stopped" "$D/dn/report.md"
expect "$D/dn/diagnosis.json" 'all(r["strongest_probed"] > r["extended_from"] for r in j["reach"] if r["extended_from"] > 0)' \
  "a reach stepped past the probes without a stronger run"
expect "$D/dn/diagnosis.json" 'any(r["extended_from"] > 0 for r in j["reach"])' \
  "no unseen candidate was stepped past the file's strongest probe" "$D/dn/report.md"
# A candidate the table cannot see is never the one named (power.h, mark_unseen).
expect "$D/ds/diagnosis.json" 'j["effect"] not in j["not_named_unseen"]' "an effect the table cannot see was named"
# "To see it, measure O at C" is never said on one run pair: a 3 sigma shift beyond the table is confirmed on
# the baseline's seeds (power.cpp), and the report scales each run's own error to the seed spread.
expect "$D/dn/diagnosis.json" 'all(r["beyond_seeds"] >= 2 for r in j["reach"] if r["beyond_max_abs_z"] >= 3) and "within_inflation" in j' \
  "a shift beyond the table was claimed on one run pair" "$D/dn/report.md"
# A 3 sigma shift beyond the table is promised for the strongest strength only; weaker strengths run there too
# (power.h, next_weaker_strength: the proportional one first), each weaker than the strongest, the bracket they
# give is consistent, and the paragraph says what they measured.
expect "$D/dn/diagnosis.json" 'all(all(0 < w["strength"] < r["strongest_probed"] for w in r["beyond_weaker"]["runs"]) and (not r["beyond_weaker"]["runs"] or (r["beyond_max_abs_z"] >= 3 and 0 < r["beyond_weaker"]["shows_from"] <= r["strongest_probed"] and r["beyond_weaker"]["short_at"] < r["beyond_weaker"]["shows_from"] and "run there on the same seeds" in j["paragraph"])) for r in j["reach"])' \
  "a weaker strength was run beyond the table without a 3 sigma shift of the strongest, or not reported" "$D/dn/report.md"
expect "$D/dn/diagnosis.json" 'all(r["beyond_weaker"]["runs"] or r["beyond_max_abs_z"] * 0.9 < 3 or any("reach: " + r["effect"] in n for n in j["notes"]) for r in j["reach"] if r["beyond_max_abs_z"] >= 3 and r["beyond_seeds"] >= 2)' \
  "a shift beyond the table well over 3 sigma got no run at a weaker strength" "$D/dn/report.md"
expect "$D/dn/diagnosis.json" 'all(r["visible"] or ("`" + r["effect"] + "`") in j["paragraph"].split("cannot see")[-1] for r in j["reach"])' \
  "the paragraph does not name a candidate the table cannot see" "$D/dn/report.md"
# What a table without a gap rules out (limits.h): each run's flag follows its Δχ² and threshold, every
# candidate ruled out is named in the paragraph, and a verdict with a gap has none.
expect "$D/dn/diagnosis.json" 'j["limits"] and all(all((x["delta_chi2"] >= x["rule_out_at"]) == x["ruled_out"] for x in l["runs"]) and (l["ruled_out_from"] == 0 or ("`" + l["effect"] + "` from") in j["paragraph"]) for l in j["limits"])' \
  "the limits of a table without a gap are inconsistent or not reported" "$D/dn/report.md"
# The sink, ruled out at its default rate, ran the other rates too: its limit with the rate free is where
# every rate rules it out (the largest of theirs, or none when one rules out nothing), and the paragraph says so.
expect "$D/dn/diagnosis.json" 'any(f["effect"] == "absorption" for f in j["limits_free_shape"]) and all(len(f["shapes"]) == len([l for l in j["limits"] if l["effect"] == f["effect"]]) and f["ruled_out_from"] == (max(l["ruled_out_from"] for l in j["limits"] if l["effect"] == f["effect"]) if all(l["ruled_out_from"] > 0 for l in j["limits"] if l["effect"] == f["effect"]) else 0) and " free (" in j["paragraph"] for f in j["limits_free_shape"])' \
  "a sink's limit with its rate free is inconsistent with its rows or not said" "$D/dn/report.md"
expect "$D/ds/diagnosis.json" 'j["limits"] == [] and j["limits_free_shape"] == []' "limits reported for a verdict with a gap"
echo "micro diagnosis e2e: $(($(date +%s) - t0)) s"
