// Micro drum runs (tests/support/small_case.h) with each liquid effect of diagnosis.md §3 at a strong
// strength against the same run without it: the fingerprint observable moves in the expected direction.
//   absorption (capacity 0.3, rate 20/s): films drain into the pores; fewer bridges, lower f_wet.
//   evaporation (tau = 1 s, the shortest in range): films + bridges fall, evaporated > 0, f_wet below the
//   base run at the end (0.6 s of rotation is too short for a clear fall within the run itself). spread
//   (wetted_fraction 0.2): a fifth of the particles hold all the liquid; f_wet lower.
// V_min = 6 % of V-bar_S (films are 5 % of own volume): a contact bridges only while both films are thick, so
// liquid leaving the films shows up in f_wet. Liquid accounting exact in every run.
#ifdef WETDEM_HAVE_APP

#include <gtest/gtest.h>

#include <cmath>

#include "app/run/run.h"
#include "support/gpu.h"
#include "support/small_run.h"

namespace wetdem::test {
namespace {

struct EffectOutcome {
  nlohmann::json summary;
  double f_wet_first = 0, f_wet_last = 0;  // mean f_wet over the first and last fifth of the rotation
  int64_t free_first = 0, free_last = 0;   // films + bridges at the first and last sample (units)
};

EffectOutcome run_micro(const std::string& name, const std::vector<std::string>& sets) {
  std::vector<std::string> o = {"run.duration=\"0.6 s\"", "run.steady_state_start=\"0.2 s\"",
                                "liquid.v_min=\"6 %\""};
  o.insert(o.end(), sets.begin(), sets.end());
  const SmallRun r = run_small("effects_" + name, o);
  std::vector<app::Sample> rot;
  for (const app::Sample& s : r.samples)
    if (s.time >= 0.25) rot.push_back(s);
  EffectOutcome out;
  out.summary = r.result.summary;
  const size_t m = std::max<size_t>(rot.size() / 5, 1);
  for (size_t k = 0; k < m && k < rot.size(); ++k) {
    out.f_wet_first += rot[k].f_wet / double(m);
    out.f_wet_last += rot[rot.size() - 1 - k].f_wet / double(m);
  }
  if (!rot.empty()) {
    out.free_first = rot.front().liquid_films + rot.front().liquid_bridges;
    out.free_last = rot.back().liquid_films + rot.back().liquid_bridges;
  }
  for (const app::Sample& s : rot)
    EXPECT_EQ(s.liquid_films + s.liquid_bridges + s.liquid_pores + s.liquid_evaporated,
              r.result.summary["liquid_total_units_start"].get<int64_t>())
        << name << " t = " << s.time;
  EXPECT_TRUE(r.result.summary.value("liquid_conserved", false)) << name;
  return out;
}

class DrumLiquidEffects : public GpuTest {};

TEST_F(DrumLiquidEffects, EachEffectMovesItsFingerprint) {
  const EffectOutcome base = run_micro("base", {});
  const EffectOutcome abs = run_micro("absorption", {"absorption.capacity=0.3", "absorption.rate=20"});
  const EffectOutcome evap = run_micro("evaporation", {"liquid.evaporation_time=\"1 s\""});
  const EffectOutcome spread = run_micro("spread", {"liquid.wetted_fraction=0.2"});
  auto line = [](const char* n, const EffectOutcome& o) {
    std::printf(
        "%-12s f_wet first %.3f last %.3f, window %.3f, bridges %.1f, AoR %.1f, free liquid %lld -> %lld\n",
        n, o.f_wet_first, o.f_wet_last, o.summary.value("f_wet_mean", -1.0),
        o.summary.value("bridges_mean", -1.0), o.summary.value("aor_deg_mean", -1.0), (long long)o.free_first,
        (long long)o.free_last);
  };
  line("base", base);
  line("absorption", abs);
  line("evaporation", evap);
  line("spread", spread);
  // absorption: the films drain into the pores, so bridges and f_wet fall below the base run.
  EXPECT_LT(abs.summary.value("bridges_mean", 0.0), 0.5 * base.summary.value("bridges_mean", 0.0));
  EXPECT_LT(abs.f_wet_last, base.f_wet_last);
  EXPECT_GT(abs.summary["liquid_end"]["pores_units"].get<int64_t>(), 0);
  // evaporation: liquid in films + bridges falls over the run, f_wet falls with it.
  EXPECT_LT(double(evap.free_last), 0.7 * double(evap.free_first));
  EXPECT_GT(evap.summary["liquid_end"]["evaporated_units"].get<int64_t>(), 0);
  EXPECT_LT(evap.f_wet_last, base.f_wet_last - 0.02);
  EXPECT_LT(evap.summary.value("f_wet_mean", 1.0), base.summary.value("f_wet_mean", 0.0));
  // spread: fewer wet particles, lower f_wet.
  EXPECT_LT(spread.summary.value("f_wet_mean", 1.0), base.summary.value("f_wet_mean", 0.0));
}

}  // namespace
}  // namespace wetdem::test

#endif
