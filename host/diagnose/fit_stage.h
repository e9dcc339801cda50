// Step 4 of the diagnosis (diagnosis.md §4), the runs: the top candidates of the screen at every probe
// strength (seed 1), at every refit setting; for an effect with a second parameter, at its other shapes; then
// rounds that refine the fit (a run at the fitted strength), extend the probed range past an edge the fit
// runs into (within the physical range), extend the shapes past an end, and extend another shape whose own
// fit runs into an edge of its knots (each shape compared at its own best strength). The statistics are
// fit.h.
#pragma once

#include "diagnose/procedure.h"
#include "diagnose/verdict.h"

namespace wetdem::diagnose {

// Fills Procedure::fitted (and the baselines of the refit settings). Runs that fail or cost more than
// max_cost cut the candidate's range there (noted, never an abort).
void run_fit(Procedure& p);

// The notes that say a fit runs into an end of the physical range (or the cut range), from c.at_limit;
// replaces any such notes already there.
void set_limit_notes(CandidateRuns& c);
// c.at_limit and its notes for the fit the verdict now reports (after the confirmation stage re-fitted with
// the fresh runs as a knot, the fit may have moved inside the range; shrink.cpp).
void settle_limit(CandidateRuns& c, const Candidate& fitted);

}  // namespace wetdem::diagnose
