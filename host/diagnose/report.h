// What a diagnosis writes: diagnosis.json (schema in docs/diagnosis.md), report.md with a plain-language
// verdict, tables and figures (scripts/plot_diagnosis.py, Debian's matplotlib).
#pragma once

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// One stage of the procedure: its wall time and the runs it computed (driver.cpp).
struct StageCost {
  std::string stage;
  double wall_s = 0.0;
  size_t runs_computed = 0;
};

struct Report {
  const DiagnosisSpec* spec = nullptr;
  std::vector<Cell> cells;
  std::vector<std::string> cell_condition;  // label per cell
  std::vector<Prediction> baseline;
  std::vector<CellGap> gaps;
  std::vector<std::string> where;
  std::vector<Screened> screened;           // best first
  std::vector<CandidateRuns> fitted;        // the runs behind every fitted candidate
  std::vector<RefitSetting> settings;       // refit settings (one, as calibrated, without refit)
  std::vector<Prediction> null_refit_pred;  // with refit: the model without effect at the null's setting
  std::vector<CellGap> null_refit_gaps;
  Verdict verdict;
  std::vector<FreshCheck> fresh;  // the chosen effect's fresh-seed runs first, then any tied one's
  FreshCheck null_fresh;          // the model without an effect at the fresh seeds (the shrink's control)
  std::vector<FreshCheck>
      confirmations;  // the chosen one's fresh checks the confirmation rounds re-fitted from
  NextExperiment next;
  BoundExperiment bound;      // the measurement that would close the chosen effect's open interval
  SecondRound second;         // a second effect on top of the first (second_effect.h)
  std::vector<Reach> reach;   // what the table can see of each candidate (power.h)
  std::vector<Limit> limits;  // what a no_gap table rules out of each (limits.h)
  std::map<std::string, double> within_inflation;  // per observable (baseline.h)
  std::vector<std::string> unseen;                 // fitted, but the probes cannot show them (power.h)
  std::vector<std::string> seen_on_fresh;          // unseen on their probes, shown by their fresh runs
  std::vector<std::string> confirmed_on_fresh;     // unseen on their probes, named first in a tie on
                                                   // fresh runs that confirm them against the control
  std::vector<std::string> notes;                  // failed runs, cut ranges
  std::vector<std::string> not_measured;           // table rows that say a quantity was not measured
  std::vector<std::string> assays_in_table;        // [assays] of the file that the table measures now
  size_t runs = 0, computed = 0;
  std::string device, store;
  double wall_s = 0.0;
  std::vector<StageCost> stages;  // where the wall time went, in the procedure's order
  Escalation escalation;          // the first pass, when the seed luck decided it (from = 0: none)
  MoreSeeds more_seeds;           // whether more seeds could decide this verdict (to = 0: it is decided)
  // The file asks to run again at more seeds only where they could decide (`escalate_when = "decidable"`),
  // and the outlook said they could not: it did not run again.
  bool escalation_held_back = false;

  const CandidateRuns* runs_of(const std::string& effect) const;
  const FreshCheck* fresh_of(const std::string& effect) const;
  // The chosen effect's fresh check (nullptr when none was made).
  const FreshCheck* chosen() const { return fresh.empty() ? nullptr : &fresh.front(); }
  // The second effect the verdict names with the first (its round's best, passing the rule), or nullptr.
  const Candidate* second_named() const {
    return (second.outcome == "closes" || second.outcome == "part") && !second.verdict.ranking.empty()
               ? &second.verdict.ranking.front()
               : nullptr;
  }
  // The pair's fresh check when its runs were made, else nullptr.
  const FreshCheck* second_fresh() const {
    return second_named() && !second.fresh.after.empty() ? &second.fresh : nullptr;
  }
  const CandidateRuns* second_runs_of(const std::string& effect) const;
};

Report make_report(const Procedure& p, double wall_s, std::vector<StageCost> stages = {});

// Writes DIR/diagnosis.json, DIR/report.md and (figures) DIR/figures/*.png; returns diagnosis.json.
nlohmann::json write_report(const std::string& dir, const Report& r, bool figures);

// The plain-language paragraph of report.md (paragraph.cpp).
// Whether the report carries a re-fitted parameter: shared by the report and its plain-language paragraph.
bool has_refit(const Report& r);

std::string verdict_paragraph(const Report& r);

// The verdict in one line, as the CLI prints it: "partial (cohesion + scale; tied: hysteresis)".
std::string verdict_line(const Verdict& v, const std::string& second = "");

// "liquid.v_max re-fitted to 0.5 %" ("liquid.v_max kept as calibrated") for refit setting j; "" without
// refit.
std::string refit_phrase(const Report& r, size_t j);

// A fitted strength with its interval, honest about open ends: "0.05 (0.03-0.08)", "0.2 (>= 0.12: the
// interval reaches the strongest strength probed)".
std::string strength_text(const Candidate& c, const CandidateRuns* runs);

// What the table can see of each candidate (power.h, every candidate's largest shift over its probe runs and
// its fresh runs): report.md's section and diagnosis.json's "reach" (report_reach.cpp).
std::string reach_markdown(const Report& r);
// Why a candidate's reach stopped where it still does not show (Reach::extension_stop), in words.
std::string reach_stop_words(const std::string& stop);
nlohmann::json reach_json(const Report& r);
// What a no_gap table rules out of each candidate (limits.h): report.md's section and diagnosis.json's
// "limits" (report_limits.cpp; nothing for another verdict).
std::string limits_markdown(const Report& r);
nlohmann::json limits_json(const Report& r);
// Each effect with a second parameter, its limit with that parameter free (limits.h, free_shape_limits).
nlohmann::json free_shape_limits_json(const Report& r);
// That limit in words, for the paragraph and report.md alike: "from pore capacity (...) = 0.125 with the rate
// k (1/s) free (0.3–30 run; set by rate k (1/s) = 0.3)", or "not ruled out with the rate k (1/s) free
// (0.3–30 run): at rate k (1/s) = 0.3 no run up to pore capacity (...) = 0.3, the end of its physical
// range, is".
std::string free_shape_text(const FreeShapeLimit& f);

// The measurement that would separate two tied effects (next_experiment.h): report.md's section (empty when
// nothing was proposed) and diagnosis.json's "next_experiment" (report_next.cpp).
std::string next_markdown(const Report& r);
nlohmann::json next_json(const Report& r);
// The same for the experiment that would close an open interval (report_bound.cpp).
std::string bound_markdown(const Report& r);
nlohmann::json bound_json(const Report& r);

// Every measurement the report asks a laboratory to make next, in the paragraph's order (the tie's, the
// interval's, then where each candidate the table cannot see would show), one per condition and observable.
// The rules are the paragraph's (paragraph_next.cpp, paragraph.cpp beyond_clause), written once here:
// report.md's checklist "Measurements to make next", diagnosis.json's "measure_next", and the list
// scripts/twin_measure.py makes on a twin (report_asked.cpp).
struct AskedMeasurement {
  std::string reason;  // "tie", "bound" or "reach"
  std::string effect;  // what it would decide: "a or b" (tie), the effect bounded, the effect it would show
  std::string condition;
  std::string observable;
  double sigma = 0.0;       // one measurement's noise (the table's median σ of the observable)
  size_t repeats = 1;       // made this often and entered as the mean (σ/√k)
  double separation = 0.0;  // what one measurement shows, in σ (after re-fit for a tie; a pair: jointly)
  bool in_table = false;    // a condition of the table (made again)
  bool assay = false;       // an assay the table does not have
  // The reach's: the strength its runs beyond the table had (its strongest), the one its promise is for.
  double strength = 0.0;
};
std::vector<AskedMeasurement> asked_measurements(const Report& r);
std::string asked_markdown(const Report& r);
nlohmann::json asked_json(const Report& r);

// The second round as diagnosis.json's "second" (null when it did not run) and its section of report.md.
nlohmann::json second_json(const Report& r);
std::string second_markdown(const Report& r);

}  // namespace wetdem::diagnose
