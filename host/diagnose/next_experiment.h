// Step 7 of the diagnosis (diagnosis.md §4): when the runner-up is not clearly worse than the chosen effect
// (verdict.h, the tie rule), the measurement that would separate them. Both fitted models are run at
// conditions in and beyond the table — the table's condition keys at new values (between the measured ones
// and one step past the last), another drum speed, a longer run — and the condition and observable where
// they differ most relative to the noise is what the engineer should measure next.
#pragma once

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// Fills Procedure::next (nothing when there is no tie, or next_conditions = 0).
void run_next_experiment(Procedure& p);

// The conditions proposed beyond the table, at most `max`: each is `base` with one key changed. In order:
// for each condition key of the table one step past its largest value; the drum speed x2 and x1/2 and the run
// x4 longer when they are not condition keys; each key two steps past its largest; the midpoints between its
// measured values. A step is the gap between the two largest values. Values are written in the unit the
// table uses for the key. Pure (tests).
std::vector<Condition> propose_conditions(const std::vector<Condition>& table, const Condition& base,
                                          double model_rpm, double model_duration_s, size_t max);

// Orders the proposals best first: those with a refit separation by it, before those without (they were not
// among the best by separation, which bounds the refit separation up to the probes' noise). A condition the
// laboratory already prepared (in_table) is the cheaper experiment: it comes first unless a new one separates
// the pair by more than `new_condition_factor` times as much (the absorption-weak twin: the free liquid at
// 2.5 % in the table, 9.96 sigma, against 1.25 %, 9.98). Equal ranks keep their order (stable). Pure (tests).
inline constexpr double kNewConditionFactor = 1.05;
void rank_proposals(std::vector<Proposal>& proposals, double new_condition_factor = kNewConditionFactor);

// `first`, then the conditions of `second` it lacks (by label), at most `max_second` of them, in their order.
// Pure (tests).
std::vector<Condition> merge_conditions(std::vector<Condition> first, const std::vector<Condition>& second,
                                        size_t max_second);

// A measurement added to the table for the refit separation: the cell it would give if one model were right
// (that model's value there; σ² the measurement's noise² plus that value's SE²), and the other model's
// response there: its null (without the effect, at its refit setting) and its prediction at every strength of
// its response, in order.
struct ExtraMeasurement {
  Cell cell;
  Prediction null;
  std::vector<Prediction> knots;
};

// How much the rival's least χ² rises when the measurements are added and it re-fits its strength to them:
// min_s [χ²_table(s) + Σ z_extra(s)²] − min_s χ²_table(s), both through the rival's emulator (fit_strength;
// `baseline` and `rival` are the table's, the extra cells are appended to them). >= 0. Pure (tests).
double refit_rise(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
                  const Response& rival, const std::vector<ExtraMeasurement>& extra);

// The same for a rival with a second parameter (absorption's rate) or refit settings: each member re-fits its
// strength, and the rise is min over the members that know every extra measurement of their χ² with them,
// minus min over all members of their χ² on the table alone (the profile's best). NaN when no member knows
// them. `baseline` and `response` point at the member's own. Pure (tests).
struct RivalMember {
  const std::vector<Prediction>* baseline = nullptr;
  const Response* response = nullptr;
  std::vector<ExtraMeasurement> extra;
  bool known = true;  // its response at every extra measurement is known
};
double refit_rise(const std::vector<Cell>& cells, const std::vector<RivalMember>& family);

// The separation of two fitted models compares them at their fitted strengths. A measurement the rival
// matches by re-fitting its strength separates nothing: one free-liquid value at one content, which a
// saturating sink matches with another pore capacity (evaporation-strong, docs/validation.md). So a design is
// also judged with each model free to re-fit: √min(rise of b if a is right, rise of a if b is right), in σ
// (the T-optimal criterion for discriminating two models, Atkinson & Fedorov 1975, applied both ways).
inline double refit_separation(double rise_b_if_a, double rise_a_if_b) {
  const double m = rise_b_if_a < rise_a_if_b ? rise_b_if_a : rise_a_if_b;
  return m > 0 ? std::sqrt(m) : 0.0;
}

// The separation after re-fit that a measurement needs to decide the tie on fresh runs: the rival's fresh χ²
// must come to exceed the first's by fresh_tie's margin, max(tie_delta x max(1, χ²_a / n), luck) over n cells
// (verdict.h), and a rise of the rival's least χ² by that much is √ of it in σ. On evaporation-strong's table
// the model's own seed luck (16.1) sets it: about 4 σ, where the plain 2 σ of a significant difference would
// not decide. Pure (tests).
double needed_separation(double chi2_a, size_t n, const VerdictRule& rule, double luck);

// What a proposal is judged by: its separation after re-fit where known, else the plain one.
inline double judged_separation(double refit, double plain) {
  return std::isfinite(refit) ? refit : plain;
}

// Whether two measurements made together are the better next experiment than the best single one: their
// refit separation exceeds √2 times the single's, what making the single measurement twice would give (a
// pair that does better breaks the rival's re-fit, not only the noise), and reaches kDecisive: a pair that
// still cannot decide is not worth twice the work. Pure (tests).
inline constexpr double kDecisive = 2.0;  // σ left after the re-fit below which a measurement may not decide
bool pair_beats_single(const ProposalPair& pair, const Proposal& single);

// The noise of a new measurement of each observable: the table's median sigma for it.
std::map<std::string, double> median_sigma(const std::vector<Cell>& cells);

// What a new measurement of each observable would carry: its noise σ (the table's median σ; an assay's, the
// σ its file gives), the factor that scales one run's own window SE to the model's seed spread, and the
// model's typical squared SE of a table cell's mean (the median over the table's cells of the baseline's,
// per table observable; sigma_at).
struct MeasurementNoise {
  std::map<std::string, double> sigma, inflation, typical_se2;
};
MeasurementNoise measurement_noise(const Procedure& p);

// One new measurement's noise at a condition where the two models' means carry se_x and se_y. A table row's
// σ holds the instrument's noise and the spread of the runs the laboratory averaged, σ² = σ_i² + s²/n, and
// the model's SE over its R seeds estimates the second part (n ≈ R). Where the runs spread more than at the
// table's typical cell (a wet bed that sticks and slips at 20 % liquid), a measurement there carries the
// excess: σ_c² = σ² + max(0, (se_x² + se_y²)/2 − typical_se2). Never below the table's σ (calmer conditions
// are not trusted to be quieter); σ itself where typical_se2 has no entry (assays: their file's σ is whole).
// On the flowing viscous-weak twin the row at 60 rpm, 20 % came back with σ 0.031 m/s against the 0.0155
// assumed (docs/validation.md, "A measurement repeated").
double sigma_at(const MeasurementNoise& n, const std::string& observable, double se_x, double se_y);

// |x - y| / sqrt(σ_c² + se_x² + se_y²), σ_c = sigma_at: how far two models' predictions of one measurement
// lie apart in its noise.
double separation_of(const MeasurementNoise& n, const std::string& observable, const Prediction& x,
                     const Prediction& y);

// How many times a laboratory would repeat one measurement (entering their mean, with σ/√k) for two
// predictions |delta| apart to lie `target` σ apart: the smallest k ≤ kMaxRepeats with
// |delta| / sqrt(σ²/k + se²) ≥ target, se² the two models' own squared errors (repeats shrink the
// measurement's noise, not the runs'). 0 when none does: the runs' own error alone holds |delta| under
// target σ (more seeds of them first), or more than kMaxRepeats would be needed. 1: one measurement does.
// Pure (tests).
inline constexpr size_t kMaxRepeats = 16;
size_t repeats_for(double delta, double sigma, double se2, double target);

// How often the tie's best single measurement must be made for its separation (after re-fit where known:
// judged_separation) to reach `needed` σ: repeats_for on the difference that separation implies,
// |Δ| = s √(σ² + se_a² + se_b²). 0 when none would, or when its models ran on fewer than `seeds` seeds (a
// condition beyond the table left on its first seed: a screen's number, not a claim). Pure (tests).
size_t tie_repeats(const Proposal& q, double needed, size_t seeds);

// Two models a, b at condition c on these seeds (their runs made), for one observable.
Proposal compare_at(const Procedure& p, const Variant& a, const Variant& b, const MeasurementNoise& n,
                    const Condition& c, const std::vector<uint64_t>& seeds, const std::string& observable,
                    bool in_table);

// Both models at condition c on these seeds (their runs made), for every observable of the table and every
// assay both report; empty when a run of either failed (noted in p.notes under `stage`). Shared by
// measure_beyond and the interval's confirming round (next_bound.cpp).
std::vector<Proposal> measure_at(Procedure& p, const Variant& a, const Variant& b, const MeasurementNoise& n,
                                 const Condition& c, const std::vector<uint64_t>& seeds,
                                 const std::string& stage);

// Both models at each proposed condition, in two rounds: on the first base seed, then on every base seed
// where some observable already separates them by 2 σ. Every observable of the table and every assay, per
// condition; `wanted` gets the conditions that could be run (the others, and failed runs, are noted in
// p.notes under `stage`). Shared by the tie's experiment and the interval's (next_bound.h).
std::vector<Proposal> measure_beyond(Procedure& p, const Variant& a, const Variant& b,
                                     const MeasurementNoise& n, std::vector<Condition>& props,
                                     std::vector<Condition>& wanted, const std::string& stage);

}  // namespace wetdem::diagnose
