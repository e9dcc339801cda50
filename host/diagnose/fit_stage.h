// Step 4 of the diagnosis (diagnosis.md §4), the runs: the top candidates of the screen at every probe
// strength (seed 1), at every refit setting; for an effect with a second parameter, at its other shapes; then
// rounds that refine the fit (a run at the fitted strength), extend the probed range past an edge the fit
// runs into (within the physical range), and extend the shapes past an end. The statistics are fit.h.
#pragma once

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// Fills Procedure::fitted (and the baselines of the refit settings). Runs that fail or cost more than
// max_cost cut the candidate's range there (noted, never an abort).
void run_fit(Procedure& p);

}  // namespace wetdem::diagnose
