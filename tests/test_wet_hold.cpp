// Issue 12 point 6 ("a wet bed that hangs on too long"): the parts of the wet model that hold a cohesive bed
// under a sustained load, each isolated and checked against physics.md on every backend.
//  - a V_max bridge pulled apart slowly: Willett's force at every gap inside the interaction range, rupture
//    in the first step with S >= S_c,max (the interaction range), no pull in that step (as MercuryDPM) nor
//    after (§4, §5; docs/closed-slice.md);
//  - a sphere hanging on a rotating end plate by a wall bridge: held while the rolling (or sliding) limit of
//  §2-3
//    can carry its weight, rolling (or sliding) down otherwise; with the plate's bridges off, no wall bridge
//    forms and nothing holds it.
// Expected values are written here from the formulas of physics.md, independently of both implementations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "reference/scenario.h"
#include "support/backend.h"
#include "support/liquid_pair.h"

namespace wetdem::test {
namespace {

// Willett (§4): f0 / (1 + 1.05 S' + 2.5 S'^2), S' = S sqrt(R_h / V); f0 while touching.
double willett(double f0, double R_h, double V, double S) {
  if (S <= 0.0) return f0;
  const double s = S * std::sqrt(R_h / V);
  return f0 / (1.0 + 1.05 * s + 2.5 * s * s);
}

class WetHold : public ::testing::TestWithParam<std::string> {};

// Two equal spheres (r = 1 mm) with a bridge at V_max, pulled apart at 0.4 m/s (4e-7 m per step); their mass
// is huge so the bridge cannot change the imposed motion. Every step inside the interaction range: the force
// equals Willett's at the gap; the bridge lasts while S < S_c,max = (1 + theta/2) V_max^(1/3) (which is also
// the interaction range) and ruptures at the end of the first step with S >= S_c,max. It does not pull in
// that step: MercuryDPM's neighbour search no longer sees the pair then, and a pull there holds a creeping
// cohesive bed ~3 degrees longer in the closed slice (docs/closed-slice.md). After it, no force.
TEST_P(WetHold, VmaxBridgeFollowsWillettUntilTheInteractionRange) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-6);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, kVmax);
  const double v = 0.4;
  SystemState s = empty_state(2);
  put_sphere(s, 0, glm::dvec3(kR, 0.0, 0.0), kR, 2500.0, glm::dvec3(0.5 * v, 0.0, 0.0));
  put_sphere(s, 1, glm::dvec3(-kR, 0.0, 0.0), kR, 2500.0, glm::dvec3(-0.5 * v, 0.0, 0.0));
  for (int k = 0; k < 2; ++k) s.p.mass[k] = s.p.inertia[k] = 1e20;
  s.pairs.push_back(bridge_record(0, 1, kVmax));
  auto b = make_backend(GetParam(), prm, 2);
  b->set_state(s);

  const double V = double(kVmax) * prm.liquid_unit_m3;
  const double Sc = (1.0 + 0.5 * prm.liq_pp.theta) * std::cbrt(V);
  EXPECT_NEAR(Sc, prm.bridge_range_pp(), 1e-12) << "a V_max bridge ruptures at the interaction range";
  const double R_h = kR;  // 2 r r / (r + r)
  const double f0 = 2.0 * kPi * R_h * prm.liq_pp.gamma * std::cos(prm.liq_pp.theta);
  const double tol = GetParam() == "reference" ? 1e-9 : 2e-5;
  double worst = 0.0;
  int rupture_step = -1;
  for (int k = 1; k <= 400 && rupture_step < 0; ++k) {
    b->step(1);
    const SystemState st = b->state();
    const double S = glm::length(st.p.x[0] - st.p.x[1]) - 2.0 * kR;
    const int64_t vb = bridge_of(st, 0, 1);
    if (S < Sc) {
      const double f = willett(f0, R_h, V, S);  // on 0 (at +x) towards 1: -x
      ASSERT_NEAR(st.p.f[0].x, -f, tol * f0) << "step " << k << ", S = " << S;
      ASSERT_NEAR(st.p.f[1].x, f, tol * f0);
      worst = std::max(worst, std::fabs(st.p.f[0].x + f) / f);
      ASSERT_EQ(vb, kVmax) << "the bridge lasts while S < S_c,max; step " << k;
      continue;
    }
    rupture_step = k;
    EXPECT_EQ(vb, 0) << "ruptures in the first step with S >= S_c,max";
    EXPECT_LT(S - Sc, v * prm.dt * 1.01);
    // Outside the interaction range: no pull in the rupture step (Willett would still give 0.0254 f0 here,
    // §7 item 2, which the earlier rule applied).
    EXPECT_EQ(st.p.f[0].x, 0.0) << "no pull beyond the interaction range, S - S_c,max = " << S - Sc;
    EXPECT_EQ(st.p.f[1].x, 0.0);
    EXPECT_EQ(st.p.film[0] + st.p.film[1], kVmax);
  }
  ASSERT_GT(rupture_step, 0);
  b->step(1);
  const SystemState after = b->state();
  EXPECT_EQ(after.p.f[0].x, 0.0) << "no pull once ruptured";
  EXPECT_EQ(rupture_step, int(std::ceil(Sc / (v * prm.dt))));
  std::printf("[%s] V_max bridge: ruptured in step %d at S_c,max = %.6e m; worst |F - Willett|/F = %.2e\n",
              GetParam().c_str(), rupture_step, Sc, worst);
}

// A sphere (r = 1 mm) hanging on the lower end plate, 5 mm off the axis, by a wall bridge; the plate turns at
// 10 rad/s and gravity is along -y, in the plate's plane. At rest the plate's Hertz force balances the
// bridge's pull f0w = 2 pi (2r) gamma cos theta (§4; the Coulomb limits use |F_n| of §1 only, §0), so the
// contact can carry at most mu_s f0w along the plate and, since the friction force acts at the contact point
// (r - delta/2 from the centre), the rolling torque can balance at most m g (r - delta/2) <= mu_r r f0w: the
// sphere stays put on the plate iff m g < min(mu_s, mu_r) f0w (the centripetal 0.05 m/s^2 is within the
// margins used: 0.8 and 1.25).
struct PlateHold {
  double moved_m;  // distance from where the plate carried its starting point
  int64_t bridge;  // wall bridge at the end
  bool contact;    // touching the plate at the end
  int64_t film;    // film at the end
};

PlateHold hang_on_plate(const std::string& backend, double mu_s, double mu_r, double load_ratio,
                        bool plate_bridges, double T = 0.04) {
  SimParams prm = dry_params(1e7, 4e6, 0.5, 1e-5);
  prm.gravity = glm::dvec3(0.0, -9.81, 0.0);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, kVmax);
  prm.liq_pw[kWallPlateLo] = water(0, kVmax);
  prm.liq_pw[kWallPlateLo].enabled = plate_bridges;
  prm.pw[kWallPlateLo].mu_s = mu_s;
  prm.pw[kWallPlateLo].mu_r = mu_r;
  prm.drum.radius = 0.05;
  prm.drum.length = 0.02;
  prm.drum.omega = 10.0;
  prm.drum.plate_lo.present = prm.drum.plate_hi.present = true;
  prm.drum.plate_lo.rotates = prm.drum.plate_hi.rotates = true;

  const double f0w = 2.0 * kPi * (2.0 * kR) * 0.072 * std::cos(20.0 * kPi / 180.0);  // 8.5022e-4 N
  const double mass = load_ratio * std::min(mu_s, mu_r) * f0w / 9.81;
  const double rho = mass / (4.0 / 3.0 * kPi * kR * kR * kR);
  const glm::dvec3 x0(0.005, 0.0, -0.5 * prm.drum.length + kR);  // touching the plate (delta = 0)
  const glm::dvec3 W(0.0, 0.0, prm.drum.omega);
  SystemState s = empty_state(1);
  put_sphere(s, 0, x0, kR, rho, glm::cross(W, x0), W);  // turning with the plate
  s.p.film[0] = 4 * kVmax;
  WallRecord& wr = s.p.wall[kWallPlateLo];
  if (plate_bridges) {
    wr.bridge = kVmax;
    wr.flags = kFlagWasInContact;
  }
  auto b = make_backend(backend, prm, 1);
  b->set_state(s);
  const int n = int(std::lround(T / prm.dt));
  b->step(uint64_t(n));
  const SystemState st = b->state();
  const double a = prm.drum.omega * n * prm.dt;
  const glm::dvec3 carried(x0.x * std::cos(a) - x0.y * std::sin(a), x0.x * std::sin(a) + x0.y * std::cos(a),
                           x0.z);
  const double gap = (st.p.x[0].z + 0.5 * prm.drum.length) - kR;
  return {glm::length(glm::dvec2(st.p.x[0] - carried)), st.p.wall[kWallPlateLo].bridge, gap <= 0.0,
          st.p.film[0]};
}

// Rolling binds (mu_r 0.3 < mu_s 0.8, the demo's values): held at 0.8 of the limit for 0.4 rad of the plate's
// turn (4,000 steps of a sustained load); at 1.25 it rolls without slipping against the capped rolling
// torque: (m + I/r^2) a = m g - mu_r f0w, a = 0.2 g / 1.4 = 1.40 m/s^2, 1.12 mm in 0.04 s. On the GPU the
// held sphere must also sit where the double-precision reference puts it (float32 over a long hold, issue 12
// point 5).
TEST_P(WetHold, SphereOnRotatingPlateHeldIffTheRollingLimitCarriesIt) {
  const PlateHold held = hang_on_plate(GetParam(), 0.8, 0.3, 0.8, true);
  const PlateHold rolls = hang_on_plate(GetParam(), 0.8, 0.3, 1.25, true);
  std::printf("[%s] plate, rolling limit: held moved %.4e m, over-limit moved %.4e m\n", GetParam().c_str(),
              held.moved_m, rolls.moved_m);
  EXPECT_EQ(held.bridge, kVmax);
  EXPECT_TRUE(held.contact);
  EXPECT_LT(held.moved_m, 5e-6) << "a held sphere turns with the plate (elastic springs only, no creep)";
  EXPECT_EQ(rolls.bridge, kVmax) << "rolling down keeps the contact and its bridge";
  const double a = (9.81 - 9.81 / 1.25) / 1.4;
  EXPECT_NEAR(rolls.moved_m, 0.5 * a * 0.04 * 0.04, 0.05 * 0.5 * a * 0.04 * 0.04)
      << "beyond mu_r f0w the rolling spring is truncated and the sphere rolls down";
  if (GetParam() != "reference") {
    const PlateHold ref = hang_on_plate("reference", 0.8, 0.3, 0.8, true);
    EXPECT_NEAR(held.moved_m, ref.moved_m, 2e-8);
    std::printf("[%s] held sphere after 4,000 steps: %.3e m from the reference\n", GetParam().c_str(),
                std::fabs(held.moved_m - ref.moved_m));
  }
}

// Sliding binds (mu_s 0.3 < mu_r 1): held at 0.8 of mu_s f0w; at 1.25 it slides with a = g - mu_s f0w / m =
// 0.2 g (1.57 mm in 0.04 s; the sliding direction turns a little with the plate, hence 5 %). A Coulomb limit
// raised by the capillary pull (not §0) would hold it.
TEST_P(WetHold, SphereOnRotatingPlateHeldIffTheSlidingLimitCarriesIt) {
  const PlateHold held = hang_on_plate(GetParam(), 0.3, 1.0, 0.8, true);
  const PlateHold slides = hang_on_plate(GetParam(), 0.3, 1.0, 1.25, true);
  std::printf("[%s] plate, sliding limit: held moved %.4e m, over-limit moved %.4e m\n", GetParam().c_str(),
              held.moved_m, slides.moved_m);
  EXPECT_LT(held.moved_m, 5e-6);
  const double a = 9.81 - 9.81 / 1.25;
  EXPECT_NEAR(slides.moved_m, 0.5 * a * 0.04 * 0.04, 0.05 * 0.5 * a * 0.04 * 0.04);
}

// walls.plates.liquid_bridges = false (the closed drum case of issue 12): a wet sphere touching the plate
// forms no wall bridge, keeps its film, and with no normal force nothing holds it: it falls (~8 mm in 0.04
// s).
TEST_P(WetHold, NoPlateBridgeWhenThePlatesBridgesAreOff) {
  const PlateHold off = hang_on_plate(GetParam(), 0.8, 0.3, 0.8, false);
  EXPECT_EQ(off.bridge, 0);
  EXPECT_EQ(off.film, 4 * kVmax);
  EXPECT_GT(off.moved_m, 5e-3);
}

INSTANTIATE_TEST_SUITE_P(Backends, WetHold, ::testing::ValuesIn(backends()), BackendName());

}  // namespace
}  // namespace wetdem::test
