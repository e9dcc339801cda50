// The honest verdict (docs/diagnosis.md, "Verdict"), on synthetic cells with known answers: the tie rule and
// `partial`, the held-out tie's noise, the effect margin, a gap spread over the table, the log density and
// the limit note. The fit's intervals, edges and second parameter: test_diagnose_fit.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "diagnose/effects.h"
#include "diagnose/emulator.h"
#include "diagnose/fit.h"
#include "diagnose/fit_stage.h"
#include "diagnose/shrink.h"
#include "diagnose/twin.h"
#include "diagnose/verdict.h"

#include "support/synthetic_cells.h"

using namespace wetdem::diagnose;
using namespace wetdem::test;

// Two candidates that fit equally well are tied; a clearly worse one is not; the fresh-seed check turns an
// effect that leaves cells significant into `partial`.
TEST(DiagnoseVerdict, TieRuleAndPartial) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.3);
  const std::vector<Prediction> base(5, Prediction{30.0, 0.1});
  const Response a = linear("evaporation", {0.01, 0.1, 1.0}, kSlope, 30.0);
  const Response twin_of_a = linear("absorption", {0.01, 0.1, 1.0}, kSlope, 30.0);  // the same fingerprint
  const Response decoy = linear("cohesion", {0.01, 0.1, 1.0}, {3.0, 2.0, 1.0, 0.5, 0.0}, 30.0);
  const double u = 2.5;
  std::vector<double> y;
  for (double k : kSlope) y.push_back(30.0 + k * u + noise(rng));
  const std::vector<Cell> cells = cells_at(kPhi, y, 0.3);
  Verdict v = decide(cells, base, {a, twin_of_a, decoy}, {1.0, 1.0, 0.1});
  ASSERT_EQ(v.kind, "effect");
  ASSERT_EQ(v.tied.size(), 1u);
  EXPECT_TRUE(v.tied[0] == "evaporation" || v.tied[0] == "absorption");
  EXPECT_NE(v.tied[0], v.effect);
  EXPECT_TRUE(clearly_worse(v.ranking[0], v.ranking[2], VerdictRule{}));
  // The rule: a held-out chi2 worse by tie_delta x max(1, chi2_best / n) is clearly worse.
  Candidate best, other;
  best.loco_cells.assign(5, 0.4);
  best.loco = 2.0;
  other.loco = 5.9;
  EXPECT_FALSE(clearly_worse(best, other, VerdictRule{}));
  other.loco = 6.0;
  EXPECT_TRUE(clearly_worse(best, other, VerdictRule{}));
  best.loco = 20.0;  // the best leaves 4x the scatter its error bars allow: the margin grows with it
  other.loco = 30.0;
  EXPECT_FALSE(clearly_worse(best, other, VerdictRule{}));
  other.loco = 36.0;
  EXPECT_TRUE(clearly_worse(best, other, VerdictRule{}));
  const Verdict alone = decide(cells, base, {a, decoy}, {1.0, 0.1});
  EXPECT_TRUE(alone.tied.empty());
  std::vector<CellGap> after(5, CellGap{0.1, 0.3, 0.76, false});
  Verdict q = alone;
  settle_verdict(q, after, VerdictRule{});
  EXPECT_EQ(q.kind, "effect");
  after[2] = {3.0, 10.0, 0.0, true};
  Verdict p = alone;
  settle_verdict(p, after, VerdictRule{});
  EXPECT_EQ(p.kind, "partial");
  EXPECT_EQ(p.effect, alone.effect);
  // The fresh runs must reproduce an improvement (fresh_confirms): the flowing null-2 twin's hysteresis fit
  // at its probe edge passed the held-out rule, and its fresh runs gave χ² 91.1 against the model's 59.9.
  EXPECT_TRUE(fresh_confirms(116.1, 6.4, VerdictRule{}));
  EXPECT_FALSE(fresh_confirms(59.9, 91.1, VerdictRule{})) << "worse on fresh seeds";
  EXPECT_FALSE(fresh_confirms(59.9, 57.0, VerdictRule{})) << "within min_drop of the model: noise";
  EXPECT_TRUE(fresh_confirms(59.9, 59.9 - VerdictRule{}.min_drop, VerdictRule{}));
  // ... nor by less than the model's own seed luck: null-2's cohesion, 117.3 on fresh runs against the
  // control's 129.7 on the same seeds, while the model alone gave 59.9 on its own seeds.
  EXPECT_TRUE(fresh_confirms(129.7, 117.3, VerdictRule{}));
  EXPECT_FALSE(fresh_confirms(129.7, 117.3, VerdictRule{}, std::fabs(129.7 - 59.9)));
  EXPECT_TRUE(fresh_confirms(62.3, 30.5, VerdictRule{}, std::fabs(62.3 - 77.2))) << "absorption-weak";
  // A near tie held out is decided on fresh runs (near_tie, fresh_tie): on the flowing absorption-weak twin
  // evaporation scored 18.5 held out and the truth, absorption, 25.3: 6.8 apart over 48 cells, past the tie
  // margin of 4 but inside twice it.
  Candidate ev, ab;
  ev.loco = 18.5;
  ev.loco_cells.assign(48, 18.5 / 48);
  ab.loco = 25.3;
  EXPECT_TRUE(clearly_worse(ev, ab, VerdictRule{}));
  EXPECT_TRUE(near_tie(ev, ab, VerdictRule{}));
  ab.loco = 27.0;
  EXPECT_FALSE(near_tie(ev, ab, VerdictRule{})) << "8.5 apart: clearly worse even at twice the margin";
  EXPECT_TRUE(fresh_tie(30.7, 33.0, 48, VerdictRule{}));
  EXPECT_FALSE(fresh_tie(30.7, 35.0, 48, VerdictRule{}));
  EXPECT_FALSE(fresh_tie(96.0, 105.0, 48, VerdictRule{})) << "the margin widens with chi2/n: 4 x 2 = 8";
  EXPECT_TRUE(fresh_tie(96.0, 103.9, 48, VerdictRule{}));
  // ... and, like an unseen tie, never separated by less than the model's own seed luck (absorption-weak's
  // 14.9): 4.3 past the tie margin is a tie there.
  EXPECT_TRUE(fresh_tie(30.7, 35.0, 48, VerdictRule{}, 14.9));
  EXPECT_FALSE(fresh_tie(30.7, 45.7, 48, VerdictRule{}, 14.9));
  EXPECT_FALSE(fresh_tie(96.0, 105.0, 48, VerdictRule{}, 2.0)) << "a small luck leaves the tie margin";
  // What the luck alone decides (Verdict::held_by_luck): cohesion-weak's viscous, 151.5 on fresh runs against
  // cohesion's 100.3, is dropped by the tie margin and kept by the luck 70.6.
  EXPECT_EQ(unseen_on_fresh(100.3, 151.5, 48, VerdictRule{}), FreshJudgement::kDrop);
  EXPECT_EQ(unseen_on_fresh(100.3, 151.5, 48, VerdictRule{}, 70.6), FreshJudgement::kKeep);
  // A tie held out that its fresh runs leave clearly worse is not named (ties_clearly_worse_on_fresh): the
  // flowing absorption-0.03-at-30 twin at 4 seeds, absorption first at 99.4 on fresh runs, evaporation 99.3,
  // scale 220.6 (worse than the model alone, 211.7), luck 22.6; a tie whose fresh runs failed is kept.
  const double nan = std::nan("");
  EXPECT_EQ(ties_clearly_worse_on_fresh(99.4, {99.3, 220.6, nan}, 48, VerdictRule{}, 22.6),
            std::vector<size_t>{1});
  EXPECT_TRUE(ties_clearly_worse_on_fresh(99.4, {99.4 + 22.5}, 48, VerdictRule{}, 22.6).empty())
      << "within the model's own seed luck: still tied";
  EXPECT_EQ(ties_clearly_worse_on_fresh(30.7, {35.0}, 48, VerdictRule{}, 0.0), std::vector<size_t>{0})
      << "past the tie margin of 4 with no luck";
  EXPECT_TRUE(ties_clearly_worse_on_fresh(nan, {220.6}, 48, VerdictRule{}, 22.6).empty())
      << "the first's fresh runs failed: nothing to compare with";
}

// Two held-out scores built on noisy probes differ by the probes' noise alone (VerdictRule::tie_noise). Two
// candidates with the truth's own fingerprint, each probed with knots as noisy as twice the data's σ: twice
// tie_delta alone leaves one of them out of the fresh runs (not a near tie) in many draws; with the margin of
// tie_noise standard deviations of the difference over paired emulator redraws, rarely (~2 % expected: 1.5
// bootstrap standard deviations are ~2.3 of the difference's own). With precise probes the noise margin is
// small and a candidate with a wrong fingerprint is no near tie. The noise never ties on its own: the tie
// (clearly_worse) is tie_delta's, and fresh runs decide a near tie.
TEST(DiagnoseVerdict, TheHeldOutTieCountsTheProbesNoise) {
  const size_t n = 12;
  std::vector<double> phi, slope;
  for (size_t i = 0; i < n; ++i) phi.push_back(0.01 * double(i)), slope.push_back(3.0 * double(i + 1) / n);
  const double sigma = 0.3, u_true = 1.5;  // the truth at 10^-0.5 x the weakest probe's decade: mid-range
  std::mt19937_64 rng(20261129);
  std::normal_distribution<double> n01(0.0, 1.0);
  const auto noisy = [&](const std::string& name, double s) {
    Response r = linear(name, {0.01, 0.1, 1.0}, slope, 30.0, s);
    for (auto& p : r.pred)
      for (auto& x : p) x.mean += s * n01(rng);
    return r;
  };
  VerdictRule fixed;
  fixed.tie_noise = 0.0;
  int far_fixed = 0, far_noise = 0, trials = 60;
  double noise_sum = 0, d_sum = 0, d_ss = 0;
  for (int t = 0; t < trials; ++t) {
    std::vector<Prediction> base(n, Prediction{30.0, 0.1});
    for (auto& b : base) b.mean += 0.1 * n01(rng);
    std::vector<double> y;
    for (double k : slope) y.push_back(30.0 + k * u_true + sigma * n01(rng));
    const std::vector<Cell> cells = cells_at(phi, y, sigma);
    const Verdict v =
        decide(cells, base, {noisy("evaporation", 2 * sigma), noisy("absorption", 2 * sigma)}, {1.0, 1.0});
    ASSERT_EQ(v.kind, "effect");
    ASSERT_EQ(v.ranking.size(), 2u);
    ASSERT_EQ(v.ranking[0].loco_draws.size(), size_t(VerdictRule{}.tie_draws));
    ASSERT_EQ(v.ranking[1].loco_draws.size(), size_t(VerdictRule{}.tie_draws));
    far_fixed += !near_tie(v.ranking[0], v.ranking[1], fixed);
    far_noise += !near_tie(v.ranking[0], v.ranking[1], VerdictRule{});
    EXPECT_EQ(v.tied.empty(), clearly_worse(v.ranking[0], v.ranking[1], fixed)) << "the tie is tie_delta's";
    noise_sum += held_out_noise(v.ranking[0], v.ranking[1]);
    // The difference with fixed labels, for its spread over independent probe sets.
    const double d = v.ranking[0].effect == "evaporation" ? v.ranking[1].loco - v.ranking[0].loco
                                                          : v.ranking[0].loco - v.ranking[1].loco;
    d_sum += d, d_ss += d * d;
  }
  const double spread = std::sqrt(d_ss / trials - (d_sum / trials) * (d_sum / trials));
  const double noise = noise_sum / trials;
  std::printf(
      "equal candidates, probes at 2 sigma: not a near tie %d/%d by tie_delta, %d/%d with the noise; "
      "held-out difference's spread over probe sets %.2f, its bootstrap estimate %.2f\n",
      far_fixed, trials, far_noise, trials, spread, noise);
  EXPECT_GE(far_fixed, trials / 5) << "twice tie_delta alone leaves equal candidates out by luck";
  EXPECT_LE(far_noise, 4) << "the noise margin runs them fresh";
  // The bootstrap never understates the spread, and overstates it by less than 2x: its knots carry their
  // noise twice (the run's and the redraw's); tie_noise's default allows for it.
  EXPECT_GT(noise, spread);
  EXPECT_LT(noise, 2.0 * spread);
  // Precise probes: the noise is small, and a wrong fingerprint is no near tie.
  std::vector<double> y;
  for (double k : slope) y.push_back(30.0 + k * u_true + sigma * n01(rng));
  const std::vector<Cell> cells = cells_at(phi, y, sigma);
  std::vector<double> half;
  for (double k : slope) half.push_back(0.5 * k + 0.5 * slope.back() / 2);
  const std::vector<Prediction> base(n, Prediction{30.0, 0.01});
  const Verdict v = decide(cells, base,
                           {linear("evaporation", {0.01, 0.1, 1.0}, slope, 30.0, 0.01),
                            linear("absorption", {0.01, 0.1, 1.0}, half, 30.0, 0.01)},
                           {1.0, 1.0});
  ASSERT_EQ(v.ranking.size(), 2u);
  ASSERT_EQ(v.ranking[0].effect, "evaporation");
  ASSERT_FALSE(v.ranking[1].loco_draws.empty()) << "it passes the effect margin: its noise is measured";
  std::printf("wrong fingerprint: held-out %.1f against %.1f, noise %.2f\n", v.ranking[1].loco,
              v.ranking[0].loco, held_out_noise(v.ranking[0], v.ranking[1]));
  EXPECT_LT(held_out_noise(v.ranking[0], v.ranking[1]), 0.1 * (v.ranking[1].loco - v.ranking[0].loco));
  EXPECT_FALSE(near_tie(v.ranking[0], v.ranking[1], VerdictRule{}));
  EXPECT_DOUBLE_EQ(near_tie_margin(v.ranking[0], v.ranking[1], VerdictRule{}),
                   near_tie_margin(v.ranking[0], v.ranking[1], fixed));
  // The near-tie margin is the larger of twice the tie margin and the noise part; an absent draw leaves the
  // fixed rule.
  Candidate a, b;
  a.loco = 10.0, b.loco = 20.0;
  a.loco_cells.assign(48, 0.2);
  EXPECT_DOUBLE_EQ(held_out_noise(a, b), 0.0);
  EXPECT_FALSE(near_tie(a, b, VerdictRule{})) << "10 past twice the tie margin of 4";
  a.loco_draws = {10, 12, 14, 16};
  b.loco_draws = {20, 16, 24, 12};  // differences 10, 4, 10, -4: sd 6.6
  EXPECT_NEAR(held_out_noise(a, b), 6.6332, 1e-3);
  b.loco = 19.0;
  EXPECT_TRUE(clearly_worse(a, b, VerdictRule{})) << "the tie is tie_delta's: 9 > 4";
  EXPECT_TRUE(near_tie(a, b, VerdictRule{})) << "9 < 1.5 x 6.6: run fresh";
  b.loco = 20.5;
  EXPECT_FALSE(near_tie(a, b, VerdictRule{})) << "10.5 > 1.5 x 6.6";
}

// A twin's noise never leaves an observable's possible range and does not bias the mean (twin.h): f_wet near
// 0 % stays in [0, 1] with the truth's mean, a surface clump size of 1.3 +- 1 stays >= 1 with mean 1.3 (a
// Gaussian truncated at 1 would give ~2.0: every dry cell of a flowing twin showed clumps the model lacks),
// and a quantity on its bound is that bound. Far from the bounds the noise is plain Gaussian, negative values
// too.
TEST(DiagnoseVerdict, TwinNoiseStaysInsideThePossibleRangeWithoutBias) {
  std::mt19937_64 rng(5);
  const auto moments = [&](const std::string& obs, double mean, double sd, double lo, double hi) {
    double s = 0, s2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const double y = noisy_measurement(obs, mean, sd, rng);
      EXPECT_GE(y, lo);
      EXPECT_LE(y, hi);
      s += y;
      s2 += y * y;
    }
    return std::pair<double, double>{s / n, std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n)))};
  };
  {
    const auto [m, sd] = moments("f_wet_mean", 0.01, 0.02, 0.0, 1.0);  // two bounds: beta
    EXPECT_NEAR(m, 0.01, 0.0005) << "the truncated Gaussian's mean was ~0.02";
    EXPECT_GT(sd, 0.005);
  }
  {
    const auto [m, sd] = moments("surface_agglomerate_size", 1.3, 1.0, 1.0, 1e300);  // one bound: gamma
    EXPECT_NEAR(m, 1.3, 0.03);
    EXPECT_NEAR(sd, 1.0, 0.1);
  }
  {
    const auto [m, sd] = moments("aor_deg_std", 12.0, 1.0, 0.0, 1e300);  // far from 0: Gaussian
    EXPECT_NEAR(m, 12.0, 0.03);
    EXPECT_NEAR(sd, 1.0, 0.03);
  }
  EXPECT_EQ(noisy_measurement("f_wet_mean", 0.0, 0.02, rng), 0.0) << "a dry bed has no bridges to mismeasure";
  EXPECT_EQ(noisy_measurement("surface_agglomerate_size", 1.0, 0.5, rng), 1.0);
  EXPECT_EQ(noisy_measurement("f_wet_mean", -0.1, 0.02, rng), 0.0) << "a mean outside is put on its edge";
  // An unbounded observable is plain Gaussian: negative values occur.
  bool negative = false;
  for (int i = 0; i < 200; ++i)
    negative = negative || noisy_measurement("surface_velocity_mps", 0.0, 0.1, rng) < 0;
  EXPECT_TRUE(negative);
}

// The effect margin counts the gap, not the noise (verdict.h, noise_floor): in a table of 48 cells whose gap
// is a weak effect (one or two cells significant), halving the whole held-out χ² is out of reach even for the
// truth, since ~48 of it is noise; removing half of what lies above the noise floor is not. A decoy that
// moves other cells does not pass, and on noise alone no candidate does.
TEST(DiagnoseVerdict, TheMarginCountsTheGapNotTheNoise) {
  const std::vector<Prediction> base(48, Prediction{30.0, 0.1});
  std::vector<double> phi, slope(48, 0.0), decoy(48, 0.0);
  for (size_t k = 0; k < 48; ++k) phi.push_back(0.01 * double(k % 6));
  // One observable, growing with the content: z of 0.3-4 at the truth (χ² ~26 over the noise's ~48).
  const double z_truth[6] = {0.3, 0.6, 1.0, 1.5, 2.5, 4.0};
  for (size_t k = 0; k < 6; ++k) slope[6 + k] = z_truth[k] * std::sqrt(0.1) / 2.477;
  for (size_t k = 0; k < 48; k += 5) decoy[k] = 1.0;
  const Response r = linear("cohesion", {0.01, 0.1, 1.0}, slope, 30.0);
  const Response d = linear("viscous", {0.01, 0.1, 1.0}, decoy, 30.0);
  const double u = std::log10(0.3) - (std::log10(0.01) - 1.0);  // the truth: 0.3
  int truth_new = 0, truth_old = 0, runs = 0, decoy_new = 0, noise_new = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, std::sqrt(0.3 * 0.3 + 0.1 * 0.1));
    std::vector<double> y, y0;
    for (size_t k = 0; k < 48; ++k) {
      const double e = noise(rng);
      y.push_back(30.0 + slope[k] * u + e);
      y0.push_back(30.0 + e);
    }
    const std::vector<Cell> cells = cells_at(phi, y, 0.3);
    const Verdict v = decide(cells, base, {r, d}, {1.0, 0.5});
    if (v.kind == "no_gap") continue;
    ++runs;
    const Candidate* c = nullptr;
    const Candidate* dc = nullptr;
    for (const Candidate& x : v.ranking) (x.effect == "cohesion" ? c : dc) = &x;
    EXPECT_GT(v.floor, 25.0) << "seed " << seed << ": ~48 of noise";
    truth_new += passes_margin(c->loco, v, VerdictRule{});
    truth_old += c->loco <= 0.5 * v.null_loco && v.null_loco - c->loco >= 4.0;
    decoy_new += passes_margin(dc->loco, v, VerdictRule{});
    const Verdict v0 = decide(cells_at(phi, y0, 0.3), base, {r, d}, {1.0, 0.5});
    for (const Candidate& x : v0.ranking)
      noise_new += v0.kind != "no_gap" && passes_margin(x.loco, v0, VerdictRule{});
  }
  ASSERT_GE(runs, 15) << "the weak effect leaves a significant cell in most draws";
  EXPECT_GE(truth_new, 3 * runs / 4) << "the truth passes the margin on the gap (15 of 17 draws)";
  EXPECT_LE(truth_old, runs / 4) << "it would rarely pass a margin on the whole χ² (1 of 17)";
  EXPECT_EQ(decoy_new, 0);
  EXPECT_LE(noise_new, 1);
}

// A gap spread thinly over the table (where.h, table_fit): 48 cells, |z| 0.8-1.8 at the baseline, none
// significant alone (Benjamini-Hochberg), χ² 86.7 against χ²_48's 1 % point 73.7. The table test finds it,
// the candidate that makes it is chosen over a decoy, and the noise floor is capped at 1 a cell (48): at the
// quiet cells' own mean z² (here all of them) it would be the null's whole χ² and the margin would ask
// nothing. Fresh runs that leave it so are `partial`, though no cell is significant.
TEST(DiagnoseVerdict, AGapSpreadOverTheTableIsFoundByItsChiSquare) {
  const std::vector<Prediction> base(48, Prediction{30.0, 0.1});
  const double sd = std::sqrt(0.3 * 0.3 + 0.1 * 0.1);
  const double z_at[6] = {0.8, 1.0, 1.2, 1.4, 1.6, 1.8};
  std::vector<double> phi, slope, decoy(48, 0.0), y;
  const double u = std::log10(0.3) - (std::log10(0.01) - 1.0);  // the truth: 0.3, u above the anchor
  for (size_t k = 0; k < 48; ++k) {
    phi.push_back(0.01 * double(k % 6));
    slope.push_back(z_at[k % 6] * sd / u);
    y.push_back(30.0 + slope.back() * u);
  }
  for (size_t k = 0; k < 48; k += 5) decoy[k] = 1.0;
  const std::vector<Cell> cells = cells_at(phi, y, 0.3);
  const std::vector<CellGap> g = where(cells, base);
  EXPECT_EQ(significant(g), 0u);
  EXPECT_NEAR(chi2_of(g), 86.72, 0.01);
  EXPECT_TRUE(has_gap(g, 0.01));
  EXPECT_FALSE(has_gap(g, 0.0)) << "the table test off: cells alone";
  const Response r = linear("cohesion", {0.01, 0.1, 1.0}, slope, 30.0);
  const Response d = linear("viscous", {0.01, 0.1, 1.0}, decoy, 30.0);
  Verdict v = decide(cells, base, {r, d}, {1.0, 0.5});
  ASSERT_EQ(v.kind, "effect");
  EXPECT_EQ(v.effect, "cohesion");
  EXPECT_DOUBLE_EQ(v.floor, 48.0);
  EXPECT_TRUE(v.tied.empty()) << "the decoy fails the margin on the gap above 48";
  VerdictRule off;
  off.table_level = 0.0;
  EXPECT_EQ(decide(cells, base, {r, d}, {1.0, 0.5}, off).kind, "no_gap");
  Verdict left = v;
  settle_verdict(left, g, VerdictRule{});
  EXPECT_EQ(left.kind, "partial") << "χ² over the table still beyond its point";
  settle_verdict(v, where(cells, r.pred[1]), VerdictRule{});
  EXPECT_EQ(v.kind, "effect");
}

// A candidate that changes nothing but is predicted with a probe knot's wider se (s √(2 + 1/R) against the
// null's s/√R) scores a lower held-out χ² than the null in every cell, and passes the margin on that alone
// (docs/diagnosis.md, "Known limit"). The held-out log density (VerdictRule::log_density) charges
// ln(v/v_null) per cell and it does not pass; a candidate that explains the gap still does.
TEST(DiagnoseVerdict, TheLogDensityDoesNotRewardAWidePrediction) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, std::sqrt(0.3 * 0.3 + 0.2 * 0.2));
  const std::vector<Prediction> base(48, Prediction{30.0, 0.2});
  std::vector<double> phi, slope(48, 0.0), none(48, 0.0), y;
  for (size_t k = 0; k < 48; ++k) phi.push_back(0.01 * double(k % 6));
  // The truth at 0.3 moves one cell per condition by 1.6 (4.4 σ), so each fold learns it from the others.
  for (size_t k : {1, 8, 15, 22, 29, 36}) slope[k] = 1.6 / 2.477;
  for (size_t k = 0; k < 48; ++k) y.push_back(30.0 + slope[k] * 2.477 + noise(rng));
  const std::vector<Cell> cells = cells_at(phi, y, 0.3);
  const double s = 0.2 * std::sqrt(2.0);  // the run-to-run spread behind the null's se at R = 2 (s ~ σ)
  const Response wide = linear("spread", {0.01, 0.1, 1.0}, none, 30.0, s * std::sqrt(2.5));
  const Response truth = linear("cohesion", {0.01, 0.1, 1.0}, slope, 30.0, s * std::sqrt(2.5));
  VerdictRule chi2, logd;
  logd.held_out = HeldOut::kLogDensity;
  const Verdict a = decide(cells, base, {wide}, {1.0}, chi2);
  ASSERT_NE(a.kind, "no_gap");
  EXPECT_LT(a.ranking.front().loco, 0.6 * a.null_loco) << "the wide prediction's z² are smaller everywhere";
  EXPECT_TRUE(passes_margin(a.ranking.front().loco, a, chi2)) << "the flaw: it passes on its width alone";
  const Verdict b = decide(cells, base, {wide}, {1.0}, logd);
  EXPECT_NEAR(b.ranking.front().loco - a.ranking.front().loco, 48 * std::log((0.09 + 0.2) / (0.09 + 0.04)),
              1e-9)
      << "ln(v/v_null) in each of the 48 cells";
  EXPECT_FALSE(passes_margin(b.ranking.front().loco, b, logd));
  const Verdict c = decide(cells, base, {truth, wide}, {1.0, 0.5}, logd);
  EXPECT_EQ(c.kind, "effect");
  EXPECT_EQ(c.effect, "cohesion");
  EXPECT_TRUE(c.tied.empty()) << "the wide no-op is not tied with the truth";
}

// The note that a fit "runs into the upper end of the physical range" follows the fit that is reported: set
// while the fit sat at the limit, it goes when a later knot (the confirmation's fresh runs) moves the fit
// inside, and comes back if the fit returns to the limit (spread-strong in the flowing matrix kept it stale).
TEST(DiagnoseVerdict, TheLimitNoteFollowsTheReportedFit) {
  const EffectSpec& spec = effect_spec("spread");
  Response r = linear("spread", {0.1, 0.3, spec.phys_hi}, kSlope, 30.0);
  const std::vector<Prediction> base(5, Prediction{30.0, 0.1});
  auto cells_for = [&](double s) {
    std::vector<double> y;
    const double u0 = std::log10(0.1) - 1.0;
    for (double k : kSlope) y.push_back(30.0 + k * (std::log10(s) - u0));
    return cells_at(kPhi, y, 0.3);
  };
  CandidateRuns c;
  c.effect = "spread";
  c.member(0, 0) = r;
  Candidate at_limit;
  at_limit.fit = fit_strength(cells_for(5.0), Emulator(base, r));  // beyond the physical range
  ASSERT_TRUE(at_limit.fit.at_hi);
  settle_limit(c, at_limit);
  EXPECT_EQ(c.at_limit, +1);
  ASSERT_EQ(c.notes.size(), 1u);
  EXPECT_EQ(c.notes[0].rfind("the fit runs into the upper end of the physical range", 0), 0u) << c.notes[0];

  c.notes.push_back("range extended to 0.9");
  Candidate inside;
  inside.fit = fit_strength(cells_for(0.5), Emulator(base, r));
  ASSERT_FALSE(inside.fit.at_hi || inside.fit.open_hi);
  settle_limit(c, inside);
  EXPECT_EQ(c.at_limit, 0);
  ASSERT_EQ(c.notes.size(), 1u) << "the limit note goes, the others stay";
  EXPECT_EQ(c.notes[0], "range extended to 0.9");
}

// The order of a tie (tie_order_evidence): the held-out lean and the fresh lean, each in its own noise,
// added. On the flowing spread-weak twin's numbers the fresh runs outweigh the held-out score. With two
// independent, equally weak pieces of evidence for the better candidate (half a standard deviation each), the
// sum names it more often than the held-out order alone (P(N(1, √2) > 0) = 0.76 against P(N(0.5, 1) > 0) =
// 0.69); a held-out lean of 3 σ is not overturned by a fresh lean within the luck. Without a noise there is
// nothing to weigh, and the held-out order stands (NaN).
TEST(DiagnoseVerdict, TheTieIsOrderedByItsEvidenceWeighedByItsNoise) {
  double hz = 0.0, fz = 0.0;
  const double e = tie_order_evidence(13.26, 19.2, 21.48, 40.86, 21.36, 21.41, &hz, &fz);
  EXPECT_GT(e, 0.0);
  EXPECT_NEAR(hz, 0.277, 0.001);
  EXPECT_NEAR(fz, 0.727, 0.001);
  EXPECT_LT(tie_order_evidence(10.0, 20.0, 3.0, 40.0, 30.0, 20.0), 0.0);
  EXPECT_TRUE(std::isnan(tie_order_evidence(10.0, 20.0, 0.0, 40.0, 30.0, 20.0)));
  EXPECT_TRUE(std::isnan(tie_order_evidence(10.0, 20.0, 3.0, 40.0, 30.0, 0.0)));

  std::mt19937_64 rng(20261206);
  std::normal_distribution<double> n01(0.0, 1.0);
  const double luck = 1.0 / std::sqrt(1.57079632679489662);  // a fresh difference of standard deviation 1
  int held_right = 0, sum_right = 0;
  const int trials = 4000;
  for (int t = 0; t < trials; ++t) {
    // b is the better candidate: lower held out and lower on fresh runs, by half a standard deviation each.
    const double loco_a = 30.0, loco_b = loco_a - 0.5 + n01(rng);
    const double fresh_b = 40.0, fresh_a = fresh_b + 0.5 + n01(rng);
    held_right += loco_b < loco_a;
    sum_right += tie_order_evidence(loco_a, loco_b, 1.0, fresh_a, fresh_b, luck) > 0.0;
  }
  EXPECT_NEAR(double(held_right) / trials, 0.69, 0.025);
  EXPECT_NEAR(double(sum_right) / trials, 0.76, 0.025);
  EXPECT_GT(sum_right, held_right);
}
