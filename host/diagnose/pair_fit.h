// Step 6b's joint re-fit (diagnosis.md §4, "A second effect"; docs/diagnosis.md): the second round fits the
// second effect on top of the first *held at its own fit*, forward stepwise. When the two fingerprints share
// cells, the first effect fitted alone also takes the second's share of them (it is the only knob), and the
// second, fitted on what is left, comes out too weak or not at all: on the micro twin with a wetted fraction
// and fast absorption withheld, absorption fitted first left spread nothing to explain (docs/validation.md).
// Backfitting one coordinate at a time converges slowly along such a valley; a joint fit does not. Pure
// statistics: nothing here runs a model.
#pragma once

#include <vector>

#include "diagnose/cells.h"
#include "diagnose/emulator.h"

namespace wetdem::diagnose {

struct PairFit {
  size_t member = 0;                 // the first's member (shape) at the joint optimum
  double first = 0.0, second = 0.0;  // the joint optimum's strengths
  double chi2 = 0.0;                 // χ² over the cells there
  double chi2_stepwise = 0.0;        // at the first held at `first_fitted`, the second at its own best
  double second_stepwise = 0.0;      // the second's best with the first held there
};

// Both strengths by weighted least squares on an additive emulator: the second's response on top of the
// first at `first_fitted` and member `fitted_member` (its emulator `second_on_top`, anchored at that model's
// runs), moved by the first's own response between there and another strength and member (`first_members`,
// the first's emulators alone on the calibrated model, one per shape of its second parameter at one refit
// setting):
//   ŷ_k(m, u_a, u_b) = second_on_top_k(u_b) + first_m,k(u_a) - first_m*,k(u_a*),  u = log10(strength),
// with the second's SE (the model it was run on) in every cell's variance, as fit_strength. Exact at
// (m*, u_a*), where it is the second round's own emulator; elsewhere it assumes the two effects' shifts add
// (no interaction), so the pair is run at the optimum before anything is concluded from it. The first's
// shape is profiled as in the first round (absorption's rate: a first fitted alone at a rate that mimics
// part of the second may need another rate once the second is in). The grid covers each emulator's range
// [u_lo, u_hi] (the first's from its baseline anchor: the first nearly absent is a candidate too), then a
// finer grid around its minimum. `idx`: the cells fitted (all when empty).
PairFit fit_pair(const std::vector<Cell>& cells, const std::vector<Emulator>& first_members,
                 size_t fitted_member, double first_fitted, const Emulator& second_on_top,
                 const std::vector<size_t>& idx = {});

// The pair's held-out χ²: leave-one-condition-out with *both* strengths re-fitted in every fold (fit_pair on
// the other conditions), the left-out cells predicted at the fold's pair. The second round's own score holds
// the first at its fit on every condition, the left-out one included; for a round whose first strength
// comes from the joint fit this is the held-out score of the two-parameter model it is. Throws
// std::invalid_argument with fewer than two conditions.
double loco_pair(const std::vector<Cell>& cells, const std::vector<Emulator>& first_members,
                 size_t fitted_member, double first_fitted, const Emulator& second_on_top);

}  // namespace wetdem::diagnose
