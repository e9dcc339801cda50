// Resource check before any work (issue 12 point 1, host/app/run/resources.h): a case that cannot fit is
// refused at once, naming the key that drives it, the need and what is available; a normal case passes.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>

#include "app/case/case.h"
#include "app/run/resources.h"
#include "app/run/run.h"
#include "support/gpu.h"

namespace wetdem {
namespace {

std::string asset(const std::string& name) {
  return std::string(WETDEM_SOURCE_DIR) + "/assets/" + name;
}

TEST(Resources, EstimateFollowsTheCase) {
  const app::Case c = app::parse_case_file(asset("pp2_l5.toml"));
  const app::ResourceEstimate e = app::estimate_resources(c);
  // The same n as `wetdem check` (PSD mean volume): pp2_l5 holds ~2.2e4 particles.
  EXPECT_GT(e.particles, 1.5e4);
  EXPECT_LT(e.particles, 3.0e4);
  // Allocated entries: the initial 16 per particle, or 1.5 x the expected list once a rebuild overflows it.
  EXPECT_GT(e.entries_in_list, 5.0);
  EXPECT_DOUBLE_EQ(e.entries_per_particle, std::max(16.0, 1.5 * e.entries_in_list));
  EXPECT_NEAR(e.device_bytes,
              e.particles * (app::device_bytes_per_particle(false) +
                             e.entries_per_particle * app::kDeviceBytesPerEntry),
              1e-6 * e.device_bytes);
  EXPECT_NEAR(e.particle_steps, e.particles * e.steps, 1e-9 * e.particle_steps);
  // n ∝ l^-3: scaling 0.05 instead of 5 multiplies it by 1e6.
  const app::ResourceEstimate big =
      app::estimate_resources(app::parse_case_file(asset("pp2_l5.toml"), {"scaling=0.05"}));
  EXPECT_NEAR(big.particles / e.particles, 1e6, 1e-6 * 1e6);
  EXPECT_EQ(big.driver_key, "scaling");
  // A normal case fits this machine; the huge one does not, and the error names the key and both numbers.
  const app::Available here{std::nullopt, "", app::host_available_bytes()};
  ASSERT_TRUE(here.host_bytes.has_value());
  EXPECT_NO_THROW(app::check_resources(e, here));
  try {
    app::check_resources(big, here);
    FAIL() << "expected a refusal";
  } catch (const app::CaseError& err) {
    EXPECT_EQ(err.key(), "scaling");
    const std::string w = err.what();
    EXPECT_NE(w.find("2.19e+10 particles"), std::string::npos) << w;
    EXPECT_NE(w.find("available"), std::string::npos) << w;
  }
}

TEST(Resources, HugeRunIsRefusedBeforeTheFill) {
  const std::string out = testing::TempDir() + "/wetdem_resources_refused";
  std::filesystem::remove_all(out);
  app::RunOptions o;
  o.case_path = asset("pp2_l5.toml");
  o.overrides = {"scaling=0.05"};
  o.out_dir = out;
  o.quiet = true;
  o.context = &test::gpu();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    app::run_case(o);
    FAIL() << "expected a refusal";
  } catch (const app::CaseError& err) {
    EXPECT_EQ(err.key(), "scaling") << err.what();
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(s, 5.0) << "refused before any fill";
  EXPECT_FALSE(std::filesystem::exists(out)) << "nothing written";
}

// The lavapipe rate `wetdem check` quotes runs through the two measured drums (410 particles: 2.1e5, the
// 1,834-particle demo: 6.3e5), rises between them and is held outside them; the printed line carries it.
TEST(Resources, QuotedLavapipeRateFollowsTheMeasuredDrums) {
  EXPECT_NEAR(app::lavapipe_throughput(410), 2.1e5, 1.0);
  EXPECT_NEAR(app::lavapipe_throughput(1834), 6.3e5, 1.0);
  EXPECT_NEAR(app::lavapipe_throughput(50), 2.1e5, 1.0);
  EXPECT_NEAR(app::lavapipe_throughput(9e6), 6.3e5, 1.0);
  double last = 0;
  for (double n = 400; n < 2000; n *= 1.1) {
    EXPECT_GE(app::lavapipe_throughput(n), last) << n;
    last = app::lavapipe_throughput(n);
  }
  app::ResourceEstimate e;
  e.particles = 1834;
  e.steps = 1e4;
  e.particle_steps = 1834 * 1e4;
  const std::string line = app::describe_resources(e, app::lavapipe_throughput(e.particles), "src");
  EXPECT_NE(line.find("at 6.3e+05 particle-steps/s (src)"), std::string::npos) << line;
  EXPECT_NE(line.find("29.1 s"), std::string::npos) << line;
}

}  // namespace
}  // namespace wetdem
