// Step 1 of the diagnosis (diagnosis.md §4): the calibrated model at every observed condition, R seeds.
#pragma once

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// Runs what is wanted (the baseline, and the screen's probes wanted before it), then fills the baseline
// predictions ŷ ± SE (SE = sd/√R; with one run, its window SE), seed 1 of the baseline (the common random
// numbers of the probes) and the run-to-run spread of one run per cell, max(SE √R, the window SE of seed 1).
// Throws std::runtime_error naming the run when the calibrated model itself fails at some condition: nothing
// can be diagnosed against a model that does not run.
void run_baseline(Procedure& p);

}  // namespace wetdem::diagnose
