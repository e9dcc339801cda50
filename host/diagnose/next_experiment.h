// Step 7 of the diagnosis (diagnosis.md §4): when the runner-up is not clearly worse than the chosen effect
// (verdict.h, the tie rule), the measurement that would separate them. Both fitted models are run at
// conditions in and beyond the table — the table's condition keys at new values (between the measured ones
// and one step past the last), another drum speed, a longer run — and the condition and observable where
// they differ most relative to the noise is what the engineer should measure next.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// Fills Procedure::next (nothing when there is no tie, or next_conditions = 0).
void run_next_experiment(Procedure& p);

// The conditions proposed beyond the table, at most `max`: each is `base` with one key changed. For each
// condition key of the table, the midpoints between its measured values and one step past the largest; then
// the drum speed x2 and x1/2 and the run x4 longer when they are not condition keys. Values are written in
// the unit the table uses for the key. Pure (tests).
std::vector<Condition> propose_conditions(const std::vector<Condition>& table, const Condition& base,
                                          double model_rpm, double model_duration_s, size_t max);

// Orders the proposals best first. A condition the laboratory already prepared (in_table) is the cheaper
// experiment: it comes first unless a new one separates the pair by more than `new_condition_factor` times as
// much (the absorption-weak twin: the free liquid at 2.5 % in the table, 9.96 sigma, against 1.25 %, 9.98).
// Equal ranks keep their order (stable). Pure (tests).
inline constexpr double kNewConditionFactor = 1.05;
void rank_proposals(std::vector<Proposal>& proposals, double new_condition_factor = kNewConditionFactor);

// `first`, then the conditions of `second` it lacks (by label), at most `max_second` of them, in their order.
// Pure (tests).
std::vector<Condition> merge_conditions(std::vector<Condition> first, const std::vector<Condition>& second,
                                        size_t max_second);

// The noise of a new measurement of each observable: the table's median sigma for it.
std::map<std::string, double> median_sigma(const std::vector<Cell>& cells);

}  // namespace wetdem::diagnose
