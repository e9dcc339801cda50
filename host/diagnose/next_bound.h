// Step 7b of the diagnosis (diagnosis.md §4): when the chosen effect's strength interval is open on one side
// (the table cannot tell the fitted strength from every stronger one, or every weaker one, within the probed
// range), the measurement that would close it. The effect at the interval's closed end and at its open end
// (the end of the probed range) are the two models; the stage compares them at the table's conditions through
// the fit's emulator (no new run) and runs both at conditions beyond the table, as the tie's experiment does
// (next_experiment.h, measure_beyond). The condition and observable where they differ most relative to the
// noise is what would bound the strength. A pore capacity fitted at a slow rate is bounded from below only:
// within the run the film never fills the pores, and a run four times as long may (docs/validation.md).
#pragma once

#include <optional>

#include "diagnose/fit.h"
#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// The two ends of an interval the table leaves open: `closed`, the end the data fix, and `open`, where the
// interval runs into the probed range (its strongest strength when open above, the baseline's anchor when
// open below; both open: the weakest and the strongest). nullopt when the interval is closed, or when its
// ends lie within a factor kMinOpenRatio (no measurement is worth making to tell them apart). Pure (tests).
inline constexpr double kMinOpenRatio = 1.25;
struct OpenInterval {
  double closed = 0.0, open = 0.0;
  bool above = true;  // open above (strength >= closed); false: open below (strength <= closed)
  bool both = false;  // open at both ends: the strength is not determined
};
std::optional<OpenInterval> open_interval(const StrengthFit& f);

// Fills Procedure::bound (nothing when the verdict names no effect, its interval is closed, or
// next_conditions = 0).
void run_bound_experiment(Procedure& p);

// When no single measurement bounds the interval (the best is under kDecisive), the one that does when
// repeated the fewest times (Proposal::repeats; the better ranked of equals) among those whose models ran on
// all the baseline's seeds (BoundExperiment::seeds; the table's own, emulated, always count; `unconfirmed`:
// any), else nullptr. Pure (tests).
const Proposal* repeated_bound(const BoundExperiment& b, bool unconfirmed = false);

}  // namespace wetdem::diagnose
