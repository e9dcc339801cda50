// Liquid sinks (diagnosis.md §3 `absorption`, `evaporation`; params.h LiquidSinkParams), whole steps on every
// backend: the per-step floor law against the analytic decay V0 e^(-kt), the pore capacity, pore liquid never
// bridging, instantaneous absorption = no liquid, exact conservation of films + bridges + pores + evaporated,
// and strength zero = bitwise the model without the sinks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "reference/scenario.h"
#include "support/backend.h"
#include "support/liquid_pair.h"

namespace wetdem::test {
namespace {

class Sinks : public ::testing::TestWithParam<std::string> {};

// Bound of the floor law (stated in docs/model.md "Liquid sinks"): V_{n+1} = V_n - floor(a V_n) lies in
// [(1 - a) V_n, (1 - a) V_n + 1), so e_n = V_n - (1 - a)^n V0 lies in [0, sum_{k<n} (1 - a)^k) within [0, n).
// (1 - a)^n = e^(-k n dt) exactly for a = 1 - e^(-k dt); the 64-bit fraction rounds a down by < 2^-64, which
// moves V_n by < n V0 2^-64 < 1 unit here. So 0 <= V_n - V0 e^(-k n dt) < n + 1, and relative to V_n that is
// < 1e-9 for the volumes below, well inside the 1e-6.
void expect_decay(int64_t v, long double v0, long double kt, uint64_t n, const char* what) {
  const long double exact = v0 * std::exp(-kt);
  const long double err = (long double)v - exact;
  EXPECT_GE(err, -1.0L) << what << " at step " << n;
  EXPECT_LT(err, (long double)n + 1.0L) << what << " at step " << n;
  EXPECT_LT(std::fabs((double)(err / exact)), 1e-6) << what << " at step " << n;
}

// A lone particle (nothing to touch) with a film: absorption at k moves its film into the pores as
// V_f0 e^(-kt) until the pores hold their capacity, then the film stays.
TEST_P(Sinks, AbsorptionFilmDecaysExponentiallyUntilCapacity) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-5);
  prm.liquid_unit_m3 = 1e-24;
  const double vol = 4.0 / 3.0 * kPi * kR * kR * kR;  // 4.19e15 units
  const int64_t v0 = int64_t(1) << 46;                // 7.0e13 units, 1.7 % of the particle volume
  prm.sinks.absorption_rate = 200.0;                  // k dt = 2e-3
  prm.sinks.pore_capacity = 0.5 * double(v0) * prm.liquid_unit_m3 / vol;  // capacity: half the film
  const int64_t cap = pore_capacity_units(prm.sinks.pore_capacity, kR, prm.liquid_unit_m3);
  ASSERT_NEAR(double(cap), 0.5 * double(v0), 2.0);
  SystemState s = empty_state(1);
  put_sphere(s, 0, glm::dvec3(0.0), kR, kRho);
  s.p.film[0] = v0;
  auto b = make_backend(GetParam(), prm, 1);
  b->set_state(s);
  const uint64_t chunk = 50;
  bool reached = false;
  for (uint64_t n = chunk; n <= 1000; n += chunk) {
    b->step(chunk);
    const SystemState st = b->state();
    ASSERT_EQ(st.p.film[0] + st.p.pore[0], v0) << "step " << n;
    const long double kt = 200.0L * (long double)n * 1e-5L;
    if ((long double)v0 * (1.0L - std::exp(-kt)) < (long double)cap - chunk * 2e-3L * v0) {
      expect_decay(st.p.film[0], (long double)v0, kt, n, "film");
    } else if (kt > std::log(2.0L) + 0.1L) {
      reached = true;
      EXPECT_EQ(st.p.pore[0], cap) << "pores full at step " << n;
      EXPECT_EQ(st.p.film[0], v0 - cap) << "film stays once the pores are full, step " << n;
    }
  }
  EXPECT_TRUE(reached);
}

// Evaporation: a lone film decays as V_f0 e^(-t/tau); a bridge loses floor(V_b e_t) per step to the lower
// id's counter, so it decays by the same law; films + bridges + evaporated stays exact.
TEST_P(Sinks, EvaporationDecaysFilmsAndBridgesExactly) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-5);
  prm.liquid_unit_m3 = 1e-24;  // volumes large in units: the floor bound n / V stays far below 1e-6
  prm.liq_pp = water(0, int64_t(1) << 41);
  prm.sinks.evaporation_time = 0.005;  // dt / tau = 2e-3
  SystemState s = empty_state(3);
  put_sphere(s, 0, glm::dvec3(0.0, 0.05, 0.0), kR, kRho);  // alone
  // A bridged pair at rest, touching (delta = 0): the bridge holds it; no rupture while it evaporates.
  put_sphere(s, 1, glm::dvec3(-kR, 0.0, 0.0), kR, kRho);
  put_sphere(s, 2, glm::dvec3(kR, 0.0, 0.0), kR, kRho);
  const int64_t f0 = 123'456'789'012, b0 = int64_t(1) << 40;  // 1.1e-12 m^3 bridge
  s.p.film[0] = f0;
  s.pairs.push_back(bridge_record(1, 2, b0));
  const int64_t total0 = s.total_liquid();
  auto be = make_backend(GetParam(), prm, 3);
  be->set_state(s);
  for (uint64_t n = 100; n <= 1000; n += 100) {
    be->step(100);
    const SystemState st = be->state();
    ASSERT_EQ(st.total_liquid(), total0) << "step " << n;
    const long double x = (long double)n * 1e-5L / 0.005L;
    expect_decay(st.p.film[0], (long double)f0, x, n, "film");
    const PairRecord* p = find_pair(st, 1, 2);
    ASSERT_NE(p, nullptr) << "step " << n;
    expect_decay(p->bridge, (long double)b0, x, n, "bridge");
    EXPECT_EQ(st.p.evaporated[0], f0 - st.p.film[0]);
    EXPECT_EQ(st.p.evaporated[1], b0 - p->bridge) << "a bridge's loss goes to its lower id";
    EXPECT_EQ(st.p.evaporated[2], 0);
  }
}

// films + bridges + pores + evaporated = liquid put in, exactly, over 10^5 steps with both sinks on: two
// pairs approach, touch, form a bridge, rebound and rupture it, while every film evaporates and is absorbed.
// The reference runs 10^5 steps; the GPU system 3 x 10^4 (lavapipe steps a tiny system at ~1,800 steps/s, so
// 10^5 steps would take ~55 s; the integer rule is the same every step). Checked every 10^4 steps.
TEST_P(Sinks, LiquidConservedExactlyOver1e5Steps) {
  SimParams prm = dry_params(5e6, 2e6, 0.9, 1e-5);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, 200'000'000, 0.5);
  prm.sinks.evaporation_time = 0.1;
  prm.sinks.absorption_rate = 3.0;
  prm.sinks.pore_capacity = 0.01;
  SystemState s = empty_state(4);
  // Pair 0-1 approaches fast enough to break its bridge on the rebound (restitution 0.9), and so does 2-3.
  put_sphere(s, 0, glm::dvec3(-kR - 2e-5, 0.0, 0.0), kR, kRho, glm::dvec3(0.3, 0.0, 0.0));
  put_sphere(s, 1, glm::dvec3(kR + 2e-5, 0.0, 0.0), kR, kRho, glm::dvec3(-0.3, 0.0, 0.0));
  put_sphere(s, 2, glm::dvec3(-kR - 2e-5, 0.01, 0.0), kR, kRho, glm::dvec3(0.2, 0.0, 0.0));
  put_sphere(s, 3, glm::dvec3(kR + 2e-5, 0.01, 0.0), kR, kRho, glm::dvec3(-0.2, 0.0, 0.0));
  for (int k = 0; k < 4; ++k) s.p.film[k] = 900'000'000'000 + 7 * k;
  const int64_t total0 = s.total_liquid();
  auto be = make_backend(GetParam(), prm, 4);
  be->set_state(s);
  uint64_t formations = 0;
  const int chunks = GetParam() == "gpu" ? 3 : 10;
  for (int chunk = 1; chunk <= chunks; ++chunk) {
    be->step(10'000);
    formations += be->read_events().formations;
    const SystemState st = be->state();
    const LiquidBudget lb = st.liquid_budget();
    ASSERT_EQ(lb.total(), total0) << "after " << chunk * 10'000 << " steps";
    ASSERT_EQ(liquid_sum(st) + lb.pores + lb.evaporated, total0);
    if (chunk == chunks) {
      EXPECT_GT(lb.pores, 0);
      EXPECT_GT(lb.evaporated, total0 / 2) << "t >= 0.3 s = 3 tau";
      EXPECT_GT(formations, 0u);
    }
  }
}

// Pore liquid never bridges, and instantaneous absorption with room for all the film equals a run without
// liquid: two spheres approach and touch; with "instantaneous" absorption the films go to the pores in the
// first step, no bridge forms, and the motion is bitwise that of the same pair without films.
TEST_P(Sinks, InstantaneousAbsorptionEqualsNoLiquid) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-6);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, 1'000'000'000);
  SystemState s = empty_state(2);
  const double v = 0.01, g0 = 5.5 * v * prm.dt;
  put_sphere(s, 0, glm::dvec3(-kR - 0.5 * g0, 0.0, 0.0), kR, kRho, glm::dvec3(0.5 * v, 0.0, 0.0));
  put_sphere(s, 1, glm::dvec3(kR + 0.5 * g0, 0.0, 0.0), kR, kRho, glm::dvec3(-0.5 * v, 0.0, 0.0));
  SystemState dry = s;
  s.p.film = {300'000'000, 100'000'000};
  SimParams absorbing = prm;
  absorbing.sinks.absorption_rate = std::numeric_limits<double>::infinity();
  absorbing.sinks.pore_capacity = 0.3;  // 1.3e12 units of room: all of it
  auto a = make_backend(GetParam(), absorbing, 2);
  auto d = make_backend(GetParam(), prm, 2);
  a->set_state(s);
  d->set_state(dry);
  a->step(1);
  EXPECT_EQ(a->state().p.pore, (std::vector<int64_t>{300'000'000, 100'000'000}));
  a->step(199);
  d->step(200);
  const SystemState sa = a->state(), sd = d->state();
  EXPECT_EQ(a->read_events().formations, 0u) << "pore liquid formed a bridge";
  EXPECT_EQ(bridge_of(sa, 0, 1), 0);
  EXPECT_EQ(sa.p.film, (std::vector<int64_t>{0, 0}));
  EXPECT_EQ(sa.p.pore, (std::vector<int64_t>{300'000'000, 100'000'000})) << "pores keep their liquid";
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(sa.p.x[k], sd.p.x[k]) << "particle " << k;
    EXPECT_EQ(sa.p.v[k], sd.p.v[k]) << "particle " << k;
  }
  EXPECT_NE(flags_of(sd, 0, 1) & kFlagWasInContact, 0u) << "the pair did touch";
}

// Strength zero is bitwise the model without the feature: capacity 0 (rate on), rate 0 (capacity on), no
// evaporation: the same states as default parameters, step for step, with bridges forming and rupturing.
TEST_P(Sinks, StrengthZeroIsBitwiseTheBaseModel) {
  SimParams prm = dry_params(5e6, 2e6, 0.9, 1e-6);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, 200'000'000, 0.5);
  SystemState s = empty_state(3);
  put_sphere(s, 0, glm::dvec3(-kR - 1e-6, 0.0, 0.0), kR, kRho, glm::dvec3(0.3, 0.0, 0.0));
  put_sphere(s, 1, glm::dvec3(kR + 1e-6, 0.0, 0.0), kR, kRho, glm::dvec3(-0.3, 0.0, 0.0));
  put_sphere(s, 2, glm::dvec3(3 * kR + 5e-6, 0.0, 0.0), kR, kRho);
  s.p.film = {400'000'000, 300'000'000, 200'000'000};
  SimParams zero_cap = prm, zero_rate = prm, no_evap = prm;
  zero_cap.sinks.absorption_rate = 50.0;
  zero_rate.sinks.pore_capacity = 0.2;
  no_evap.sinks.evaporation_time = 0.0;
  auto base = make_backend(GetParam(), prm, 3);
  base->set_state(s);
  base->step(400);
  const SystemState want = base->state();
  EXPECT_GT(base->read_events().formations, 0u);
  for (const SimParams* p : {&zero_cap, &zero_rate, &no_evap}) {
    auto b = make_backend(GetParam(), *p, 3);
    b->set_state(s);
    b->step(400);
    const SystemState got = b->state();
    EXPECT_EQ(got.p.x, want.p.x);
    EXPECT_EQ(got.p.v, want.p.v);
    EXPECT_EQ(got.p.film, want.p.film);
    EXPECT_EQ(got.p.pore, want.p.pore);
    EXPECT_EQ(got.p.evaporated, want.p.evaporated);
    ASSERT_EQ(got.pairs.size(), want.pairs.size());
    for (size_t k = 0; k < got.pairs.size(); ++k) EXPECT_EQ(got.pairs[k].bridge, want.pairs[k].bridge);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, Sinks, ::testing::ValuesIn(backends()), BackendName());

}  // namespace
}  // namespace wetdem::test
