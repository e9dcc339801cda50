// What a run may quote (issue 21, app/output/window_rules.h), on synthetic series: the AoR drift is reported
// only over a window of >= 1 revolution holding >= 10 independent samples, a mean is quotable only when its
// window is stationary, a bridge network that spans the bed is not called an agglomerate, and the result
// lines of the log say each of these.
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "app/case/case.h"
#include "app/output/summary.h"
#include "app/output/window_rules.h"
#include "support/numbers.h"

namespace wetdem {
namespace {

// AR(1) series x_{i+1} = phi x_i + noise (sd 1), mean m.
std::vector<double> ar1_series(size_t n, double phi, double m, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(n);
  double x = 0;
  for (size_t i = 0; i < n; ++i) v[i] = m + (x = phi * x + g(rng));
  return v;
}

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

std::vector<double> times(size_t n, double dt) {
  std::vector<double> t(n);
  for (size_t i = 0; i < n; ++i) t[i] = dt * double(i);
  return t;
}

TEST(WindowRules, DriftNeedsOneRevolution) {
  const double omega = 2 * kPi * 10 / 60;  // 10 rpm: 6 s per revolution
  const std::vector<double> t = times(400, 0.02), white = ar1_series(400, 0.0, 30, 1);
  // The demo's window: 0.8 s at 10 rpm, 0.13 revolutions (its drift read -129 deg/rev).
  const std::string short_window = app::drift_rule_reason(t, white, 0.8, omega, 0.02);
  EXPECT_TRUE(has(short_window, "0.13 revolutions")) << short_window;
  EXPECT_EQ(app::drift_rule_reason(t, white, 8.0, omega, 0.02), "");   // 1.33 revolutions of white noise
  EXPECT_EQ(app::drift_rule_reason(t, white, 8.0, -omega, 0.02), "");  // either sense of rotation
  EXPECT_TRUE(has(app::drift_rule_reason(t, white, 8.0, 0.0, 0.02), "does not turn"));
  EXPECT_NEAR(app::window_revolutions(8.0, omega), 4.0 / 3.0, 1e-12);
}

TEST(WindowRules, DriftNeedsTenIndependentSamplesAboutItsTrend) {
  const double omega = 2 * kPi;  // 1 revolution per second: 4 revolutions in the window
  const std::vector<double> t = times(200, 0.02);
  // Strongly correlated (tau_int = 49.5 samples): 200 samples are ~2 independent ones.
  const std::vector<double> slow = ar1_series(200, 0.98, 30, 7);
  const std::string why = app::drift_rule_reason(t, slow, 4.0, omega, 0.02);
  EXPECT_FALSE(why.empty());
  EXPECT_TRUE(has(why, "n_eff") || has(why, "correlation time")) << why;
  EXPECT_EQ(app::drift_rule_reason(t, ar1_series(200, 0.3, 30, 7), 4.0, omega, 0.02), "");
  // A real drift (10 deg over the window) on white noise: the trend itself does not hide the drift.
  std::vector<double> drifting = ar1_series(200, 0.0, 30, 11);
  for (size_t i = 0; i < drifting.size(); ++i) drifting[i] += 10.0 * t[i] / 4.0;
  EXPECT_FALSE(window_stats(drifting, 0.02).stationary);
  EXPECT_EQ(app::drift_rule_reason(t, drifting, 4.0, omega, 0.02), "");
}

TEST(WindowRules, MeanNeedsAStationaryWindow) {
  EXPECT_EQ(app::mean_rule_reason(window_stats(ar1_series(300, 0.2, 0.7, 3), 0.02)), "");
  std::vector<double> ramp(300);
  for (size_t i = 0; i < ramp.size(); ++i) ramp[i] = 0.5 + 0.001 * double(i);
  EXPECT_FALSE(app::mean_rule_reason(window_stats(ramp, 0.02)).empty());
  EXPECT_TRUE(has(app::mean_rule_reason(window_stats({}, 0.02)), "no sample"));
}

TEST(WindowRules, BridgeNetworkSpanningTheBedIsNoAgglomerate) {
  EXPECT_TRUE(app::network_spans_bed(1834.0, 1834));  // the demo: the whole bed in one cluster
  EXPECT_TRUE(app::network_spans_bed(0.5 * 400, 400));
  EXPECT_FALSE(app::network_spans_bed(2.5, 400));
  EXPECT_FALSE(app::network_spans_bed(std::nan(""), 400));
  EXPECT_FALSE(app::network_spans_bed(1.0, 1));
}

// A window of samples every 0.02 s from the case's window start: AoR from `aor`, f_wet from `fwet`, every
// particle in one bridge cluster when `spans`.
std::vector<app::Sample> window(const app::Case& c, const std::vector<double>& aor,
                                const std::vector<double>& fwet, double cluster) {
  std::vector<app::Sample> v;
  const double t_from = c.run.settle + c.run.steady_state_start;
  for (size_t i = 0; i < aor.size(); ++i) {
    app::Sample s;
    s.time = t_from + c.run.sample_interval * double(i);
    const double a = aor[i] * kPi / 180.0;
    s.com_x = 0.03 * std::sin(a);
    s.com_y = -0.03 * std::cos(a);
    s.aor_signed_deg = aor[i];
    s.flagged = false;
    s.f_wet = fwet[i];
    s.camera.agglomerate_size_mean = cluster;
    s.camera.aor_surface_deg = aor[i] + 2.0;
    v.push_back(s);
  }
  return v;
}

nlohmann::json summary_of(const app::Case& c, const std::vector<app::Sample>& s, size_t particles) {
  app::RunTotals t;
  t.particles = particles;
  t.inserted_diameters = {2.6e-3, 3e-3, 4e-3};
  return app::make_summary(c, app::Derived{}, s, t);
}

// The demo's own window (0.8 s at 10 rpm) with a steady AoR: the mean is quotable, the drift is not reported,
// the bed-spanning network is labelled so, and the result lines say all three.
TEST(WindowRules, ShortWindowReportsNoDriftAndLabelsTheNetwork) {
  const app::Case c = app::parse_case_file(std::string(WETDEM_SOURCE_DIR) + "/assets/demo.toml",
                                           {"run.sample_interval=\"0.002 s\""});
  const size_t n = 401;  // 0.8 s every 2 ms
  const nlohmann::json j =
      summary_of(c, window(c, ar1_series(n, 0.0, 40, 5), ar1_series(n, 0.0, 0.9, 6), 1834.0), 1834);
  ASSERT_TRUE(j["aor_stationary"].get<bool>()) << j["aor_stationary_reason"];
  EXPECT_TRUE(j["aor_drift_deg_per_rev"].is_null());
  EXPECT_TRUE(j["aor_drift_deg_per_rev_sem"].is_null());
  EXPECT_TRUE(has(j["aor_drift_reason"].get<std::string>(), "revolutions"));
  EXPECT_TRUE(j["bridge_network_spans_bed"].get<bool>());
  EXPECT_TRUE(j["not_quotable"].contains("agglomerate_size_mean"));
  EXPECT_FALSE(j["not_quotable"].contains("aor_deg_mean"));
  EXPECT_TRUE(j["f_wet_stationary"].get<bool>()) << j["f_wet_stationary_reason"];
  EXPECT_GT(j["f_wet_sem"].get<double>(), 0.0);

  std::string all;
  for (const std::string& l : app::result_lines(j)) all += l + "\n";
  EXPECT_TRUE(has(all, "dynamic AoR")) << all;
  EXPECT_TRUE(has(all, "stationary, n_eff")) << all;
  EXPECT_TRUE(has(all, "f_wet")) << all;
  EXPECT_TRUE(has(all, "AoR drift    not reported: the window spans 0.13 revolutions")) << all;
  EXPECT_TRUE(has(all, "spans the bed")) << all;
  EXPECT_FALSE(has(all, "agglomerates ")) << all;
}

// A long window (4 revolutions at 60 rpm) of white noise: the drift is reported with its error; a window
// whose AoR and f_wet climb is not stationary, and the result lines say "do not quote" for both.
TEST(WindowRules, LongWindowReportsDriftAndATrendIsNotQuoted) {
  const app::Case c =
      app::parse_case_file(std::string(WETDEM_SOURCE_DIR) + "/assets/demo.toml",
                           {"drum.rpm=60", "run.duration=\"4.8 s\"", "run.steady_state_start=\"0.8 s\"",
                            "run.sample_interval=\"0.02 s\""});
  const size_t n = 201;
  const nlohmann::json j =
      summary_of(c, window(c, ar1_series(n, 0.0, 35, 8), ar1_series(n, 0.0, 0.7, 9), 3.0), 400);
  ASSERT_TRUE(j["aor_drift_deg_per_rev"].is_number()) << j["aor_drift_reason"];
  EXPECT_EQ(j["aor_drift_reason"], "");
  EXPECT_LT(std::fabs(j["aor_drift_deg_per_rev"].get<double>()),
            4 * j["aor_drift_deg_per_rev_sem"].get<double>());
  EXPECT_FALSE(j["bridge_network_spans_bed"].get<bool>());
  EXPECT_TRUE(j["not_quotable"].empty()) << j["not_quotable"].dump();

  std::vector<double> climb(n), fclimb(n);
  for (size_t i = 0; i < n; ++i) climb[i] = 20.0 + 0.2 * double(i), fclimb[i] = 0.3 + 0.003 * double(i);
  const nlohmann::json k = summary_of(c, window(c, climb, fclimb, 3.0), 400);
  EXPECT_NEAR(k["aor_drift_deg_per_rev"].get<double>(), 10.0, 1e-6);  // 0.2 deg per 0.02 s, 1 s per rev
  EXPECT_FALSE(k["aor_stationary"].get<bool>());
  EXPECT_FALSE(k["f_wet_stationary"].get<bool>());
  EXPECT_TRUE(k["not_quotable"].contains("aor_deg_mean"));
  EXPECT_TRUE(k["not_quotable"].contains("f_wet_mean"));
  EXPECT_TRUE(k["not_quotable"].contains("aor_surface_deg"));
  std::string all;
  for (const std::string& l : app::result_lines(k)) all += l + "\n";
  EXPECT_TRUE(has(all, "dynamic AoR")) << all;
  size_t dnq = 0;
  for (size_t at = all.find("NOT STATIONARY, do not quote"); at != std::string::npos;
       at = all.find("NOT STATIONARY, do not quote", at + 1))
    ++dnq;
  EXPECT_EQ(dnq, 2u) << all;  // the AoR and f_wet
  EXPECT_TRUE(has(all, "aor_surface_deg")) << all;
  EXPECT_TRUE(has(all, "agglomerates 3 particles")) << all;
}

}  // namespace
}  // namespace wetdem

#endif  // WETDEM_HAVE_APP
