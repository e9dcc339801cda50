// Step 6b of the diagnosis (diagnosis.md §4, "A second effect"): when the chosen effect explains the gap only
// in part, the cells it leaves may have a second cause. Forward stepwise, as in regression: the model with
// the first effect at its fitted strength becomes the null, the other candidates are screened against what it
// leaves, the best are fitted on top of it (every probe strength, seed 1 against that model's seed 1), and
// the verdict rule of step 5 decides whether one of them explains the rest. The pair is then run with fresh
// seeds; `effect` (both named) only when those runs leave no cell significant.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

// The settled outcome of the second round from what it found (pure, unit-tested):
//  "closes"  the second candidate passes the rule against the first effect alone and the pair's fresh runs
//            leave no cell significant: the verdict becomes `effect`, naming both;
//  "part"    it passes, but cells stay significant with the pair: `partial`, naming both;
//  "noise"   the first effect's own seeds 1..R leave no cell significant (only its fresh seeds did): nothing
//            left for a second effect to explain, `partial` as it was;
//  "none"    no candidate passes the rule: `partial` as it was.
std::string second_outcome(const Verdict& second, const std::vector<CellGap>& pair_after);

// Fills Procedure::second and settles the verdict (the outcomes above). Does nothing unless the verdict is
// `partial` with fresh runs and the diagnosis file allows it (`second_effect`, default true).
void run_second_effect(Procedure& p);

}  // namespace wetdem::diagnose
