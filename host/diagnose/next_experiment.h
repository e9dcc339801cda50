// Step 7 of the diagnosis (diagnosis.md §4): when the runner-up is not clearly worse than the chosen effect
// (verdict.h, the tie rule), the measurement that would separate them. Both fitted models are run at
// conditions in and beyond the table — the table's condition keys at new values (between the measured ones
// and one step past the last), another drum speed, a longer run — and the condition and observable where
// they differ most relative to the noise is what the engineer should measure next.
#pragma once

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "diagnose/measurement_noise.h"
#include "diagnose/procedure.h"
#include "diagnose/refit_separation.h"

namespace wetdem::diagnose {

// Fills Procedure::next (nothing when there is no tie, or next_conditions = 0).
void run_next_experiment(Procedure& p);

// The conditions proposed beyond the table, at most `max`: each is `base` with one key changed. In order:
// for each condition key of the table one step past its largest value; the drum speed x2 and x1/2 and the run
// x4 longer when they are not condition keys; each key two steps past its largest; the midpoints between its
// measured values. A step is the gap between the two largest values. Values are written in the unit the
// table uses for the key. A drum speed above `max_omega` (rad/s) is not proposed. Pure (tests).
std::vector<Condition> propose_conditions(const std::vector<Condition>& table, const Condition& base,
                                          double model_rpm, double model_duration_s, size_t max,
                                          double max_omega = std::numeric_limits<double>::infinity());

// The fastest drum speed (rad/s) whose Froude number ω²R/g stays within `max_froude` (DiagnosisSpec): a
// laboratory measures AoR and surface flow in a bed with a free surface, not one thrown about or centrifuged.
// Infinite when the radius is unknown (<= 0).
double max_drum_omega(double drum_radius_m, double max_froude);

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
