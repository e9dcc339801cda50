// Step 3 of the diagnosis (diagnosis.md §4), the statistic: how far a candidate's response points the way the
// gap does. The stage that runs the probes is in stages.h.
#pragma once

#include <vector>

#include "diagnose/cells.h"

namespace wetdem::diagnose {

// Projection of the z-vector of the baseline on the candidate's response pattern
// r_k = (ŷ_probe,k - ŷ_base,k) / sqrt(σ_k² + SE_k²), normalised: Σ z_k r_k / |r|. Positive when the effect
// moves the model towards the observations; 0 when it changes nothing.
double screen_score(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
                    const std::vector<Prediction>& probe);

}  // namespace wetdem::diagnose

namespace wetdem::diagnose {

class Procedure;

// The screen stage: each candidate at one probe strength (the middle of its probes, at its default shape),
// seed 1 (common random numbers with baseline seed 1). want_screen asks for those runs before the baseline
// runs, so both run together. run_screen scores them; a probe that failed or would cost more than max_cost
// is replaced by the next weaker probe (and noted), so a probe never aborts the diagnosis; a candidate none
// of whose probes can run scores 0 and is noted. Fills Procedure::screened, best first.
void want_screen(Procedure& p);
void run_screen(Procedure& p);

}  // namespace wetdem::diagnose
