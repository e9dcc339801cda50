// Window quantities (app/observe/window.h): the AoR drift per revolution of a series with a set slope (exact
// without noise, within its standard error with correlated noise, whose error the correlation factor widens),
// the window mean of a series with gaps, and summary.json / timeseries.csv carrying the camera observables.
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "app/observe/window.h"
#include "app/output/summary.h"
#include "app/output/timeseries_stats.h"
#include "support/numbers.h"

namespace wetdem::test {
namespace {

TEST(ObserveWindow, DriftOfAnExactLine) {
  // 40 - 0.5 °/s over 10 s at ω = π/2 rad/s (a revolution every 4 s): -2 °/rev.
  std::vector<double> t, a;
  for (int i = 0; i <= 200; ++i) t.push_back(0.05 * i), a.push_back(40.0 - 0.5 * t.back());
  const observe::Drift d = observe::aor_drift(t, a, 0.5 * kPi);
  EXPECT_EQ(d.n, 201u);
  EXPECT_NEAR(d.slope_deg_per_rev, -2.0, 1e-12);
  EXPECT_NEAR(d.se_deg_per_rev, 0.0, 1e-10);
  // The sense of rotation does not matter; a still drum has no revolution.
  EXPECT_NEAR(observe::aor_drift(t, a, -0.5 * kPi).slope_deg_per_rev, -2.0, 1e-12);
  EXPECT_TRUE(std::isnan(observe::aor_drift(t, a, 0.0).slope_deg_per_rev));
  EXPECT_TRUE(std::isnan(observe::aor_drift({0.0, 1.0}, {1.0, 2.0}, 1.0).slope_deg_per_rev));
}

TEST(ObserveWindow, DriftWithCorrelatedNoiseIsWithinItsError) {
  // AR(1) noise (φ = 0.9, sd 1°) on a drift of 0.3 °/rev, 2048 samples over 8 revolutions. Repeated over 40
  // seeds: the estimate is within 3 SE of the truth in (nearly) every case, the blocked error is well above
  // the plain OLS one (τ_int = (1 + φ)/(1 - φ) = 19 samples: factor ≈ √19 ≈ 4.4), and the standard deviation
  // of the estimates over seeds matches the mean reported SE within 30 % (the spread of a standard deviation
  // from 40 draws is ~11 %).
  const double omega = 2.0 * kPi / 1.0, slope = 0.3;  // one revolution per second, 0.3 °/s
  std::vector<double> est, se, factor;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, std::sqrt(1.0 - 0.81));
    std::vector<double> t, a;
    double e = 0;
    for (int i = 0; i < 2048; ++i) {
      e = 0.9 * e + g(rng);
      t.push_back(i * 8.0 / 2048.0);
      a.push_back(35.0 + slope * t.back() + e);
    }
    const observe::Drift d = observe::aor_drift(t, a, omega);
    est.push_back(d.slope_deg_per_rev), se.push_back(d.se_deg_per_rev),
        factor.push_back(d.se_deg_per_rev / d.se_ols_deg_per_rev);
  }
  double mean = 0, var = 0, mse = 0, mf = 0;
  int outside = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    mean += est[i] / 40, mse += se[i] / 40, mf += factor[i] / 40;
    if (std::fabs(est[i] - slope) > 3 * se[i]) ++outside;
  }
  for (double x : est) var += (x - mean) * (x - mean) / 39;
  EXPECT_LE(outside, 1);
  EXPECT_GT(mf, 3.0);
  EXPECT_LT(mf, 6.0);
  EXPECT_NEAR(std::sqrt(var) / mse, 1.0, 0.3);
  EXPECT_NEAR(mean, slope, 3 * mse / std::sqrt(40.0));
}

TEST(ObserveWindow, WindowStatsSkipSamplesWithoutValue) {
  const double nan = std::nan("");
  const WindowStats w = window_stats_finite({1.0, nan, 3.0, nan, 5.0, 7.0}, 0.01);
  EXPECT_EQ(w.n, 4u);
  EXPECT_DOUBLE_EQ(w.mean, 4.0);
  EXPECT_GT(w.sem, 0.0);
  EXPECT_FALSE(w.sem_reliable);  // 4 samples: too few for a verdict
  EXPECT_EQ(window_stats_finite({nan, nan}, 0.01).n, 0u);
}

TEST(ObserveWindow, TimeseriesRowAndCheckpointRoundTrip) {
  app::Sample s;
  s.time = 1.5;
  s.flagged = false;
  s.aor_signed_deg = 31.0;
  s.camera.aor_surface_deg = 30.5;
  s.camera.agglomerate_size_mean = 2.25;
  const std::string head = app::timeseries_header(), row = app::timeseries_row(s);
  EXPECT_NE(head.find(",aor_surface_deg,aor_plate_deg,aor_centre_deg,surface_velocity_mps,"
                      "flowing_layer_depth_m,agglomerate_size_mean,drum_to_agglomerate_ratio,"
                      "liquid_free_fraction,surface_size_ratio,surface_agglomerate_size\n"),
            std::string::npos);
  EXPECT_NE(row.find(",30.5,,,,,2.25,,,,\n"), std::string::npos) << row;  // no value: empty cell
  s.interface = {0.01, std::nan(""), -0.002};
  const std::vector<app::Sample> back = app::samples_from_json(app::samples_to_json({s}));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].camera.aor_surface_deg, 30.5);
  EXPECT_EQ(back[0].camera.agglomerate_size_mean, 2.25);
  EXPECT_TRUE(std::isnan(back[0].camera.aor_plate_deg));
  const app::Sample with = app::samples_from_json(app::samples_to_json({s}))[0];
  ASSERT_EQ(with.interface.size(), 3u);
  EXPECT_EQ(with.interface[0], 0.01);
  EXPECT_TRUE(std::isnan(with.interface[1]));
  EXPECT_EQ(with.interface[2], -0.002);
  // A checkpoint written before the interface profile (no trailing array) reads without one; one written
  // before the camera observables (no camera array either) still reads.
  nlohmann::json old = app::samples_to_json({s});
  old[0].erase(old[0].size() - 1);
  EXPECT_TRUE(app::samples_from_json(old)[0].interface.empty());
  EXPECT_EQ(app::samples_from_json(old)[0].camera.aor_surface_deg, 30.5);
  old[0].erase(old[0].size() - 1);
  EXPECT_TRUE(std::isnan(app::samples_from_json(old)[0].camera.aor_surface_deg));
}

}  // namespace
}  // namespace wetdem::test
#endif  // WETDEM_HAVE_APP
