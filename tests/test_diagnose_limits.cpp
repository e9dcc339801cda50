// What a table without a gap rules out (limits.h): the χ² difference of a run against the model, the
// bracket of a candidate's runs, and the rule's error rates on observations drawn from a known model.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "diagnose/limits.h"

namespace {

using wetdem::diagnose::Cell;
using wetdem::diagnose::kRuleOutDelta;
using wetdem::diagnose::Limit;
using wetdem::diagnose::limit_noise_share;
using wetdem::diagnose::limit_of;
using wetdem::diagnose::limit_run;
using wetdem::diagnose::limit_scale;
using wetdem::diagnose::LimitRun;
using wetdem::diagnose::Prediction;
using wetdem::diagnose::ruled_out;

std::vector<Cell> limit_cells(const std::vector<double>& y, double sigma) {
  std::vector<Cell> c(y.size());
  for (size_t k = 0; k < y.size(); ++k) c[k].y = y[k], c[k].sigma = sigma, c[k].observable = "x";
  return c;
}

TEST(DiagnoseLimits, DeltaIsTheChi2DifferenceAtTheRunsVariance) {
  // P = R: no seed-noise share. Observed 0, 0; the model predicts 0, 0; a run predicts 3 (se 0) and the
  // model's 0 (no shift there, left out): v = 1.
  EXPECT_DOUBLE_EQ(limit_noise_share(2, 2), 0.0);
  const std::vector<Cell> cells = limit_cells({0.0, 0.0}, 1.0);
  const std::vector<Prediction> model = {{0.0, 0.5}, {0.0, 0.5}};
  const std::vector<Prediction> run = {{3.0, 0.0}, {0.0, 1.0}};
  EXPECT_DOUBLE_EQ(limit_run(cells, model, run, 2, 2).delta, 9.0);
  // Observations the run gives favour it: the difference is negative, by the same amount.
  EXPECT_DOUBLE_EQ(limit_run(limit_cells({3.0, 0.0}, 1.0), model, run, 2, 2).delta, -9.0);
  // A wider run that predicts what the model does is not ruled out for its width.
  const std::vector<Prediction> wide = {{0.0, 5.0}, {0.0, 5.0}};
  EXPECT_DOUBLE_EQ(limit_run(limit_cells({1.0, -1.0}, 1.0), model, wide, 1, 2).delta, 0.0);
  // A cell without a value (NaN) is left out.
  std::vector<Cell> gap = cells;
  gap[0].y = std::nan("");
  EXPECT_DOUBLE_EQ(limit_run(gap, model, run, 2, 2).delta, 0.0);
  // The seed noise's share (P = 1, R = 2: 0.4 of se²) is taken out, and the scatter without a shift is
  // that of A² - B² (P = R = 1, σ = s = 1: var A = var B = 2, cov 1, so 2 (4 + 4 - 2) / (1 + 3)²).
  const std::vector<Prediction> one = {{1.0, 1.0}};
  EXPECT_DOUBLE_EQ(limit_noise_share(1, 2), 0.4);
  EXPECT_DOUBLE_EQ(limit_run(limit_cells({0.0}, 1.0), {{0.0, 0.0}}, one, 1, 2).delta, (1.0 - 0.4) / 2.0);
  const std::vector<Prediction> knot = {{1.0, std::sqrt(3.0)}};
  EXPECT_NEAR(limit_run(limit_cells({0.0}, 1.0), {{0.0, 0.0}}, knot, 1, 1).noise_sd, std::sqrt(0.75), 1e-12);
}

TEST(DiagnoseLimits, ScaleIsThePdgFactorOfTheModelsScatter) {
  const std::vector<Prediction> model(3, Prediction{0.0, 0.0});
  EXPECT_DOUBLE_EQ(limit_scale(limit_cells({0.5, -0.5, 0.0}, 1.0), model), 1.0);
  // χ² = 4 + 4 + 4 over n - 1 = 2.
  EXPECT_DOUBLE_EQ(limit_scale(limit_cells({2.0, -2.0, 2.0}, 1.0), model), 6.0);
}

TEST(DiagnoseLimits, TheBracketIsTheRuledOutTailAndTheRunUnderIt) {
  // Cohesion-like: 0.003 allowed, 0.01 and 0.03 ruled out; the limit is where √Δ crosses 3 between them, in
  // log strength.
  Limit l = limit_of("cohesion", {{0.03, 90.0}, {0.003, 2.1}, {0.01, 41.0}}, kRuleOutDelta);
  EXPECT_DOUBLE_EQ(l.ruled_out_from, 0.01);
  EXPECT_DOUBLE_EQ(l.allowed_to, 0.003);
  const double t = (3.0 - std::sqrt(2.1)) / (std::sqrt(41.0) - std::sqrt(2.1));
  EXPECT_NEAR(l.about, std::pow(10.0, std::log10(0.003) + t * (std::log10(0.01) - std::log10(0.003))), 1e-12);
  EXPECT_GT(l.about, 0.003);
  EXPECT_LT(l.about, 0.01);
  EXPECT_DOUBLE_EQ(l.runs.front().strength, 0.003);  // sorted
  // A weak run ruled out under an allowed stronger one is no limit: the tail starts above the allowed one.
  l = limit_of("spread", {{0.3, 12.0}, {0.5, 3.0}, {0.7, 20.0}}, kRuleOutDelta);
  EXPECT_DOUBLE_EQ(l.ruled_out_from, 0.7);
  EXPECT_DOUBLE_EQ(l.allowed_to, 0.5);
  // An allowed run the observations favour (Δ < 0) counts as no shift.
  l = limit_of("cohesion", {{0.003, -4.0}, {0.01, 36.0}}, kRuleOutDelta);
  EXPECT_NEAR(l.about, std::pow(10.0, std::log10(0.003) + 0.5 * (std::log10(0.01) - std::log10(0.003))),
              1e-12);
  // Nothing ruled out: allowed up to the strongest run, no limit.
  l = limit_of("viscous", {{0.01, 0.5}, {0.1, 5.0}}, kRuleOutDelta);
  EXPECT_DOUBLE_EQ(l.ruled_out_from, 0.0);
  EXPECT_DOUBLE_EQ(l.allowed_to, 0.1);
  EXPECT_DOUBLE_EQ(l.about, 0.0);
  // Every run ruled out: the limit is under the weakest, which no run brackets.
  l = limit_of("scale", {{0.2, 30.0}, {0.4, 80.0}}, kRuleOutDelta);
  EXPECT_DOUBLE_EQ(l.ruled_out_from, 0.2);
  EXPECT_DOUBLE_EQ(l.allowed_to, 0.0);
  EXPECT_DOUBLE_EQ(l.about, 0.0);
  // A larger threshold (a table with more scatter than its errors) rules out less.
  l = limit_of("cohesion", {{0.003, 2.1}, {0.01, 41.0}, {0.03, 90.0}}, 2.0 * 41.0);
  EXPECT_DOUBLE_EQ(l.ruled_out_from, 0.03);
}

// The runs that bracket a limit: one probe step under a weakest run that is already ruled out (floored at
// the physical range), the middle of a bracket wider than kLimitRatio, nothing for a narrow bracket, for a
// candidate nothing rules out, or for a step onto a strength already run.
TEST(DiagnoseLimits, TheNextRunBracketsTheLimit) {
  using wetdem::diagnose::next_limit_strength;
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("absorption", {{0.03, 22.4}}, 9.0), 3.0, 1e-3), 0.01);
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("cohesion", {{0.003, 2.5}, {0.01, 89.5}}, 9.0), 3.33, 1e-4),
                   0.00548);
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("spread", {{0.3, 1.0}, {0.7, 26.4}}, 9.0), 3.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("viscous", {{0.03, -3.1}, {0.1, 5.0}}, 9.0), 3.33, 1e-4),
                   0.0);
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("scale", {{0.0012, 30.0}}, 9.0), 3.0, 0.001), 0.001);
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("scale", {{0.001, 12.0}, {0.0012, 30.0}}, 9.0), 3.0, 0.001),
                   0.0);
  // Another shape of a sink (climb): nothing ruled out there yet, so straight to the range's end; at the end
  // (or within 10 % of it), nothing more. The default shape does not climb: the reach says where it would
  // show. Ruled out at the end, the bracket it makes is split at its geometric middle.
  const Limit slow = limit_of("absorption", {{0.05, 2.0}}, 9.0);
  EXPECT_DOUBLE_EQ(next_limit_strength(slow, 3.0, 1e-3, 0.3, true), 0.3);
  EXPECT_DOUBLE_EQ(next_limit_strength(slow, 3.0, 1e-3, 0.3, false), 0.0);
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("absorption", {{0.28, 2.0}}, 9.0), 3.0, 1e-3, 0.3, true),
                   0.0);
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("absorption", {{0.3, 2.0}}, 9.0), 3.0, 1e-3, 0.3, true), 0.0);
  EXPECT_DOUBLE_EQ(
      next_limit_strength(limit_of("absorption", {{0.03, 2.0}, {0.3, 40.0}}, 9.0), 3.0, 1e-3, 0.3, true),
      0.0949);
  // Ruled out at that shape too: bracketed downward as any limit.
  EXPECT_DOUBLE_EQ(next_limit_strength(limit_of("absorption", {{0.05, 40.0}}, 9.0), 3.0, 1e-3, 0.3, true),
                   0.0167);
}

// The limit with the second parameter free (a profile over the shapes run): ruled out only where every shape
// rules it out, so set by the shape that allows the most; open when one shape rules out none of its runs.
// An effect run at one shape only, or without a second parameter, has none.
TEST(DiagnoseLimits, TheFreeShapeLimitIsWhereEveryShapeRulesOut) {
  using wetdem::diagnose::default_limit;
  using wetdem::diagnose::free_shape_limits;
  const auto at = [](Limit l, double shape) {
    l.shape = shape;
    return l;
  };
  std::vector<Limit> ls = {at(limit_of("absorption", {{0.01, 2.0}, {0.05, 40.0}}, 9.0), 3.0),
                           at(limit_of("absorption", {{0.05, 3.0}, {0.15, 50.0}}, 9.0), 0.3),
                           at(limit_of("absorption", {{0.05, 90.0}}, 9.0), 30.0),
                           limit_of("cohesion", {{0.01, 41.0}}, 9.0)};
  ASSERT_EQ(default_limit(ls, "absorption"), &ls[0]);
  ASSERT_EQ(default_limit(ls, "cohesion"), &ls[3]);
  EXPECT_EQ(default_limit(ls, "viscous"), nullptr);
  auto f = free_shape_limits(ls);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].effect, "absorption");
  EXPECT_EQ(f[0].shapes, (std::vector<double>{0.3, 3.0, 30.0}));
  EXPECT_DOUBLE_EQ(f[0].ruled_out_from, 0.15);
  EXPECT_DOUBLE_EQ(f[0].binding, 0.3);
  EXPECT_TRUE(f[0].open.empty());
  // The slow rate rules out none of its runs: with the rate free, nothing is ruled out.
  ls[1] = at(limit_of("absorption", {{0.05, 3.0}, {0.15, 5.0}}, 9.0), 0.3);
  f = free_shape_limits(ls);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_DOUBLE_EQ(f[0].ruled_out_from, 0.0);
  ASSERT_EQ(f[0].open.size(), 1u);
  EXPECT_DOUBLE_EQ(f[0].open[0].first, 0.3);
  EXPECT_DOUBLE_EQ(f[0].open[0].second, 0.15);
  // One shape run: nothing to profile.
  EXPECT_TRUE(free_shape_limits({ls[0], ls[3]}).empty());
}

// Observations drawn from the model (48 cells, unit noise) and probes made as Procedure::probe makes them:
// the model's mean over R = 2 seeds plus one probe run's difference from the model's run on seed 1, each run
// with unit seed noise, its knot SE √(2 + 1/2). A run that shifts nothing is rarely ruled out: its own noise
// is taken out (else the mean Δ would be 48 × 1/3.5 = 13.7) and its scatter counted (Δ ≥ 9 alone would rule
// it out in ~10 % of tables). One that shifts a cell by the threshold's 3 σ is ruled out about a quarter of
// the time, one of 6 σ almost always.
TEST(DiagnoseLimits, RuledOutAsOftenAsTheShiftSays) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  const size_t cells = 48, trials = 2000;
  const double knot = std::sqrt(2.5), v = 3.5;  // σ² + knot²
  // The fraction ruled out, and the fraction whose Δ alone passes the threshold.
  const auto rate = [&](double shift_z) {
    size_t ruled = 0, past = 0;
    for (size_t t = 0; t < trials; ++t) {
      std::vector<double> y(cells);
      std::vector<Prediction> model(cells), run(cells);
      for (size_t k = 0; k < cells; ++k) {
        y[k] = n01(rng);
        const double e1 = n01(rng), e2 = n01(rng), ep = n01(rng);
        model[k] = {0.5 * (e1 + e2), std::sqrt(0.5)};
        run[k] = {model[k].mean + (k == 5 ? shift_z * std::sqrt(v) : 0.0) + ep - e1, knot};
      }
      const std::vector<Cell> c = limit_cells(y, 1.0);
      const double threshold = kRuleOutDelta * limit_scale(c, model);
      const LimitRun x = limit_run(c, model, run, 1, 2);
      ruled += ruled_out(x, threshold);
      past += x.delta >= threshold;
    }
    return std::make_pair(double(ruled) / trials, double(past) / trials);
  };
  const auto [none, none_past] = rate(0.0);
  EXPECT_LT(none, 0.04);
  EXPECT_GT(none_past, 0.05);
  const double at3 = rate(3.0).first;
  EXPECT_GT(at3, 0.15);
  EXPECT_LT(at3, 0.45);
  EXPECT_GT(rate(6.0).first, 0.85);
}

}  // namespace
