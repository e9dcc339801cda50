// Step 6 of the diagnosis (diagnosis.md §4, "Shrink"): the chosen effect at its fitted strength (and refit
// setting and shape), run again with fresh seeds at every condition, and any tied candidate likewise. What is
// left significant after it is the remaining gap; an effect that leaves cells significant explains the gap
// only in part (verdict `partial`, verdict.h).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// Fills Procedure::fresh (the chosen effect first, then the tied ones) and settles the verdict. When cells
// stay significant, up to `confirm` rounds re-fit with the fresh runs as a knot and run the new strength
// fresh; a re-fit whose fresh runs are worse than the strength it left by more than the seed luck is undone
// (Procedure::confirmations lists what each round started from).
void run_shrink(Procedure& p);

// The strength a fitted candidate is run at: 3 significant digits.
double rounded_strength(double s);

// The mean of |chi2(A) - chi2(B)| over every split of `seeds` into two halves A, B of equal size, each split
// counted once (the half holding seeds[0] is A): 3 splits of 4 seeds, 10 of 6, 35 of 8. The model's seed
// luck (Verdict::seed_luck) is this over its 2R runs per condition, seeds 1..R and the control's R+1..2R:
// one split (1..R against R+1..2R) is one draw of a heavy-tailed quantity, and on the flowing matrix an
// unlucky one (docs/validation.md, "Is the inserted powder the seed luck?"). Throws on an odd count.
double split_luck(const std::vector<uint64_t>& seeds,
                  const std::function<double(const std::vector<uint64_t>&)>& chi2_of_set);

}  // namespace wetdem::diagnose
