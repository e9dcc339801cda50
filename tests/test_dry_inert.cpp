// The claim behind app::physics_identity (and the diagnosis's reuse of the dry baseline run for a liquid-only
// probe at a dry condition): without liquid, each liquid-only candidate effect at a strong strength leaves
// the run bit for bit the plain dry run. One micro drum run per effect through the whole driver; the final
// states are compared field by field (tests/support/state_diff.h) and the summaries' numbers exactly. The
// same overrides on the wet case must change the run (else the comparison could not fail).
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>

#include "app/case/case.h"
#include "support/gpu.h"
#include "support/small_case.h"
#include "support/small_run.h"
#include "support/state_diff.h"

namespace wetdem::test {
namespace {

const std::vector<std::pair<std::string, std::vector<std::string>>> kLiquidOnly = {
    {"viscous", {"liquid.viscosity=\"0.1 Pa s\""}},
    {"hysteresis", {"liquid.theta_receding=\"2 deg\""}},
    {"evaporation", {"liquid.evaporation_time=\"1 s\""}},
    {"spread", {"liquid.wetted_fraction=0.2"}},
    {"absorption", {"absorption.capacity=0.3", "absorption.rate=20"}},
};

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(PhysicsIdentity, DryLiquidOnlyParametersAreNotPartOfTheRun) {
  const std::vector<std::string> dry = {"liquid.content=0"};
  const nlohmann::json base = app::case_to_json(app::physics_identity(app::parse_case_string(kSmall, dry)));
  for (const auto& [name, sets] : kLiquidOnly) {
    const app::Case d = app::parse_case_string(kSmall, with(dry, sets));
    EXPECT_NE(app::case_to_json(d), base) << name << ": the case itself differs";
    EXPECT_EQ(app::case_to_json(app::physics_identity(d)), base) << name;
    // With liquid the parameter acts: the identity keeps it.
    const app::Case w = app::parse_case_string(kSmall, sets);
    EXPECT_NE(app::case_to_json(app::physics_identity(w)),
              app::case_to_json(app::physics_identity(app::parse_case_string(kSmall))))
        << name << " wet";
  }
  // Cohesion acts on dry contacts: never reset.
  const app::Case c = app::parse_case_string(kSmall, with(dry, {"cohesion.surface_energy=\"0.01 J/m2\""}));
  EXPECT_NE(app::case_to_json(app::physics_identity(c)), base);
}

class DryInert : public GpuTest {};

TEST_F(DryInert, LiquidOnlyEffectsLeaveADryRunBitForBit) {
  const std::vector<std::string> o = {"run.settle=\"0.1 s\"", "run.duration=\"0.25 s\"",
                                      "run.steady_state_start=\"0.1 s\""};
  const std::vector<std::string> dry = with(o, {"liquid.content=0"});
  const SmallRun base = run_small("dry_base", dry);
  const SmallRun wet = run_small("wet_base", o);
  for (const auto& [name, sets] : kLiquidOnly) {
    const SmallRun r = run_small("dry_" + name, with(dry, sets));
    EXPECT_EQ(first_difference(base.result.final_state, r.result.final_state), "") << name;
    for (const char* k : {"aor_deg_mean", "aor_deg_std", "surface_velocity_mps", "contacts_mean"})
      if (base.result.summary.contains(k)) {
        EXPECT_EQ(base.result.summary[k], r.result.summary[k]) << name << " " << k;
      }
    // Wet, the same override changes the run (absorption and evaporation within 0.35 s at these strengths).
    const SmallRun w = run_small("wet_" + name, with(o, sets));
    EXPECT_NE(first_difference(wet.result.final_state, w.result.final_state), "") << name << " wet";
  }
}

}  // namespace
}  // namespace wetdem::test

#endif
