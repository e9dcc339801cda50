// Step 1 of the diagnosis (diagnosis.md §4): the calibrated model at every observed condition, R seeds.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// Runs what is wanted (the baseline, and the screen's probes wanted before it), then fills the baseline
// predictions ŷ ± SE (SE = sd/√R; with one run, its window SE), seed 1 of the baseline (the common random
// numbers of the probes) and the run-to-run spread of one run per cell, max(SE √R, the window SE of seed 1).
// Throws std::runtime_error naming the run when the calibrated model itself fails at some condition: nothing
// can be diagnosed against a model that does not run.
void run_baseline(Procedure& p);

// How far one run's own window error understates the spread between seeds, per observable, from the
// baseline's replicates (one prediction per seed and cell): f² = Σ s²_between / Σ mean(own SE²) over the
// cells of that observable, where s²_between is the sample variance of the seeds' values (n - 1 degrees of
// freedom each). If the window errors were right, both sums would estimate the same variance (a run's value
// scatters by its own SE); an intermittently avalanching wet bed decorrelates slower than the window's
// autocorrelation shows, and its surface clumps scatter between seeds by twice their window SE. Floored at 1
// (few degrees of freedom: never shrink an error); 1 for an observable with no cell that two seeds report.
std::map<std::string, double> within_inflation(const std::vector<Cell>& cells,
                                               const std::vector<std::vector<Prediction>>& per_seed);

}  // namespace wetdem::diagnose
