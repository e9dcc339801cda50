// The state of one diagnosis as its stages fill it in (diagnosis.md §4), and the runs they share. A reader
// follows the procedure by file name: baseline.cpp, where.cpp, screen.cpp, fit_stage.cpp (with the statistics
// of fit.cpp), verdict.cpp, shrink.cpp, second_effect.cpp, next_experiment.cpp, next_bound.cpp, power.cpp;
// driver.cpp calls them in that order and report.cpp writes what they found.
#pragma once

#include <limits>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "diagnose/driver.h"
#include "diagnose/effects.h"
#include "diagnose/files.h"
#include "diagnose/limits.h"
#include "diagnose/power.h"
#include "diagnose/runbook.h"
#include "diagnose/table.h"
#include "diagnose/verdict.h"
#include "diagnose/where.h"

namespace wetdem::diagnose {

// One fitted candidate: its runs at every member of its family (a refit setting x a shape of its second
// parameter), and what limited its range.
struct CandidateRuns {
  std::string effect;
  double screen = 0.0;
  std::vector<double> shapes;              // the second parameter's values ({NaN}: the effect has none)
  std::vector<Response> members;           // one response per member with runs
  std::vector<size_t> refit_of, shape_of;  // per member
  double cut = std::numeric_limits<double>::infinity();  // strengths >= cut cannot run (failed or too costly)
  int at_limit = 0;                // the fit ran into the physical range: -1 low end, +1 high end
  std::vector<std::string> notes;  // what happened to its range: extended, cut, failed runs
  // The member of (refit setting j, shape m), created empty when absent.
  Response& member(size_t j, size_t m);
  Family family(const std::vector<std::vector<Prediction>>& baselines) const;
};

// A candidate's screen score (screen.cpp).
struct Screened {
  double score = 0.0;
  std::string effect;
  double strength = 0.0;  // the probe the score comes from (0: none could run)
};

// The chosen model (or a tied one) run with fresh seeds at every condition.
struct FreshCheck {
  std::string effect;
  double strength = 0.0;
  size_t refit = 0;
  double shape = std::numeric_limits<double>::quiet_NaN();
  std::vector<Prediction> after;  // empty when its runs failed
  std::vector<CellGap> gaps_after;
  std::string failure;
};

// A gap found on the baseline's seeds only: no candidate's fresh runs confirmed it (fresh_rejected,
// verdict.h) and the model itself on the fresh seeds (`null_fresh`, the shrink's control) departs from no
// cell at the table's level (has_gap, where.h). More seeds of the model may close it (the flowing off-grid
// null, 6 Dec 2026: 3 of 40 cells at R = 2, χ² 21.0 over 40 and none on seeds 3-4; no_gap at R = 4). Read by
// the report's paragraph and by the escalation (driver.cpp), so both say the same.
bool gap_on_baseline_seeds_only(bool fresh_rejected, const FreshCheck& null_fresh, double table_level);

// One proposal of the next-experiment stage: a condition (in or beyond the table), the observable where two
// tied models differ most there, and by how much relative to the noise.
struct Proposal {
  std::string condition;  // "liquid.content=15 %, drum.rpm=60"
  std::string observable;
  double model_a = 0.0, model_b = 0.0, se_a = 0.0, se_b = 0.0, sigma = 0.0;
  double separation = 0.0;  // |a - b| / sqrt(sigma² + se_a² + se_b²)
  bool in_table = false;    // the condition is one the table already has
  bool assay = false;       // the observable is not in the table: an assay the file names ([assays])
  size_t seeds = 0;         // seeds behind each model's number (one: a condition that did not look promising)
  // The separation once each model may re-fit its strength to the other's value there (refit_separation,
  // next_experiment.h); NaN where the models were not run at their probed strengths at this condition.
  double refit_separation = std::numeric_limits<double>::quiet_NaN();
  // The bound experiment's: how often the measurement must be repeated to reach kDecisive (repeats_for,
  // next_experiment.h); 0 when repeating it cannot (the runs' own error), or where not computed.
  size_t repeats = 0;
};
// An assay made on every sample of the table: the pair's separation over all its conditions together.
struct AssaySeries {
  std::string observable;
  size_t conditions = 0;    // the table's conditions at which both models report it
  double separation = 0.0;  // sqrt(sum of each condition's separation²): independent measurements
  double refit_separation = std::numeric_limits<double>::quiet_NaN();  // all of them, each model re-fitted
};
// Two measurements at two conditions made together: a model that can re-fit its strength to match one
// measurement may be unable to match both (the fraction a saturating sink leaves free changes with content, a
// steady one's does not).
struct ProposalPair {
  Proposal first, second;
  double separation = 0.0;  // the two separations in quadrature
  double refit_separation = 0.0;
};
struct NextExperiment {
  std::string effect_a, effect_b;
  std::vector<Proposal> proposals;  // best first
  std::vector<ProposalPair> pairs;  // of the proposals with a refit separation, best first
  std::vector<AssaySeries> series;  // per assay ([assays]), best first
  // The separation after re-fit a measurement needs to decide the tie on fresh runs (needed_separation,
  // next_experiment.h); 0 where not known.
  double needed = 0.0;
  // How often the best single measurement must be made to reach max(kDecisive, needed) (tie_repeats,
  // next_experiment.h): 1 once is enough, 0 no number of repeats would (or its runs were a screen).
  size_t repeats = 0;
  std::string note;  // why none was run, when none was
};

// The measurement that would close the chosen effect's open interval (next_bound.h): the effect at the
// interval's closed end (model_a of each proposal) and at its open end (model_b).
struct BoundExperiment {
  std::string effect;
  double closed = 0.0, open = 0.0;  // strengths
  bool above = true;                // open above: strength >= closed
  bool both = false;                // open at both ends
  double shape = std::numeric_limits<double>::quiet_NaN();
  size_t refit = 0;
  std::vector<Proposal> proposals;  // best first
  std::string note;                 // why none was run, when none was
  size_t seeds = 1;  // the baseline's seeds: a repeated measurement is asked for on all of them
};

// The second round (second_effect.h): a second candidate fitted on top of the first effect when that one
// explains the gap only in part.
struct SecondRound {
  std::string base_effect;  // the first effect, at its fitted strength, refit setting and shape
  double base_strength = 0.0;
  double base_shape = std::numeric_limits<double>::quiet_NaN();
  size_t refit = 0;
  std::vector<Prediction> base;       // the model with the first effect, seeds 1..R: the round's null
  std::vector<CellGap> base_gaps;     // the cells it leaves
  std::vector<Screened> screened;     // the other candidates against what it leaves, best first
  std::vector<CandidateRuns> fitted;  // their runs on top of it (one member each)
  Verdict verdict;                    // step 5's rule with the first effect as the null
  FreshCheck fresh;                   // the pair at the fitted strength, fresh seeds (effect: the second)
  std::string outcome;                // second_outcome(); "" when the round did not run
  std::vector<std::string> notes;
  // The joint re-fit (pair_fit.h) of the best second candidate with the first: the pair's optimum on the
  // additive emulator of the first alone and the second on top of it (0: not computed), χ² there and at the
  // stepwise fit, and the pair's held-out χ² with both strengths re-fitted in every fold (loco_pair).
  std::string joint_effect;
  double joint_first = 0.0, joint_second = 0.0, joint_chi2 = 0.0, stepwise_chi2 = 0.0;
  double joint_first_shape = std::numeric_limits<double>::quiet_NaN();  // the first's shape there
  double joint_loco = 0.0;
  // The pair's fresh runs are at the joint optimum, the first at joint_first (rounded): the second failed the
  // rule with the first held at its own fit and the pair's held-out χ² passes it (`joint_rescued`), or it
  // passed stepwise and the pair fitted jointly predicts the left-out conditions better.
  bool joint = false;
  bool joint_rescued = false;
  double pair_first = 0.0;  // the first's strength in the pair's fresh runs (base_strength unless joint)
  double pair_first_shape = std::numeric_limits<double>::quiet_NaN();  // ... and its shape
  // The comparison of the pair's fresh runs with the first alone was decided by the seed luck alone.
  bool held_by_luck = false;
};

// Would more seeds decide an undecided verdict (more_seeds.h)? One tie's outlook at R' seeds per condition,
// for the two models as fitted now: more seeds also re-fit both, which can move them apart (or together).
struct TieOutlook {
  std::string effect;    // the tied candidate (against the chosen one)
  bool known = false;    // both have fresh runs: the separation below was estimated
  double at_more = 0.0;  // predicted_separation at R' seeds
  double exact = 0.0;    // ... with exact models (R' → ∞); not a bound (cells below 0 weigh more)
  double margin = 0.0;   // the fresh tie margin at R' (fresh_tie_margin, the luck scaled by R/R')
  int seeds_needed = 0;  // the fewest seeds per condition (up to kMostSeeds) at which the separation reaches
                         // the margin there; 0: none
  bool could_decide() const { return !known || at_more >= margin; }
};

struct MoreSeeds {
  int from = 0, to = 0;          // seeds per condition now and in the outlook (to = 0: not computed)
  std::vector<TieOutlook> ties;  // one per tied candidate
  // Undecided for a reason no outlook covers: the chosen effect unconfirmed by the luck, a second effect's
  // confirmation, a gap on the baseline's seeds only.
  std::vector<std::string> other;
  // More seeds could decide the verdict: some tie could be decided, or something else is undecided.
  bool worth() const;
};

// The first pass of an escalated diagnosis (DiagnosisSpec::escalate_replicates; driver.cpp): at `from` seeds
// per condition its verdict was not decided (a tie, or a comparison the seed luck decided), so the diagnosis
// ran again at `to`.
struct Escalation {
  int from = 0, to = 0;
  std::vector<std::string> tied;          // the first pass's ties
  std::vector<std::string> held_by_luck;  // what the luck decided in the first pass
  double seed_luck = 0.0;                 // the first pass's luck (χ²)
  bool baseline_only = false;             // its gap unconfirmed, and absent from the model's fresh seeds
  std::string verdict;                    // the first pass's verdict: "partial (cohesion; tied: hysteresis)"
  size_t runs_computed = 0;               // runs the first pass computed
  MoreSeeds outlook;                      // why more seeds could decide it (more_seeds.h)
};

class Procedure {
 public:
  Procedure(const DiagnosisSpec& d, const DiagnoseOptions& o);
  Procedure(const Procedure&) = delete;  // d refers to this object's own spec

 private:
  // The file's spec, less the [assays] the table measures now (the constructor; assays_in_table says which).
  DiagnosisSpec spec_;

 public:
  const DiagnosisSpec& d;
  const DiagnoseOptions& o;
  Table tab;
  RunBook book;
  std::string store;
  std::vector<RefitSetting> settings;  // refit settings (setting 0: as calibrated)
  std::vector<ModelFacts> models;      // per setting
  std::vector<std::string> effects;    // the candidates that can act in the model
  std::vector<uint64_t> base_seeds, fresh_seeds, probe_seeds;
  // Per table condition: the particle-steps of one baseline run there (the cost unit of max_cost there).
  std::vector<double> base_steps;

  // Filled by the stages, in order.
  std::vector<std::vector<Prediction>> baselines, seed1;  // per refit setting: mean over the seeds, seed 1
  std::vector<double> spread;                             // per cell: run-to-run sd of one run
  std::map<std::string, double> within_inflation;  // per observable: seed spread / own window SE (>= 1)
  std::vector<CellGap> gaps;
  std::vector<Screened> screened;  // best first
  std::vector<CandidateRuns> fitted;
  Verdict verdict;
  std::vector<FreshCheck> fresh;  // the chosen effect first, then any tied one
  FreshCheck null_fresh;          // the model without an effect at the fresh seeds (the shrink's control)
  std::vector<FreshCheck> confirmations;  // the chosen one's fresh check at every strength the rounds ran
  NextExperiment next;
  BoundExperiment bound;  // the measurement that would close an open interval (next_bound.h)
  SecondRound second;
  std::vector<Reach> reach;   // what the table can see of every candidate (power.h)
  std::vector<Limit> limits;  // what a no_gap table rules out of each (limits.h)
  // per (effect, shape; 0: none): strengths run to bracket its limit
  std::map<std::pair<std::string, double>, std::set<double>> limit_strengths;
  std::map<std::string, std::set<double>> reach_strengths;  // per effect: strengths run past its probes
  std::vector<std::string> unseen;              // fitted candidates whose runs the table cannot see (power.h)
  std::vector<std::string> unseen_rejected;     // of them, tied held out but clearly worse on fresh runs
  std::vector<std::string> seen_on_fresh;       // of them, shown by their fresh runs (power.h, fresh_shift)
  std::vector<std::string> confirmed_on_fresh;  // of them, named first in a tie once their fresh runs
                                                // confirmed them (fresh_ties.cpp, order_tie_by_evidence)
  std::vector<std::string> notes;               // failed runs, cut ranges, what could not be probed
  // [assays] of the file that the table measures now: its observables (d lacks them)
  std::vector<std::string> assays_in_table;
  Escalation escalation;  // from = 0: this is the only pass
  MoreSeeds more_seeds;   // to = 0: the verdict was decided (more_seeds.h)

  // The effect (none: "") at strength s, refit setting j, shape value (NaN: the effect's default shape).
  Variant variant(const std::string& effect, double s, size_t j = 0,
                  double shape = std::numeric_limits<double>::quiet_NaN()) const;
  // The most particle-steps v needs at any condition of the table, each in baseline runs at that same
  // condition (0 when unknown): the cost guard's measure (want refuses above max_cost). Per condition, so
  // that a table with one long row (a 12 s run beside 3 s ones) does not count every variant's long run
  // against the short baseline and cap every probe. Particle-steps, not steps: a finer scaling multiplies the
  // particles as well as the steps (scale 0.4: 4.6x the particles), and counted in steps it ran as cheap.
  double cost(const Variant& v) const;
  // Every condition of the table, with these seeds. "" when wanted; else why it will not run (its cost).
  std::string want(const Variant& v, const std::vector<uint64_t>& seeds);
  // The fitted candidates' families (one emulator per member), the unseen included (decide_seen).
  std::vector<Family> families() const;
  // The seed-spread factor of an observable's own window errors (1 when unknown).
  double inflation(const std::string& observable) const {
    const auto it = within_inflation.find(observable);
    return it == within_inflation.end() ? 1.0 : it->second;
  }
  // Runs what is wanted; failures are recorded in the book (RunBook::run).
  void run() { book.run(); }
  // Why some run of v at these seeds failed ("" when all completed).
  std::string failure(const Variant& v, const std::vector<uint64_t>& seeds) const {
    return book.failure(tab.conditions, v, seeds);
  }
  // Mean and SE over the seeds, per cell; NaN where no run of v reports the cell's observable.
  std::vector<Prediction> predict(const Variant& v, const std::vector<uint64_t>& seeds) const;
  // A probe at refit setting j (its P = probe_seeds seeds) as a knot of the emulator: common random numbers
  // against the same seeds of the baseline at j, on top of that setting's replicate mean (knot_se).
  std::vector<Prediction> probe(const Variant& v, size_t j) const;
};

// The SE of a probe knot over P seeds against the same P seeds of the baseline, on top of the mean over R:
// s √(2/P + 1/R), s the larger of the baseline's run-to-run sd (spread) and the probe's own (probe_se, the SE
// of its P-seed mean, times √P). It counts the spread of the probe's mean and of the baseline's P seeds and
// the error of the R-seed mean, and leaves out the common random numbers' correlation (conservative). With
// P = 1 it is s √(2 + 1/R).
double knot_se(double spread, double probe_se, size_t probe_seeds, size_t replicates);

}  // namespace wetdem::diagnose
