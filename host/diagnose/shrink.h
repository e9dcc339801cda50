// Step 6 of the diagnosis (diagnosis.md §4, "Shrink"): the chosen effect at its fitted strength (and refit
// setting and shape), run again with fresh seeds at every condition, and any tied candidate likewise. What is
// left significant after it is the remaining gap; an effect that leaves cells significant explains the gap
// only in part (verdict `partial`, verdict.h).
#pragma once

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// Fills Procedure::fresh (the chosen effect first, then the tied ones) and settles the verdict.
void run_shrink(Procedure& p);

// The strength a fitted candidate is run at: 3 significant digits.
double rounded_strength(double s);

}  // namespace wetdem::diagnose
