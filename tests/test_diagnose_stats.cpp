// The diagnosis statistics (host/diagnose) on synthetic cells with known answers: Benjamini-Hochberg against
// hand-worked p-values, z and the "where" summary, the screen projection, strength recovery by the emulator
// fit, and the verdict on a planted effect, a decoy and a null.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "diagnose/candidates.h"
#include "diagnose/where.h"

using namespace wetdem::diagnose;

TEST(DiagnoseStats, BenjaminiHochbergIsStepUp) {
  // m = 5, q = 0.05: thresholds k q/m = .01 .02 .03 .04 .05; sorted p = .005 .01 .03 .04 .2 -> the four
  // smallest.
  EXPECT_EQ(benjamini_hochberg({0.01, 0.04, 0.03, 0.005, 0.2}, 0.05),
            (std::vector<bool>{true, true, true, true, false}));
  // Step-up: 0.02 fails its own threshold (0.0167) but is declared because 0.03 <= 2 q/3 = 0.0333.
  EXPECT_EQ(benjamini_hochberg({0.02, 0.03, 0.5}, 0.05), (std::vector<bool>{true, true, false}));
  EXPECT_EQ(benjamini_hochberg({0.3, 0.6}, 0.05), (std::vector<bool>{false, false}));
}

namespace {

// Five liquid contents x one observable; the model under-predicts from 5 % on by a gap growing with content.
std::vector<Cell> aor_cells(const std::vector<double>& y) {
  std::vector<Cell> c;
  const double phi[] = {0.0, 0.0125, 0.025, 0.05, 0.10};
  for (size_t i = 0; i < y.size(); ++i)
    c.push_back({{{"liquid.content", phi[i]}}, "aor_deg_mean", y[i], 0.5});
  return c;
}

}  // namespace

TEST(DiagnoseStats, WhereFindsAndDescribesAGrowingGap) {
  const std::vector<Cell> cells = aor_cells({30.1, 30.2, 29.9, 34.0, 40.0});
  const std::vector<Prediction> base(5, Prediction{30.0, 0.5});
  const std::vector<CellGap> g = where(cells, base);
  EXPECT_NEAR(g[3].z, 4.0 / std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(g[3].p, std::erfc(g[3].z / std::sqrt(2.0)), 1e-15);
  EXPECT_FALSE(g[0].significant);
  EXPECT_FALSE(g[2].significant);
  EXPECT_TRUE(g[3].significant);
  EXPECT_TRUE(g[4].significant);
  const std::vector<std::string> d = describe_where(cells, g);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d[0].find("above the model at 2 of 5"), std::string::npos) << d[0];
  EXPECT_NE(d[0].find("liquid.content 0.05-0.1"), std::string::npos) << d[0];
  EXPECT_NE(d[0].find("growing with liquid.content"), std::string::npos) << d[0];
}

TEST(DiagnoseStats, ScreenProjectsTheGapOnTheResponse) {
  const std::vector<Cell> cells = aor_cells({30, 30, 30, 34, 40});
  const std::vector<Prediction> base(5, Prediction{30.0, 0.0});
  std::vector<Prediction> along = base, against = base, other = base;
  along[4].mean = 35;                                               // moves the model towards the observation
  against[4].mean = 25;                                             // away from it
  other[0].mean = 33;                                               // changes a cell that has no gap
  EXPECT_NEAR(screen_score(cells, base, along), 10.0 / 0.5, 1e-9);  // z_5 = 20 projected on e_5
  EXPECT_NEAR(screen_score(cells, base, against), -20.0, 1e-9);
  EXPECT_NEAR(screen_score(cells, base, other), 0.0, 1e-12);
  EXPECT_EQ(screen_score(cells, base, base), 0.0);
}

namespace {

// A response linear in u = log10(s) above the baseline anchor: mean_k(u) = base + slope_k (u - u_anchor).
Response linear_response(const std::string& name, const std::vector<double>& slope, double base) {
  Response r;
  r.effect = name;
  r.strengths = {1e-3, 1e-2, 1e-1};
  const double u_anchor = -4.0;
  for (double s : r.strengths) {
    std::vector<Prediction> p;
    for (double k : slope) p.push_back({base + k * (std::log10(s) - u_anchor), 0.2});
    r.pred.push_back(p);
  }
  return r;
}

}  // namespace

TEST(DiagnoseStats, FitRecoversTheStrengthWithAnInterval) {
  const std::vector<double> slope = {0.0, 0.5, 1.0, 2.0, 3.0};
  const Response r = linear_response("absorption", slope, 30.0);
  const std::vector<Prediction> base(5, Prediction{30.0, 0.2});
  const Emulator em(base, r);
  const double u_true = std::log10(0.02);
  std::vector<double> y;
  for (double k : slope) y.push_back(30.0 + k * (u_true + 4.0));
  const std::vector<Cell> cells = aor_cells(y);
  const StrengthFit f = fit_strength(cells, em);
  EXPECT_NEAR(std::log10(f.strength), u_true, 1e-3);
  EXPECT_LT(f.chi2, 1e-4);
  EXPECT_LT(f.lo, f.strength);
  EXPECT_GT(f.hi, f.strength);
  EXPECT_FALSE(f.at_edge);
}

TEST(DiagnoseStats, VerdictPicksThePlantedEffectOverADecoyAndNullsAreNoGap) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5);
  const std::vector<Prediction> base(5, Prediction{30.0, 0.2});
  const Response truth = linear_response("evaporation", {0.0, 0.3, 1.0, 2.5, 4.0}, 30.0);
  const Response decoy = linear_response("cohesion", {4.0, 3.0, 1.0, 0.2, 0.0}, 30.0);
  const double u_true = std::log10(0.05);
  std::vector<double> y;
  for (double k : {0.0, 0.3, 1.0, 2.5, 4.0}) y.push_back(30.0 + k * (u_true + 4.0) + noise(rng));
  const std::vector<Cell> cells = aor_cells(y);
  std::vector<double> screens;
  for (const Response* r : {&truth, &decoy}) screens.push_back(screen_score(cells, base, r->pred[1]));
  EXPECT_GT(screens[0], screens[1]);
  const Verdict v = decide(cells, base, {truth, decoy}, screens);
  EXPECT_EQ(v.kind, "effect");
  EXPECT_EQ(v.effect, "evaporation");
  EXPECT_GE(v.held_out_shrink, 0.7);
  EXPECT_NEAR(std::log10(v.ranking.front().fit.strength), u_true, 0.2);

  // Null: observations are the baseline plus measurement noise.
  std::vector<double> y0;
  for (int i = 0; i < 5; ++i) y0.push_back(30.0 + noise(rng));
  const std::vector<Cell> null_cells = aor_cells(y0);
  const Verdict v0 = decide(null_cells, base, {truth, decoy}, {0.0, 0.0});
  EXPECT_EQ(v0.kind, "no_gap");
}

TEST(DiagnoseStats, AGapNoCandidateExplainsIsUnexplained) {
  const std::vector<Prediction> base(5, Prediction{30.0, 0.2});
  // The gap is at the lowest content, where neither candidate acts.
  const std::vector<Cell> cells = aor_cells({38.0, 30.0, 30.1, 29.9, 30.0});
  const Response a = linear_response("evaporation", {0.0, 0.0, 0.5, 1.0, 2.0}, 30.0);
  const Verdict v = decide(cells, base, {a}, {0.0});
  EXPECT_EQ(v.kind, "unexplained");
  EXPECT_LT(v.held_out_shrink, 0.5);
}

TEST(DiagnoseStats, OneConditionAllowsNoHeldOutCheck) {
  const std::vector<Cell> cells = {{{{"liquid.content", 0.05}}, "aor_deg_mean", 35.0, 0.5},
                                   {{{"liquid.content", 0.05}}, "f_wet_mean", 0.5, 0.05}};
  const std::vector<Prediction> base = {{30.0, 0.2}, {0.4, 0.01}};
  Response r;
  r.effect = "spread";
  r.strengths = {0.5};
  r.pred = {base};
  EXPECT_THROW(loco_score(cells, Emulator(base, r)), std::invalid_argument);
}

// Refinement: pore absorption of capacity c (fraction of own volume) leaves a free liquid fraction
// 1 - min(c, phi)/phi at liquid content phi, a response that bends between probes a factor 4-5 apart. The
// emulator through the probes alone misplaces c; knots added at the fitted strength converge on it.
TEST(DiagnoseStats, RefinementConvergesOnABentResponse) {
  const std::vector<double> phi = {0.05, 0.10, 0.15};
  auto free_fraction = [&](double c) {
    std::vector<Prediction> p;
    for (double f : phi) p.push_back({1.0 - std::min(c, f) / f, 0.0});
    return p;
  };
  const double c_true = 0.08;
  std::vector<Cell> cells;
  for (size_t k = 0; k < phi.size(); ++k) {
    Cell c;
    c.condition = {{"liquid.content", phi[k]}};
    c.observable = "liquid_free_fraction";
    c.y = free_fraction(c_true)[k].mean;
    c.sigma = 0.02;
    cells.push_back(c);
  }
  const std::vector<Prediction> base = free_fraction(1e-9);
  Response r;
  r.effect = "absorption";
  for (double s : {0.01, 0.05, 0.2}) r.strengths.push_back(s), r.pred.push_back(free_fraction(s));
  const double coarse = fit_strength(cells, Emulator(base, r)).strength;
  EXPECT_GT(std::fabs(std::log(coarse / c_true)), 0.05) << "the probes alone should misplace it: " << coarse;
  int rounds = 0;
  for (double s; rounds < 5 && (s = next_knot(cells, base, r)) > 0.0; ++rounds)
    add_knot(r, s, free_fraction(s));
  const StrengthFit f = fit_strength(cells, Emulator(base, r));
  EXPECT_NEAR(f.strength, c_true, 0.02 * c_true) << "after " << rounds << " rounds";
  EXPECT_TRUE(std::is_sorted(r.strengths.begin(), r.strengths.end()));
  EXPECT_EQ(r.strengths.size(), r.pred.size());
  EXPECT_EQ(next_knot(cells, base, r), 0.0) << "refined: the fit sits on a knot";
}
