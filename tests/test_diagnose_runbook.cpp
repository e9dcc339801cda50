// The diagnosis's run book plans a run whose physics is an earlier one's (app::physics_identity: a
// liquid-only effect at a dry condition) as that run: within one book, and across books sharing a store once
// the first run is complete. Planning only; nothing runs (tests/test_dry_inert.cpp shows the runs are the
// same bits).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "diagnose/runbook.h"

namespace fs = std::filesystem;
using namespace wetdem::diagnose;

namespace {

const std::string kMicroModel = std::string(WETDEM_SOURCE_DIR) + "/assets/diagnosis/micro/model.toml";

Condition at(const std::string& content) {
  Condition c;
  c.values = {{"liquid.content", content, "\"" + content + "\"", std::nan("")}};
  c.label = condition_label(c.values);
  return c;
}

Variant probe(const std::string& effect, double s, std::vector<std::string> overrides) {
  Variant v;
  v.effect = effect;
  v.strength = s;
  v.overrides = std::move(overrides);
  return v;
}

struct Store {
  fs::path p = fs::temp_directory_path() / ("wetdem-runbook-" + std::to_string(::getpid()));
  Store() { fs::remove_all(p); }
  ~Store() { fs::remove_all(p); }
  RunBook book() const { return RunBook(p.string(), "runbook.toml", "runbook", kMicroModel, {}, {}); }
};

TEST(RunBook, ADryLiquidOnlyProbeIsTheDryBaselineRun) {
  Store s;
  RunBook b = s.book();
  Condition dry = at("0 %"), wet = at("5 %");
  const Variant base, visc = probe("viscous", 0.1, {"liquid.viscosity=\"0.1 Pa s\""}),
                      spread = probe("spread", 0.7, {"liquid.wetted_fraction=0.3"}),
                      coh = probe("cohesion", 0.01, {"cohesion.surface_energy=\"0.01 J/m2\""});
  b.want(dry, base, {1, 2});
  EXPECT_EQ(b.runs(), 2u);
  b.want(dry, visc, {1});
  b.want(dry, spread, {1, 2});
  EXPECT_EQ(b.runs(), 2u) << "a dry liquid-only probe planned a run of its own";
  b.want(dry, coh, {1});  // cohesion acts without liquid
  EXPECT_EQ(b.runs(), 3u);
  b.want(wet, base, {1});
  b.want(wet, visc, {1});
  b.want(wet, spread, {1});
  EXPECT_EQ(b.runs(), 6u) << "with liquid each probe is a run";
  // Each probe reads the run it was given: not run yet, so no summaries; no failure recorded.
  EXPECT_FALSE(b.has_summaries({dry}, visc, {1}));
  EXPECT_EQ(b.failure(dry, visc, 1), "");
  EXPECT_TRUE(fs::exists(s.p / "physics")) << "the store records each physics identity's first run";
}

TEST(RunBook, AnotherBookUsesTheCompleteRunWithTheSamePhysics) {
  Store s;
  Condition dry = at("0 %");
  const Variant base, visc = probe("viscous", 0.1, {"liquid.viscosity=\"0.1 Pa s\""});
  {
    RunBook a = s.book();
    a.want(dry, base, {7});
  }
  // Not complete yet: a second book plans its own run.
  {
    RunBook b = s.book();
    b.want(dry, visc, {7});
    EXPECT_EQ(b.runs(), 1u);
    EXPECT_FALSE(b.has_summaries({dry}, visc, {7}));
  }
  // The first run completes (its summary.json is what makes a run complete): a third book reads it.
  std::string first;
  for (const auto& e : fs::directory_iterator(s.p / "physics")) std::ifstream(e.path()) >> first;
  ASSERT_FALSE(first.empty());
  fs::create_directories(s.p / "runs" / first);
  std::ofstream(s.p / "runs" / first / "summary.json") << R"({"aor_deg_mean": 31.5})";
  RunBook c = s.book();
  c.want(dry, visc, {7});
  EXPECT_EQ(c.runs(), 0u) << "the complete run with the same physics was planned again";
  EXPECT_TRUE(c.has_summaries({dry}, visc, {7}));
  EXPECT_DOUBLE_EQ(c.predict(dry, visc, {7}, "aor_deg_mean").mean, 31.5);
}

}  // namespace

// The cost guard's measure (Procedure::cost): a finer scaling has more particles as well as a smaller time
// step, and its particle-steps count both. l -> 0.6 l is (1/0.6)³ = 4.6x the particles in the same drum.
TEST(RunBook, AFinerScalingCostsItsParticlesAsWellAsItsSteps) {
  Store s;
  const RunBook b = s.book();
  const Condition wet = at("5 %");
  const Variant base, finer = probe("scale", 0.4, {"scaling=3"});
  const double steps = b.steps(wet, finer) / b.steps(wet, base);
  const double ps = b.particle_steps(wet, finer) / b.particle_steps(wet, base);
  EXPECT_GT(steps, 1.0) << "a finer scaling takes a smaller time step";
  EXPECT_GT(ps / steps, 3.5) << "particle-steps " << ps << "x against steps " << steps << "x";
  EXPECT_LT(ps / steps, 6.0) << "particle-steps " << ps << "x against steps " << steps << "x";
}
