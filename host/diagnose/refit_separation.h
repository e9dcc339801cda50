// The separation of two fitted models after each re-fits its strength to a new measurement (diagnosis.md §4,
// the next experiment): how much the rival's least χ² rises when the measurements are added, what a tie needs
// to be decided on fresh runs, and when a pair of measurements beats the best single one. Pure (tests).
#pragma once

#include <cmath>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

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

}  // namespace wetdem::diagnose
