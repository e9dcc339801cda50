// The fresh-seed runs as the verdict's last word (docs/diagnosis.md, "Verdicts"): a tie confirmed where the
// first is not, an unseen candidate tied but neither dropped nor named first on its held-out score, one its
// fresh runs show ranked as a seen one, and the seed luck that sets every fresh comparison's margin.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "diagnose/shrink.h"
#include "diagnose/verdict.h"

using namespace wetdem::diagnose;

namespace {

// A fitted candidate with its held-out χ² spread evenly over the flowing table's 48 cells.
Candidate cand(const std::string& e, double loco) {
  Candidate c;
  c.effect = e;
  c.loco = loco;
  c.loco_cells.assign(48, loco / 48);
  return c;
}

}  // namespace

// The chosen effect's fresh runs do not confirm it; a candidate the held-out score did not separate from it,
// whose fresh runs do, is named instead (absorption-strong's numbers: control 71.5, luck 8.3, scale 70.2,
// absorption 47.4). Not an unseen one, not one whose drop is within the luck, not a failed one; of several,
// the least χ².
TEST(DiagnoseFresh, ATieWhoseFreshRunsConfirmItIsNamedWhenTheFirstsDoNot) {
  const VerdictRule rule;
  const double control = 71.5, luck = 8.3;
  EXPECT_FALSE(fresh_confirms(control, 70.2, rule, luck));
  EXPECT_EQ(confirmed_instead(control, {70.2, 47.4}, {false, true}, rule, luck), 1u);
  EXPECT_EQ(confirmed_instead(control, {70.2, 47.4}, {false, false}, rule, luck), kNone) << "unseen";
  EXPECT_EQ(confirmed_instead(control, {70.2, 65.0}, {false, true}, rule, luck), kNone)
      << "lower by 6.5: within the seed luck";
  EXPECT_EQ(confirmed_instead(control, {70.2, 65.0}, {false, true}, rule, 0.0), 1u) << "beyond min_drop";
  EXPECT_EQ(
      confirmed_instead(control, {70.2, std::nan(""), 50.0, 40.0}, {false, true, true, true}, rule, luck),
      3u);
  EXPECT_EQ(confirmed_instead(control, {30.0, 47.4}, {true, true}, rule, luck), 1u)
      << "index 0 is the chosen one: never its own replacement";
  EXPECT_THROW(confirmed_instead(control, {70.2}, {false, true}, rule, luck), std::invalid_argument);
}

// A confirmation round's re-fit is dropped for the strength it left only when its fresh runs are worse by
// more than the margin (the seed luck): viscous-strong with 120 rpm rows, R = 4, P = 2 (0.1 gave 99.3, the
// re-fit to 0.03 115.2, luck 23.4) keeps the re-fit; null-2 (cohesion 0.001 gave 72.4, the re-fit's 0.003
// 117.3, luck 56.9) keeps it too, where the better of the two draws would have made a null `partial`. The
// least of several rounds; a round that failed (NaN) never wins, and any round that ran beats a failed
// re-fit.
TEST(DiagnoseFresh, AReFitIsDroppedOnlyWhenItsFreshRunsAreWorseByMoreThanTheLuck) {
  EXPECT_EQ(best_fresh_round({99.3}, 115.2, 23.4), kNone) << "within the luck";
  EXPECT_EQ(best_fresh_round({72.4}, 117.3, 56.9), kNone) << "null-2: within the luck";
  EXPECT_EQ(best_fresh_round({99.3}, 115.2, 4.0), 0u) << "beyond the margin";
  EXPECT_EQ(best_fresh_round({115.2}, 99.3, 0.0), kNone) << "the re-fit is better";
  EXPECT_EQ(best_fresh_round({99.3}, 99.3, 0.0), kNone) << "a tie keeps the re-fit";
  EXPECT_EQ(best_fresh_round({120.0, 80.0, 90.0}, 105.0, 20.0), 1u);
  EXPECT_EQ(best_fresh_round({120.0, 101.0}, std::nan(""), 50.0), 1u) << "the re-fit's runs failed";
  EXPECT_EQ(best_fresh_round({std::nan("")}, 140.0, 0.0), kNone) << "a round that failed never wins";
  EXPECT_EQ(best_fresh_round({}, 140.0, 0.0), kNone) << "no round ran";
}

// Within the margin the point goes to the strength whose fresh runs match better when the verdict reads the
// same on it. cohesion 0.012 J/m² (fresh twins, 7 Dec 2026): 0.0123 gave 86.4, the re-fit's 0.0204 105.4,
// both confirming with cells left: 0.0123 is kept. null-2: cohesion 0.00105 gave 78.3 and would confirm, the
// re-fit's 109.7 does not: the re-fit's runs decide. A better round that would clear the last cells, a worse
// one, a failed one, or a failed re-fit (best_fresh_round's case) are not picked; of two eligible the least.
TEST(DiagnoseFresh, WithinTheLuckThePointGoesToTheBetterMatchIfTheVerdictReadsTheSame) {
  const FreshOutcome refit_partial{105.4, true, true};
  EXPECT_EQ(closer_fresh_round({{86.4, true, true}}, refit_partial), 0u) << "cohesion 0.012";
  EXPECT_EQ(closer_fresh_round({{78.3, true, true}}, {109.7, false, true}), kNone) << "null-2";
  EXPECT_EQ(closer_fresh_round({{80.0, true, false}}, refit_partial), kNone) << "it alone leaves no cell";
  EXPECT_EQ(closer_fresh_round({{120.1, true, true}}, refit_partial), kNone) << "the re-fit matches better";
  EXPECT_EQ(closer_fresh_round({{105.4, true, true}}, refit_partial), kNone) << "a tie keeps the re-fit";
  EXPECT_EQ(closer_fresh_round({{std::nan(""), false, false}}, refit_partial), kNone) << "a failed round";
  EXPECT_EQ(closer_fresh_round({{86.4, true, true}}, {std::nan(""), false, false}), kNone) << "failed re-fit";
  EXPECT_EQ(closer_fresh_round({{99.0, true, true}, {70.0, true, false}, {90.0, true, true}}, refit_partial),
            2u);
  EXPECT_EQ(closer_fresh_round({}, refit_partial), kNone) << "no round ran";
}

// The strengths the fresh runs cannot tell from the kept one stay in its interval: viscous-strong with 120
// rpm rows, R = 4, P = 2 kept 0.03 [0.017, 0.054] (χ² 115.2); 0.1 gave 99.3, luck 23.4, so the interval
// reaches the truth. A strength worse by more than the margin, one already inside, and a failed one change
// nothing.
TEST(DiagnoseFresh, StrengthsTheFreshRunsCannotTellApartStayInTheInterval) {
  double lo = 0.017, hi = 0.054;
  EXPECT_EQ(widen_to_fresh_ties(lo, hi, 115.2, {{0.1, 99.3}}, 23.4), std::vector<double>{0.1});
  EXPECT_DOUBLE_EQ(lo, 0.017);
  EXPECT_DOUBLE_EQ(hi, 0.1);
  lo = 0.002, hi = 0.004;
  EXPECT_TRUE(widen_to_fresh_ties(lo, hi, 72.4, {{0.001, 117.3}}, 40.0).empty())
      << "worse by more than the luck";
  EXPECT_DOUBLE_EQ(lo, 0.002);
  EXPECT_EQ(widen_to_fresh_ties(lo, hi, 72.4, {{0.001, 117.3}}, 56.9), std::vector<double>{0.001});
  EXPECT_DOUBLE_EQ(lo, 0.001);
  EXPECT_DOUBLE_EQ(hi, 0.004);
  EXPECT_TRUE(widen_to_fresh_ties(lo, hi, 72.4, {{0.003, 70.0}, {0.01, std::nan("")}}, 10.0).empty())
      << "inside already; failed";
  EXPECT_TRUE(widen_to_fresh_ties(lo, hi, std::nan(""), {{0.01, 70.0}}, 10.0).empty())
      << "the kept one failed";
  EXPECT_DOUBLE_EQ(hi, 0.004);
}

// Only what the table can see is named first, and an unseen candidate that scores best is tied, never dropped
// (name_only_seen): the flowing evaporation-strong twin (truth evaporation 0.8) scored evaporation 13.4 held
// out and absorption 17.1, null 90.0 over a floor of 68.8; evaporation's probes moved no cell past 2.2 σ.
TEST(DiagnoseFresh, AnUnseenCandidateIsTiedNeitherDroppedNorNamedFirst) {
  Verdict base;
  base.kind = "effect";
  base.null_loco = 90.0;
  base.floor = 68.8;
  base.ranking = {cand("evaporation", 13.4), cand("absorption", 17.1), cand("spread", 40.0),
                  cand("hysteresis", 85.0)};
  base.effect = "evaporation";
  base.tied = {"absorption"};
  const VerdictRule rule;
  Verdict v = base;
  const std::vector<std::string> notes = name_only_seen(v, {"evaporation"}, {}, rule);
  EXPECT_EQ(v.kind, "effect");
  EXPECT_EQ(v.effect, "absorption");
  EXPECT_EQ(v.ranking.front().effect, "absorption") << "the chosen one heads the ranking (shrink reads it)";
  EXPECT_EQ(v.ranking[1].effect, "evaporation");
  ASSERT_EQ(v.tied, std::vector<std::string>{"evaporation"}) << "better held out: tied, not dropped";
  EXPECT_NEAR(v.held_out_shrink, 1.0 - 17.1 / 90.0, 1e-12);
  EXPECT_NEAR(v.held_out_gap_shrink, (90.0 - 17.1) / (90.0 - 68.8), 1e-12);
  EXPECT_EQ(notes.size(), 2u) << "one for the order, one for the tie";
  // spread (40.0) passes the margin but is clearly worse than absorption: not tied.
  // Seen candidates only: the verdict is decide()'s own.
  Verdict w = base;
  EXPECT_TRUE(name_only_seen(w, {}, {}, rule).empty());
  EXPECT_EQ(w.effect, "evaporation");
  EXPECT_EQ(w.tied, std::vector<std::string>{"absorption"});
  // Fresh runs have dropped evaporation: absorption alone.
  Verdict x = base;
  name_only_seen(x, {"evaporation"}, {"evaporation"}, rule);
  EXPECT_EQ(x.effect, "absorption");
  EXPECT_TRUE(x.tied.empty());
  // decide()'s verdict over another ranking: the first chosen, none tied.
  const auto ranked = [&](std::vector<Candidate> r) {
    Verdict out = base;
    out.effect = r.front().effect;
    out.ranking = std::move(r);
    out.tied.clear();
    return out;
  };
  // An unseen candidate clearly worse than the chosen one is not tied.
  Verdict y = ranked({cand("absorption", 13.4), cand("evaporation", 30.0)});
  name_only_seen(y, {"evaporation"}, {}, rule);
  EXPECT_EQ(y.effect, "absorption");
  EXPECT_TRUE(y.tied.empty());
  // Only unseen candidates pass the margin (hysteresis at 1.8 σ on the null-2 twin): unexplained, not named.
  Verdict z = ranked({cand("hysteresis", 13.4), cand("cohesion", 85.0)});
  const std::vector<std::string> zn = name_only_seen(z, {"hysteresis"}, {}, rule);
  EXPECT_EQ(z.kind, "unexplained");
  EXPECT_TRUE(z.effect.empty());
  EXPECT_EQ(zn.size(), 1u);
  // Other kinds are left alone.
  Verdict u = base;
  u.kind = "no_gap";
  EXPECT_TRUE(name_only_seen(u, {"evaporation"}, {}, rule).empty());
  EXPECT_EQ(u.effect, "evaporation");
  // The fresh runs decide an unseen tie: the tie margin over 48 cells is 4 x max(1, χ²/48).
  EXPECT_EQ(unseen_on_fresh(28.5, 40.0, 48, rule), FreshJudgement::kDrop);
  EXPECT_EQ(unseen_on_fresh(28.5, 30.0, 48, rule), FreshJudgement::kKeep);
  EXPECT_EQ(unseen_on_fresh(28.5, 26.0, 48, rule), FreshJudgement::kKeep);
  EXPECT_EQ(unseen_on_fresh(28.5, 20.0, 48, rule), FreshJudgement::kSwap);
  // ... or by the model's own seed luck where that is larger: on null-2 (PSD tails, no effect) the model gave
  // χ² 59.9 on its seeds and 129.7 on the fresh ones, and hysteresis, which no probe shows, 70.7 on the fresh
  // seeds against cohesion's 117.3. That is not evidence for hysteresis: it stays tied, not first.
  const double luck = std::fabs(129.7 - 59.9);
  EXPECT_EQ(unseen_on_fresh(117.3, 70.7, 48, rule), FreshJudgement::kSwap) << "the tie rule alone";
  EXPECT_EQ(unseen_on_fresh(117.3, 70.7, 48, rule, luck), FreshJudgement::kKeep);
  EXPECT_EQ(unseen_on_fresh(117.3, 90.1, 48, rule, luck), FreshJudgement::kKeep);
  EXPECT_EQ(unseen_on_fresh(30.5, 79.3, 48, rule, 14.9), FreshJudgement::kDrop) << "absorption-weak's spread";
}

// An unseen candidate that its own fresh runs show (power.h, fresh_shift) is ranked as a seen one: by its
// held-out score, with the fresh runs as the check (seen_on_fresh); the candidates tied with the former first
// stay tied unless clearly worse both held out and on fresh runs (stays_tied). Numbers of evaporation-strong
// at R = 4 (docs/validation.md): absorption named first at 28.4 held out (fresh 31.6), evaporation unseen at
// 14.8 (fresh 34.2, its fresh runs 4.7 σ from the control's), spread tied at 30.2 (fresh 57.2), luck 16.9.
TEST(DiagnoseFresh, ACandidateItsFreshRunsShowIsRankedAsASeenOne) {
  const VerdictRule rule;
  const double luck = 16.9;
  const Candidate abs = cand("absorption", 28.4), evap = cand("evaporation", 14.8),
                  spread = cand("spread", 30.2);
  // Better held out and not clearly worse on fresh runs: named first (an unseen one would only stay tied).
  EXPECT_EQ(seen_on_fresh(abs, evap, 31.6, 34.2, 48, rule, luck), FreshJudgement::kSwap);
  EXPECT_EQ(unseen_on_fresh(31.6, 34.2, 48, rule, luck), FreshJudgement::kKeep);
  // Worse held out and not clearly worse fresh: tied, second.
  EXPECT_EQ(seen_on_fresh(evap, abs, 34.2, 31.6, 48, rule, luck), FreshJudgement::kKeep);
  // Clearly worse on fresh runs (by more than the luck): dropped, whatever it scored held out.
  EXPECT_EQ(seen_on_fresh(abs, evap, 31.6, 50.0, 48, rule, luck), FreshJudgement::kDrop);
  // Clearly better on fresh runs: first, even when worse held out.
  EXPECT_EQ(seen_on_fresh(evap, abs, 60.0, 31.6, 48, rule, luck), FreshJudgement::kSwap);
  // With evaporation first, absorption is clearly worse held out (13.6 past a margin of 4) but ties on fresh
  // runs: tied. Spread is clearly worse on both (23.0 past the luck): no longer tied.
  EXPECT_TRUE(clearly_worse(evap, abs, rule));
  EXPECT_TRUE(stays_tied(evap, abs, 34.2, 31.6, 48, rule, luck));
  EXPECT_FALSE(stays_tied(evap, spread, 34.2, 57.2, 48, rule, luck));
  // Close held out keeps it whatever the fresh runs say.
  EXPECT_TRUE(stays_tied(abs, spread, 31.6, 57.2, 48, rule, luck));
}

// The seed luck is the mean |Δχ²| over every split of the model's 2R seeds into two halves, each split once
// (split_luck, shrink.h). With χ² of a set = the sum of its seeds, the splits of {1, 2, 3, 4} are {1,2|3,4},
// {1,3|2,4}, {1,4|2,3}: |3-7|, |4-6|, |5-5|, mean 2. On the flowing matrix the one split 1-2 against 3-4 was
// an unlucky draw (docs/validation.md).
TEST(DiagnoseFresh, SeedLuckIsTheMeanOverEverySplitOfTheSeeds) {
  const auto sum = [](const std::vector<uint64_t>& s) {
    double x = 0;
    for (uint64_t v : s) x += double(v);
    return x;
  };
  size_t calls = 0;
  EXPECT_DOUBLE_EQ(split_luck({1, 2, 3, 4},
                              [&](const std::vector<uint64_t>& s) {
                                ++calls;
                                EXPECT_EQ(s.size(), 2u);
                                return sum(s);
                              }),
                   2.0);
  EXPECT_EQ(calls, 6u) << "3 splits, two sets each";
  calls = 0;
  split_luck({1, 2, 3, 4, 5, 6}, [&](const std::vector<uint64_t>& s) { return ++calls, sum(s); });
  EXPECT_EQ(calls, 20u) << "C(6,3)/2 = 10 splits";
  EXPECT_DOUBLE_EQ(split_luck({7, 9}, sum), 2.0);
  EXPECT_THROW(split_luck({1, 2, 3}, sum), std::invalid_argument);
}

// A candidate whose tie the luck kept in the first round, and whose confirmation on top of the first effect
// the luck decided in the second, is one entry of held_by_luck, in the order first held.
TEST(DiagnoseFresh, HeldByLuckListsEachCandidateOnce) {
  Verdict v;
  hold_by_luck(v, "hysteresis");
  hold_by_luck(v, "scale");
  hold_by_luck(v, "hysteresis");
  EXPECT_EQ(v.held_by_luck, (std::vector<std::string>{"hysteresis", "scale"}));
}
