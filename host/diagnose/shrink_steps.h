// The steps of the shrink stage (shrink.h) that its two files share: shrink.cpp runs the fresh checks, the
// confirmation rounds and the verdict on the fresh runs; fresh_ties.cpp decides the candidates whose probes
// and fresh runs disagree (unseen ties, an unseen lead, a tie confirmed where the chosen one is not).
// Internal to the diagnose library: nothing outside those two files includes it.
#pragma once

#include <string>
#include <vector>

#include "diagnose/procedure.h"

namespace wetdem::diagnose::shrink_steps {

// The fit runs of `effect` (nullptr when it was not fitted) and its place in the ranking (nullptr when it is
// not ranked).
CandidateRuns* runs_of(Procedure& p, const std::string& effect);
const Candidate* ranked(const Procedure& p, const std::string& effect);
bool listed(const std::vector<std::string>& list, const std::string& e);

// The fresh check of a ranked candidate at its fitted strength, refit setting and shape: want_fresh asks for
// its runs (seeds R+1..2R), collect_fresh reads them once p.run() has made them.
FreshCheck want_fresh(Procedure& p, const Candidate& c);
void collect_fresh(Procedure& p, FreshCheck& f);
// The control, the model without an effect on the same fresh seeds (Procedure::null_fresh), asked for.
void want_control(Procedure& p, size_t refit);
// χ² of a fresh check over the cells; NaN when its runs failed or are missing.
double fresh_chi2(const FreshCheck& f);
// The model's own seed luck (Verdict::seed_luck, split_luck over seeds 1..R and the control's fresh seeds).
double seed_luck(const Procedure& p);
// The verdict decided again on the candidates the table can see (decide_seen).
Verdict redecide(Procedure& p);

// fresh_ties.cpp: the unseen candidates tied held out, judged on their fresh runs (seen after all, dropped,
// named first or kept tied).
void judge_unseen_on_fresh(Procedure& p);
// fresh_ties.cpp: an unexplained verdict whose only passing candidate is unseen: named when its fresh runs
// show it and confirm the fit.
void try_unseen_lead(Procedure& p);
// fresh_ties.cpp: the chosen effect's fresh runs do not confirm it against the control (χ² `before`): a tie
// or near tie whose own fresh runs do is named first instead.
void promote_confirmed(Procedure& p, double before);
// fresh_ties.cpp: a tie of two seen candidates whose held-out score and fresh runs lean opposite ways: named
// in the order the two, each in its own noise, favour together.
void order_tie_by_evidence(Procedure& p, double before);

}  // namespace wetdem::diagnose::shrink_steps
