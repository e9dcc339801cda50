// What the table can see (diagnose/power.h): the largest shift of a probe over the baseline, in units of each
// cell's noise, against hand-computed values.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "diagnose/baseline.h"
#include "diagnose/effects.h"
#include "diagnose/next_experiment.h"
#include "diagnose/power.h"

namespace wetdem::diagnose {
namespace {

Cell cell(double sigma) {
  Cell c;
  c.observable = "aor_deg_mean";
  c.sigma = sigma;
  return c;
}

TEST(DiagnosePower, TheLargestShiftIsCountedInEachCellsNoise) {
  // Cell 0: a shift of 2 against sigma 1 and se 0: 2 sigma. Cell 1: a shift of 6 against sqrt(3^2 + 4^2) = 5:
  // 1.2 sigma, though larger in absolute terms. Cell 2: a shift of -0.9 against sqrt(0.3^2 + 0.4^2) = 0.5:
  // 1.8 sigma (the sign does not matter).
  const std::vector<Cell> cells = {cell(1.0), cell(3.0), cell(0.3)};
  const std::vector<Prediction> base = {{10.0, 0.5}, {20.0, 0.5}, {0.0, 0.5}};
  const std::vector<Prediction> probe = {{12.0, 0.0}, {26.0, 4.0}, {-0.9, 0.4}};
  const Shift s = shift_of(cells, base, probe);
  EXPECT_NEAR(s.max_z, 2.0, 1e-12);
  EXPECT_EQ(s.cell, 0u);
  EXPECT_EQ(s.cells, 3u);
  // chi2 4 + 1.44 + 3.24 = 8.68, less what the probe's own noise gives: 0 + 16/25 + 0.16/0.25 = 1.28.
  EXPECT_NEAR(s.chi2_excess, 8.68 - 1.28, 1e-12);
  EXPECT_LT(s.max_z, kVisibleZ) << "2 sigma in one cell is not a shift a lab would call significant";
  EXPECT_LT(s.chi2_excess, visible_chi2_excess(cells.size()));
}

TEST(DiagnosePower, CellsAProbeDoesNotReportAreSkipped) {
  // A probe that reports no value at a cell (NaN: the quantity does not exist there) never makes the largest
  // shift, and a probe identical to the baseline has none (its excess is minus its own noise).
  const std::vector<Cell> cells = {cell(1.0), cell(1.0)};
  const std::vector<Prediction> base = {{1.0, 0.1}, {5.0, 0.1}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Shift s = shift_of(cells, base, {{nan, nan}, {8.5, 0.0}});
  EXPECT_NEAR(s.max_z, 3.5, 1e-12);
  EXPECT_EQ(s.cell, 1u);
  EXPECT_EQ(s.cells, 1u);
  EXPECT_EQ(shift_of(cells, base, base).max_z, 0.0);
  EXPECT_LT(shift_of(cells, base, base).chi2_excess, 0.0);
}

// Visible through the whole table: 48 cells each moved by 1.2 sigma (no single cell near 3 sigma) make a chi2
// excess of 69, past the upper 1 % point of a chi2 with 48 degrees of freedom less its mean (73.7 - 48
// = 25.7); 48 cells at 0.6 sigma (17.3) do not pass.
TEST(DiagnosePower, ManySmallShiftsAreVisibleTogether) {
  EXPECT_NEAR(visible_chi2_excess(48), 73.68 - 48, 0.05) << "chi2 with 48 dof: upper 1 % point 73.68";
  EXPECT_NEAR(visible_chi2_excess(3), 11.34 - 3, 0.05) << "chi2 with 3 dof: upper 1 % point 11.34";
  const std::vector<Cell> cells(48, cell(1.0));
  const std::vector<Prediction> base(48, {0.0, 0.0});
  const Shift many = shift_of(cells, base, std::vector<Prediction>(48, {1.2, 0.0}));
  EXPECT_LT(many.max_z, kVisibleZ);
  EXPECT_GE(many.chi2_excess, visible_chi2_excess(48));
  EXPECT_LT(shift_of(cells, base, std::vector<Prediction>(48, {0.6, 0.0})).chi2_excess,
            visible_chi2_excess(48));
}

Cell cell_of(const std::string& observable) {
  Cell c;
  c.observable = observable;
  c.sigma = 1.0;
  return c;
}

// R runs on each side (a candidate's fresh runs against the control's, power.h): both sides' errors are in
// the noise and in what the excess subtracts, by hand: cell 0 a shift of 3 against sqrt(1 + 0.36 + 0.64) =
// sqrt(2): 2.12 sigma; cell 1 a shift of -3 against sqrt(4 + 0 + 0) = 2: 1.5 sigma. chi2 4.5 + 2.25 =
// 6.75, less 1/2 + 0 = 0.5. The same pair with the control's error dropped (one side's noise, as shift_of
// counts a probe against the baseline) would over-state the shift.
TEST(DiagnosePower, FreshRunsAgainstTheControlCountBothSidesNoise) {
  const std::vector<Cell> cells = {cell(1.0), cell(2.0)};
  const std::vector<Prediction> control = {{10.0, 0.8}, {5.0, 0.0}};
  const std::vector<Prediction> fresh = {{13.0, 0.6}, {2.0, 0.0}};
  const Shift s = fresh_shift(cells, control, fresh);
  EXPECT_NEAR(s.max_z, 3.0 / std::sqrt(2.0), 1e-12);
  EXPECT_EQ(s.cell, 0u);
  EXPECT_EQ(s.cells, 2u);
  EXPECT_NEAR(s.chi2_excess, 6.75 - 0.5, 1e-12);
  EXPECT_GT(shift_of(cells, control, fresh).max_z, s.max_z);
  EXPECT_FALSE(shows(s, cells.size())) << "2.1 sigma and an excess of 6.25 over 2 cells (visible from 7.2)";
  // Twice the shift shows, in one cell and through the table.
  const Shift twice = fresh_shift(cells, control, {{16.0, 0.6}, {-1.0, 0.0}});
  EXPECT_NEAR(twice.max_z, 6.0 / std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(shows(twice, cells.size()));
  EXPECT_EQ(fresh_shift(cells, control, control).max_z, 0.0);
}

TEST(DiagnosePower, AnUnseenLeadIsNamedOnlyWhenItsFreshRunsShowItAndConfirmTheFit) {
  // Two cells of sigma 1, the control (the model without the lead, the fresh seeds) 4 sigma below the data in
  // cell 0: chi2 16 + 0 against the data. Fresh runs of the lead that close cell 0 show it (4 sigma against
  // the control, more than kVisibleZ) and drop chi2 from 16 to 0: named.
  const std::vector<Cell> cells = {cell(1.0), cell(1.0)};
  const std::vector<Prediction> control = {{6.0, 0.0}, {5.0, 0.0}};
  const double data0 = 10.0, data1 = 5.0;
  const auto chi2 = [&](const std::vector<Prediction>& m) {
    return (m[0].mean - data0) * (m[0].mean - data0) + (m[1].mean - data1) * (m[1].mean - data1);
  };
  const VerdictRule rule;  // min_drop 4
  const std::vector<Prediction> closes = {{10.0, 0.0}, {5.0, 0.0}};
  const Shift s = fresh_shift(cells, control, closes);
  EXPECT_TRUE(names_unseen_lead(s, cells.size(), chi2(control), chi2(closes), rule, 0.0));
  // The same drop within the model's own seed luck (16 < 20) is not confirmed.
  EXPECT_FALSE(names_unseen_lead(s, cells.size(), chi2(control), chi2(closes), rule, 20.0));
  // A shift as large the wrong way (away from the data) shows but raises chi2: not named.
  const std::vector<Prediction> away = {{2.0, 0.0}, {5.0, 0.0}};
  const Shift a = fresh_shift(cells, control, away);
  EXPECT_TRUE(shows(a, cells.size()));
  EXPECT_FALSE(names_unseen_lead(a, cells.size(), chi2(control), chi2(away), rule, 0.0));
  // A drop the runs' own noise hides: the lead moves cell 0 by 1.5 against sqrt(1 + 1 + 1) (the cell's sigma,
  // the fresh runs' se and the control's), 0.87 sigma, though chi2 against the data falls from 16 to 6.25 by
  // the cells' sigma alone. The table cannot tell that shift from noise: not named, whatever the drop.
  const std::vector<Prediction> noisy_control = {{6.0, 1.0}, {5.0, 0.0}};
  const std::vector<Prediction> noisy = {{7.5, 1.0}, {5.0, 0.0}};
  const Shift n = fresh_shift(cells, noisy_control, noisy);
  EXPECT_LT(n.max_z, kVisibleZ);
  EXPECT_FALSE(shows(n, cells.size()));
  EXPECT_GE(chi2(noisy_control) - chi2(noisy), rule.min_drop) << "the drop alone would confirm";
  EXPECT_FALSE(names_unseen_lead(n, cells.size(), chi2(noisy_control), chi2(noisy), rule, 0.0));
}

TEST(DiagnoseWithinInflation, SeedSpreadOverOwnErrorPooledPerObservable) {
  // Two seeds at two conditions of each observable. Clumps: the seeds differ by 4 and 2 (sample variances
  // 8 and 2) with own SEs 1 (mean SE² 1 and 1): f² = (8 + 2) / (1 + 1) = 5. AoR: the seeds differ by 1 and 0
  // with own SEs 2: f² = 0.5 / 8 < 1, floored at 1 (an own error is never shrunk). Velocity: a seed that does
  // not report the cell leaves one value, no spread: f = 1.
  const std::vector<Cell> cells = {cell_of("clumps"), cell_of("clumps"), cell_of("aor"), cell_of("aor"),
                                   cell_of("velocity")};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::vector<Prediction>> seeds = {
      {{20.0, 1.0}, {10.0, 1.0}, {30.0, 2.0}, {31.0, 2.0}, {0.1, 0.01}},
      {{24.0, 1.0}, {12.0, 1.0}, {31.0, 2.0}, {31.0, 2.0}, {nan, nan}}};
  const std::map<std::string, double> f = within_inflation(cells, seeds);
  EXPECT_NEAR(f.at("clumps"), std::sqrt(5.0), 1e-12);
  EXPECT_EQ(f.at("aor"), 1.0);
  EXPECT_EQ(f.at("velocity"), 1.0);
}

// The screen of one run pair beyond the table (power.h, reach_screen_z). Seeds whose spread dominates the
// noise (per-run sd 1, no table sigma) and a true shift that R = 2 seeds each show at 3.5 sigma: a pair
// screened at kVisibleZ finds it about a third of the time, so most such shifts were never confirmed;
// screened at 3/sqrt(2) most are. With no shift the lower screen asks for confirming seeds more often, which
// only costs runs: the claim still needs 3 sigma over the R seeds each, and that stays rare.
TEST(DiagnosePower, ThePairScreenCatchesWhatTheSeedsWouldConfirm) {
  EXPECT_DOUBLE_EQ(reach_screen_z(1), kVisibleZ);
  EXPECT_NEAR(reach_screen_z(2), 2.1213, 1e-4);
  EXPECT_DOUBLE_EQ(reach_screen_z(4), 1.5);
  // P probe seeds each side: 3 sqrt(P / R); with every replicate already run there is nothing to confirm.
  EXPECT_NEAR(reach_screen_z(4, 2), 2.1213, 1e-4);
  EXPECT_DOUBLE_EQ(reach_screen_z(2, 2), kVisibleZ);
  EXPECT_DOUBLE_EQ(reach_screen_z(2, 3), kVisibleZ);
  const size_t R = 2, trials = 20000;
  const double delta = 3.5 * std::sqrt(2.0 / double(R));  // 3.5 sigma over R seeds each side
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  const auto rates = [&](double shift) {
    size_t at_visible = 0, at_screen = 0, claimed = 0;
    for (size_t k = 0; k < trials; ++k) {
      double a = 0, b = 0;
      std::vector<double> xa, xb;
      for (size_t r = 0; r < R; ++r) xa.push_back(shift + n01(rng)), xb.push_back(n01(rng));
      const double pair = std::fabs(xa[0] - xb[0]) / std::sqrt(2.0);
      for (size_t r = 0; r < R; ++r) a += xa[r] / double(R), b += xb[r] / double(R);
      const double all = std::fabs(a - b) / std::sqrt(2.0 / double(R));
      at_visible += pair >= kVisibleZ;
      at_screen += pair >= reach_screen_z(R);
      claimed += pair >= reach_screen_z(R) && all >= kVisibleZ;
    }
    return std::array<double, 3>{double(at_visible) / trials, double(at_screen) / trials,
                                 double(claimed) / trials};
  };
  const auto real = rates(delta);
  EXPECT_LT(real[0], 0.45);  // P(|N(2.47, 1)| >= 3) = 0.30
  EXPECT_GT(real[1], 0.60);  // P(|N(2.47, 1)| >= 2.12) = 0.64
  EXPECT_GT(real[2], 0.45);  // confirmed over both seeds
  const auto none = rates(0.0);
  EXPECT_LT(none[2], 0.01);  // a claim with no shift: the pair and the mean both past their thresholds
}

}  // namespace
}  // namespace wetdem::diagnose

using namespace wetdem::diagnose;

// Where the strongest strength shows beyond the table by z >= 3 σ, weaker strengths run there too (power.h,
// next_weaker_strength): first the one that would show by 3 σ in proportion (strongest × 3/z, 3 digits),
// then, once one fell short, the geometric middle of the bracket; none when nothing shows, or the step lands
// within 10 % of a strength already run (not worth a run).
TEST(DiagnosePower, WeakerStrengthsBracketWhereAShiftBeyondTheTableStartsToShow) {
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 4.0, {}), 0.075);
  EXPECT_DOUBLE_EQ(next_weaker_strength(28.0, 9.0, {}), 9.33);
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 3.46, {}), 0.0867) << "the micro CI's cohesion beyond the table";
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 3.2, {}), 0.0) << "0.0938 is within 10 % of 0.1";
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 2.9, {}), 0.0) << "under 3 σ: nothing shows to scale from";
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.0, 5.0, {}), 0.0);
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, std::nan(""), {}), 0.0);
  // The flowing viscous-weak twin's table: 0.1 Pa s at 6.0 σ, its proportional 0.0503 at 1.8 σ: the middle.
  const std::vector<WeakerRun> fell{{0.0503, 1.8}};
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 5.97, fell), 0.0709);
  WeakerBracket b = weaker_bracket(0.1, 5.97, fell);
  EXPECT_DOUBLE_EQ(b.from, 0.1);
  EXPECT_DOUBLE_EQ(b.below, 0.0503);
  // The middle shows: the bracket closes from above; it is now 0.0503-0.0709, and its middle is next.
  const std::vector<WeakerRun> closed{{0.0503, 1.8}, {0.0709, 3.4}};
  b = weaker_bracket(0.1, 5.97, closed);
  EXPECT_DOUBLE_EQ(b.from, 0.0709);
  EXPECT_DOUBLE_EQ(b.from_z, 3.4);
  EXPECT_DOUBLE_EQ(b.below, 0.0503);
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 5.97, closed), 0.0597);
  // A proportional step that shows again steps on from it (0.0868 at 3.6 σ: 0.0723).
  const std::vector<WeakerRun> shown{{0.0868, 3.6}};
  b = weaker_bracket(0.1, 3.46, shown);
  EXPECT_DOUBLE_EQ(b.from, 0.0868);
  EXPECT_DOUBLE_EQ(b.below, 0.0);
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 3.46, shown), 0.0723);
  // A bracket narrower than 10 % either side of its middle is closed.
  EXPECT_DOUBLE_EQ(next_weaker_strength(0.1, 5.0, {{0.085, 2.5}, {0.092, 3.1}}), 0.0);
  // A shift that is not monotonic in the strength (noise): the bracket takes the weakest that showed and the
  // strongest under it that fell short.
  b = weaker_bracket(0.1, 5.0, {{0.05, 3.2}, {0.07, 2.4}});
  EXPECT_DOUBLE_EQ(b.from, 0.05);
  EXPECT_DOUBLE_EQ(b.below, 0.0);
}

// The reach steps past the file's strongest probe (power.h, next_reach_strength) by the probes' ratio, at
// least 3x, to the end of the range the model can realise, and stops where less than a quarter more is left.
TEST(DiagnosePower, TheReachStepsPastTheProbesToTheEndOfTheRange) {
  const std::vector<double> viscous = {0.003, 0.01, 0.03};
  EXPECT_DOUBLE_EQ(next_reach_strength(0.03, viscous, 1.0), 0.1) << "x3.33, the probes' 0.003 -> 0.01";
  EXPECT_DOUBLE_EQ(next_reach_strength(0.1, viscous, 1.0), 0.333);
  EXPECT_DOUBLE_EQ(next_reach_strength(0.03, {0.01, 0.02, 0.03}, 1.0), 0.09) << "at least 3x";
  EXPECT_DOUBLE_EQ(next_reach_strength(0.5, viscous, 1.0), 1.0) << "capped at the end of the range";
  EXPECT_DOUBLE_EQ(next_reach_strength(0.9, viscous, 1.0), 0.0) << "1.0 is less than a quarter more";
  EXPECT_DOUBLE_EQ(next_reach_strength(0.05, {0.01, 0.05}, 1.0), 0.25) << "the probes' own ratio, 5x";
  EXPECT_DOUBLE_EQ(next_reach_strength(0.01, {0.01}, 1.0), 0.03) << "one probe: 3x";
  EXPECT_DOUBLE_EQ(next_reach_strength(0.0, viscous, 1.0), 0.0) << "nothing ran";
  // Hysteresis (θ - θ_r) cannot pass the model's θ: θ_r is floored at 0 (effects.cpp).
  ModelFacts m;
  m.theta_rad = 30.0 * 3.14159265358979323846 / 180.0;
  const EffectSpec& h = effect_spec("hysteresis");
  EXPECT_NEAR(h.realisable_hi(m), 30.0, 1e-9);
  EXPECT_DOUBLE_EQ(next_reach_strength(28.0, h.probes, h.realisable_hi(m)), 0.0)
      << "30 is not a quarter more";
  EXPECT_NEAR(next_reach_strength(10.0, h.probes, h.realisable_hi(m)), 30.0, 1e-9)
      << "x3.33 (the probes' 3 -> 10) is 33.3, capped at θ";
  EXPECT_DOUBLE_EQ(effect_spec("viscous").realisable_hi(m), 1.0);
}

// Which shift beyond the table run_reach runs again on every base seed (power.h, confirms_beyond). One at the
// pair screen is; so is one under it that a repeated measurement would show (the runs' own error is small
// against their difference: repeats_for > 0), because the report then asks a laboratory to repeat that
// measurement and must not ask on one seed's number. One the runs' own error hides (no number of repeats
// helps) is not, nor is one already run on every seed, or one whose seeds cannot be run.
TEST(DiagnosePower, AShiftARepeatedMeasurementWouldShowIsConfirmedOnEverySeed) {
  const double screen = reach_screen_z(2);  // 2.12: R = 2 base seeds, P = 1 probe seed
  // Δ = 1.8 against a measurement noise σ = 1: z = 1.8 / √(1 + se²).
  const size_t shows = repeats_for(1.8, 1.0, 0.01, kVisibleZ);  // the runs differ by 18 of their own σ
  const size_t hidden = repeats_for(1.8, 1.0, 0.5, kVisibleZ);  // 2.5: never 3 σ, however often measured
  EXPECT_EQ(shows, 3u);  // 1.8 / √(1/3 + 0.01) = 3.07; 1.8 / √(1/2 + 0.01) = 2.52
  EXPECT_EQ(hidden, 0u);
  const double z_shows = 1.8 / std::sqrt(1.01), z_hidden = 1.8 / std::sqrt(1.5);
  ASSERT_LT(z_shows, screen);
  EXPECT_TRUE(confirms_beyond(z_shows, shows, 1, 2, screen));
  EXPECT_FALSE(confirms_beyond(z_hidden, hidden, 1, 2, screen));
  EXPECT_TRUE(confirms_beyond(screen, 0, 1, 2, screen));        // at the screen: as before
  EXPECT_FALSE(confirms_beyond(z_shows, shows, 2, 2, screen));  // already on every seed
  EXPECT_FALSE(confirms_beyond(5.0, shows, 0, 2, screen));      // its confirming seeds cannot be run
  EXPECT_FALSE(confirms_beyond(z_shows, shows, 1, 1, screen));  // one base seed: nothing to confirm with
}
