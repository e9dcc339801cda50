#!/usr/bin/env bash
# End to end on the micro drum, through the CLI: an unseen lead that alone passes the held-out rule
# (shrink.cpp, try_unseen_lead). Cohesion at 0.06 J/m² withheld; its probes move no cell by 3 σ, so before its
# fresh runs it cannot be named and no other candidate passes. Its fresh runs at the fitted strength, against
# the control on the same seeds, show it (f_wet at 5 %) and confirm the fit, so the verdict names it, and says
# why a candidate its probes could not show is named.
# usage: unseen_lead_e2e.sh WETDEM SOURCE_DIR [STORE]
source "$(dirname "$0")/lib.sh" "$@"

wd twin "$SRC/tests/diagnose/twin_cohesion_mid_ci.toml" --out "$D/t" --store "$S" --quiet
wd diagnose "$SRC/assets/diagnosis/micro/diagnose.toml" --observations "$D/t/observations.csv" --out "$D/d" \
  --store "$S" --quiet --no-figures
echo "unseen lead: $(J "$D/d/diagnosis.json" 'j["verdict"], j["effects"], j["seen_on_fresh"], j["chi2_null_fresh"]')"
expect "$D/d/diagnosis.json" 'j["verdict"] == "effect" and j["effects"] == ["cohesion"]' \
  "the unseen lead was not named through its fresh runs" "$D/d/report.md"
expect "$D/d/diagnosis.json" '"cohesion" in j["seen_on_fresh"] and "cohesion" not in j["unseen"]' \
  "cohesion is not listed as seen on its fresh runs"
expect "$D/d/diagnosis.json" 'any(n.startswith("shrink: cohesion passes the held-out rule alone and is seen on its fresh runs") for n in j["notes"])' \
  "no note says the lead alone passed and was seen on its fresh runs"
# Named only with both halves of the rule (power.h, names_unseen_lead): its fresh runs beat the control on the
# same seeds by min_drop or the seed luck, and leave no cell significant.
expect "$D/d/diagnosis.json" 'j["fresh"][0]["chi2_after"] <= j["chi2_null_fresh"] - max(j["rule"]["min_drop"], j["seed_luck_chi2"])' \
  "the lead's fresh runs do not confirm the fit against the control"
expect "$D/d/diagnosis.json" 'j["fresh"][0]["significant_cells"] == 0' "the lead's fresh runs leave cells"
expect_text "$D/d/report.md" "its fresh runs at .* do against the model without it on the same seeds" \
  "the paragraph does not say why a candidate its probes could not show is named"
# An interval the table leaves open (cohesion runs to its physical limit here) gets the measurement that would
# close it (next_bound.h): both ends run beyond the table, and the paragraph names the best or says it stays open.
expect "$D/d/diagnosis.json" 'not any(c["effect"] == j["effect"] and any(c["strength_interval_open"]) for c in j["ranking"]) or (j["bound_experiment"]["effect"] == j["effect"] and any(not q["in_table"] for q in j["bound_experiment"]["proposals"]))' \
  "an open interval got no bounding experiment beyond the table" "$D/d/report.md"
expect "$D/d/diagnosis.json" '"bound_experiment" not in j or ("To bound" in j["paragraph"] or "stays open" in j["paragraph"])' \
  "the paragraph does not say how to bound the open interval"
echo "unseen-lead e2e: $(($(date +%s) - t0)) s"
