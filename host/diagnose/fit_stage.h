// Step 4 of the diagnosis (diagnosis.md §4), the runs: the top candidates of the screen at every probe
// strength (seed 1), at every refit setting; for an effect with a second parameter, at its other shapes; then
// rounds that refine the fit (a run at the fitted strength), extend the probed range past an edge the fit
// runs into (within the physical range), extend the shapes past an end, and extend another shape whose own
// fit runs into an edge of its knots (each shape compared at its own best strength), add shapes between the
// listed ones, and bracket a best shape probed at one strength only (a knot each side: its interval is then
// bounded by runs, not a point at the edge). The statistics are fit.h.
#pragma once

#include "diagnose/procedure.h"
#include "diagnose/verdict.h"

namespace wetdem::diagnose {

// Fills Procedure::fitted (and the baselines of the refit settings) with the first `top` candidates of the
// screen that could run a probe (default: screen_top). Runs that fail or cost more than max_cost cut the
// candidate's range there (noted, never an abort). Called again with a larger `top`, it keeps every run of
// the first call (the book) and fits the new candidates beside the old ones.
void run_fit(Procedure& p);
void run_fit(Procedure& p, size_t top);

// The widened fit (stage 4, diagnosis.md): when no candidate the screen passed on explains the gap (verdict
// `unexplained`), the next candidates with a positive screen score are fitted as well, up to screen_top more.
// The screen ranks by one probe's direction, and a probe that moves the table by ~1-2 σ (cohesion at its
// middle probe on the flowing drum) has a direction mostly of its own seed noise: on a twin withholding
// cohesion and absorption, cohesion scored 0.82, fourth, beside a dry-bed gap only it can make
// (docs/validation.md). Returns how many of `screened` to fit in all (the `top` of run_fit), or 0 when no
// candidate is left to add. `fitted`: the effects fitted so far (the first of the screen's order).
size_t widened_top(const std::vector<Screened>& screened, const std::vector<std::string>& fitted,
                   size_t screen_top);
// The candidates the widened fit adds, best first (widened_top's count of them).
std::vector<Screened> widened_candidates(const std::vector<Screened>& screened,
                                         const std::vector<std::string>& fitted, size_t screen_top);

// The notes that say a fit runs into an end of the physical range (or the cut range), from c.at_limit;
// replaces any such notes already there.
void set_limit_notes(CandidateRuns& c);
// c.at_limit and its notes for the fit the verdict now reports (after the confirmation stage re-fitted with
// the fresh runs as a knot, the fit may have moved inside the range; shrink.cpp).
void settle_limit(CandidateRuns& c, const Candidate& fitted);

}  // namespace wetdem::diagnose
