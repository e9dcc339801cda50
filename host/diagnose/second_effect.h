// Step 6b of the diagnosis (diagnosis.md §4, "A second effect"): when the chosen effect explains the gap only
// in part, the cells it leaves may have a second cause. Forward stepwise, as in regression: the model with
// the first effect at its fitted strength becomes the null, the other candidates are screened against what it
// leaves, the best are fitted on top of it (every probe strength, seed 1 against that model's seed 1), and
// the verdict rule of step 5 decides whether one of them explains the rest. The pair is then run with fresh
// seeds; the second is named only when those runs beat the first effect's own fresh runs by the seed luck
// (confirm_second), and `effect` (both named) only when they also leave no cell significant.
// Stepwise holds the first at its own fit, which took the second's share of any cells the two move, and the
// second's held-out score holds it there in every fold. So the best second candidate is also fitted jointly
// with the first (pair_fit.h); one that fails the rule stepwise is taken on when the pair's held-out χ², both
// strengths re-fitted in every fold, passes it, and its fresh runs are then at the joint optimum (settled
// and confirmed as above).
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
std::string second_outcome(const Verdict& second, const std::vector<CellGap>& pair_after,
                           const VerdictRule& rule = {});

// "closes" and "part" become "unconfirmed" unless the pair's fresh runs (seeds R+1..2R) give a χ² over the
// cells at least max(min_drop, luck) below that of the first effect alone on the same fresh seeds (its own
// confirmation runs): fresh_confirms (verdict.h), the rule the first effect met against the model without it.
// A second effect is fitted to what the first leaves on seeds 1..R, so it can follow those seeds' luck as a
// first effect can; naming it on less would credit it with what two seed sets of the same model differ by.
// Without fresh runs of the pair (they failed) the outcome stays as it was ("part": not shown to close).
// "unconfirmed": `partial` as it was, the second not named; the report says which and by how much.
std::string confirm_second(const std::string& outcome, double chi2_first_fresh, double chi2_pair_fresh,
                           const VerdictRule& rule, double luck);

// Fills Procedure::second and settles the verdict (the outcomes above). Does nothing unless the verdict is
// `partial` with fresh runs and the diagnosis file allows it (`second_effect`, default true).
void run_second_effect(Procedure& p);

}  // namespace wetdem::diagnose
