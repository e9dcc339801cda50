#!/usr/bin/env bash
# End to end on the micro drum, through the CLI: the next experiment (next_experiment.cpp) with an assay the
# table lacks. The slow-evaporation twin of the escalation check ties the two liquid sinks at two seeds; both
# fitted models then run beyond the table (a run four times as long among the conditions), and the assay named
# in [assays] (the AoR's fluctuation) is weighed at the table's conditions (from the fresh runs) and beyond,
# with its own sd. It is never fitted: the verdict's cells are the table's.
# usage: next_e2e.sh WETDEM SOURCE_DIR [STORE]
source "$(dirname "$0")/lib.sh" "$@"

wd twin "$SRC/tests/diagnose/twin_evaporation_ci.toml" --out "$D/t" --store "$S" --quiet
wd diagnose "$SRC/tests/diagnose/micro_next_ci.toml" --observations "$D/t/observations.csv" --out "$D/d" --store "$S" \
  --quiet --no-figures
echo "verdict: $(J "$D/d/diagnosis.json" 'j["verdict"], j["effect"], j["tied"]')"
echo "best proposals: $(J "$D/d/diagnosis.json" \
  '[(q["condition"], q["observable"], round(q["separation"], 2), q["refit_separation"] and round(q["refit_separation"], 2), q["assay"]) for q in j["next_experiment"]["proposals"][:4]]')"
expect "$D/d/diagnosis.json" 'len(j["tied"]) > 0 and "evaporation" in [j["effect"]] + j["tied"]' \
  "the sinks did not tie with the truth among them (the check needs a tie)" "$D/d/report.md"
expect "$D/d/diagnosis.json" 'all(c["observable"] != "aor_deg_std" for c in j["cells"])' \
  "an assay entered the table's cells"
P='j["next_experiment"]["proposals"]'
expect "$D/d/diagnosis.json" "any(q['assay'] and q['in_table'] and q['observable'] == 'aor_deg_std' for q in $P)" \
  "the assay was not weighed at the table's conditions" "$D/d/report.md"
expect "$D/d/diagnosis.json" "any(q['assay'] and not q['in_table'] for q in $P)" \
  "the assay was not weighed beyond the table" "$D/d/report.md"
expect "$D/d/diagnosis.json" "all(q['sigma'] == 0.5 for q in $P if q['assay'])" "the assay's sd is not the file's"
# The assay on every sample of the table: its separations at the table's conditions in quadrature.
expect "$D/d/diagnosis.json" "[(a['observable'], a['conditions'] >= 2, abs(a['separation'] - sum(q['separation'] ** 2 for q in $P if q['assay'] and q['in_table']) ** 0.5) < 1e-9) for a in j['next_experiment']['assay_series']] == [('aor_deg_std', True, True)]" \
  "the assay series is not the table conditions' separations in quadrature"
expect_text "$D/d/report.md" "aor_deg_std (assay, not in the table)" "the report does not mark the assay"
expect "$D/d/diagnosis.json" "any('run.duration=1.2 s' in q['condition'] for q in $P)" \
  "no run four times as long (0.3 s -> 1.2 s) among the conditions"
# Two steps past the table's largest content (0-5-10 % -> 20 %), run or noted as not runnable.
expect "$D/d/diagnosis.json" "any(q['condition'] == 'liquid.content=20 %' for q in $P) or any('liquid.content=20 %' in n for n in j.get('notes', []))" \
  "the content two steps past the table (20 %) was neither proposed nor noted"
# The separation once each model re-fits its strength (refit_rise): at the table's conditions from the probes'
# runs, and at the best conditions beyond it from the runs at every probed strength; at most the plain
# separation up to the probes' noise (a re-fit can only help the rival), and the proposals rank by it.
R='[q["refit_separation"] for q in '"$P"' if q["refit_separation"] is not None]'
expect "$D/d/diagnosis.json" "any(q['refit_separation'] is not None and q['in_table'] for q in $P) and any(q['refit_separation'] is not None and not q['in_table'] for q in $P)" \
  "no refit separation in or beyond the table" "$D/d/report.md"
expect "$D/d/diagnosis.json" "all(q['refit_separation'] <= q['separation'] + 1.0 for q in $P if q['refit_separation'] is not None)" \
  "a refit separation well above the plain one (the re-fit can only help the rival)"
expect "$D/d/diagnosis.json" "$P[0]['refit_separation'] is not None and max($R) <= 1.05 * $P[0]['refit_separation'] + 1e-12" \
  "the first proposal is not the best after the re-fit"
expect_text "$D/d/report.md" "after re-fit (σ)" "the report has no separation after the re-fit"
# The checklist (report.h, asked_measurements): the tie's measurement first, its best single one or both of its
# pair, each made at least once; report.md carries it as a section.
expect "$D/d/diagnosis.json" "j['measure_next'] and j['measure_next'][0]['reason'] == 'tie' and j['measure_next'][0]['condition'] == ($P[0]['condition'] if not j['next_experiment']['pairs'] or len([m for m in j['measure_next'] if m['reason'] == 'tie']) == 1 else j['next_experiment']['pairs'][0]['first']['condition']) and all(m['repeats'] >= 1 for m in j['measure_next'])" \
  "measure_next does not start with the tie's measurement" "$D/d/report.md"
expect_text "$D/d/report.md" "## Measurements to make next" "the report has no checklist of measurements"
# The figure of the next experiment (plot_diagnosis.py), drawn from this diagnosis.json.
/usr/bin/python3 "$SRC/scripts/plot_diagnosis.py" "$D/d" > "$D/plot.log" 2>&1 || { cat "$D/plot.log"; echo "FAIL: plot_diagnosis.py"; exit 1; }
[ -s "$D/d/figures/next_experiment.png" ] || { echo "FAIL: no figures/next_experiment.png for a tie"; exit 1; }
[ -s "$D/d/figures/reach.png" ] || { echo "FAIL: no figures/reach.png (what the table can see)"; exit 1; }
# The laboratory makes the assay (the twin's own value and noise at the table's conditions: the same runs) and
# runs the same file on the table with its rows: the assay is one of the table's observables from then on (the
# report says so), not an error that stops the measuring loop (scripts/twin_measure.py).
sed -e "s|^case = .*|case = \"$SRC/assets/diagnosis/micro/model.toml\"|" -e '/^\[noise\]/a aor_deg_std = 0.5' \
  "$SRC/tests/diagnose/twin_evaporation_ci.toml" > "$D/twin_assay.toml"
wd twin "$D/twin_assay.toml" --out "$D/ta" --store "$S" --quiet
{ cat "$D/t/observations.csv"; grep ',aor_deg_std,' "$D/ta/observations.csv"; } > "$D/obs_assay.csv"
[ "$(grep -c ',aor_deg_std,' "$D/obs_assay.csv")" = 3 ] || { echo "FAIL: the assay's rows (3 contents)"; cat "$D/obs_assay.csv"; exit 1; }
wd diagnose "$SRC/tests/diagnose/micro_next_ci.toml" --observations "$D/obs_assay.csv" --out "$D/d2" --store "$S" \
  --quiet --no-figures
echo "with the assay's rows: $(J "$D/d2/diagnosis.json" 'j["verdict"], j["effect"], j["tied"]')"
expect "$D/d2/diagnosis.json" "any(c['observable'] == 'aor_deg_std' for c in j['cells'])" \
  "the assay's rows did not enter the table's cells"
expect "$D/d2/diagnosis.json" "not any(q['assay'] for q in j['next_experiment']['proposals'])" \
  "a table observable still proposed as an assay"
expect "$D/d2/diagnosis.json" "j['assays_in_table'] == ['aor_deg_std']" \
  "diagnosis.json does not say the assay is in the table now" "$D/d2/report.md"
expect_text "$D/d2/report.md" "aor_deg_std. was an assay of the diagnosis file (.assays.) and the table measures it now" \
  "the report does not say the assay is in the table now"
echo "next-experiment e2e: $(($(date +%s) - t0)) s"
