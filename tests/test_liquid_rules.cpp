// Liquid bridges and migration (§4-§5, §7 item 7 of physics.md): formation at first touch, lifetime and
// rupture, the A-B-C migration chain, a hanging sphere. Whole steps on every backend.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "reference/contact_law.h"
#include "reference/liquid_events.h"
#include "reference/scenario.h"
#include "support/backend.h"
#include "support/liquid_pair.h"

namespace wetdem::test {
namespace {

SimParams wet_params(int64_t v_min, int64_t v_max, double d_c = 1.0) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-6);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(v_min, v_max, d_c);
  return prm;
}

double gap_of(const SystemState& s, uint32_t i, uint32_t j) {
  return glm::length(s.p.x[i] - s.p.x[j]) - s.p.radius[i] - s.p.radius[j];
}

class Liquid : public ::testing::TestWithParam<std::string> {};

// §7.7: two spheres approach; the bridge appears at the end of the first step with delta >= 0, with
// V_b = min(V_f,i + V_f,j, V_max) drawn in proportion to the films; none when the films are <= V_min
// (the flag is still set).
TEST_P(Liquid, BridgeFormsAtFirstTouch) {
  struct Case {
    int64_t fa, fb, v_min, v_max;
    bool forms;
  };
  for (const Case c : {Case{300'000'000, 100'000'000, 100'000'000, kVmax, true},
                       Case{300'000'000, 100'000'000, 100'000'000, 200'000'000, true},
                       Case{50'000'000, 50'000'000, 100'000'000, kVmax, false}}) {
    const SimParams prm = wet_params(c.v_min, c.v_max);
    const double v = 0.01, g0 = 5.5 * v * prm.dt;  // closes 1e-8 m per step: touches in step 6
    SystemState s = empty_state(2);
    put_sphere(s, 0, glm::dvec3(-kR - 0.5 * g0, 0.0, 0.0), kR, kRho, glm::dvec3(0.5 * v, 0.0, 0.0));
    put_sphere(s, 1, glm::dvec3(kR + 0.5 * g0, 0.0, 0.0), kR, kRho, glm::dvec3(-0.5 * v, 0.0, 0.0));
    s.p.film[0] = c.fa;
    s.p.film[1] = c.fb;
    auto b = make_backend(GetParam(), prm, 2);
    b->set_state(s);
    int k = 0;
    SystemState st;
    for (; k < 20; ++k) {
      b->step(1);
      st = b->state();
      if (gap_of(st, 0, 1) <= 0.0) break;
      ASSERT_EQ(bridge_of(st, 0, 1), 0) << "no bridge before the touch";
      ASSERT_EQ(flags_of(st, 0, 1), 0u);
    }
    ASSERT_EQ(k, 5) << "touch expected in step 6";
    EXPECT_EQ(flags_of(st, 0, 1), uint32_t(kFlagWasInContact));
    EXPECT_EQ(liquid_sum(st), c.fa + c.fb);
    const EventCounts ev = b->read_events();
    if (!c.forms) {
      EXPECT_EQ(bridge_of(st, 0, 1), 0);
      EXPECT_EQ(st.p.film[0], c.fa);
      EXPECT_EQ(ev.formations, 0u);
      continue;
    }
    const int64_t vb = std::min(c.fa + c.fb, c.v_max);
    EXPECT_EQ(bridge_of(st, 0, 1), vb);
    EXPECT_EQ(ev.formations, 1u);
    const int64_t from_a = ref::split_proportional(vb, c.fa, c.fb, c.fa, c.fb);
    EXPECT_EQ(st.p.film[0], c.fa - from_a);
    EXPECT_EQ(st.p.film[1], c.fb - (vb - from_a));
    // In proportion to the films (3:1), to the unit of the 16-bit fraction.
    EXPECT_NEAR(double(from_a), 0.75 * double(vb), 1e-4 * double(vb));
  }
}

// §7.7: on separation the bridge lasts while S < S_c; in the step where S >= S_c its force still acts
// (the stored force of that step is the capillary force at that gap), then it ruptures into equal halves.
TEST_P(Liquid, BridgeLastsUntilRuptureDistance) {
  const SimParams prm = wet_params(0, kVmax);
  const int64_t vb = 400'000'001;  // odd: the lower id gets V_b/2 (floor), the other the rest
  const double v = 0.3;
  SystemState s = empty_state(2);
  put_sphere(s, 0, glm::dvec3(-kR, 0.0, 0.0), kR, kRho, glm::dvec3(-0.5 * v, 0.0, 0.0));
  put_sphere(s, 1, glm::dvec3(kR, 0.0, 0.0), kR, kRho, glm::dvec3(0.5 * v, 0.0, 0.0));
  s.pairs.push_back(bridge_record(0, 1, vb));
  auto b = make_backend(GetParam(), prm, 2);
  b->set_state(s);
  const double Sc = rupture_distance(prm.liq_pp.theta, double(vb) * prm.liquid_unit_m3);
  const double f0 = ref::pull_off_force(kR, prm.liq_pp.gamma, prm.liq_pp.theta);
  bool ruptured = false;
  for (int k = 0; k < 2000 && !ruptured; ++k) {
    b->step(1);
    const SystemState st = b->state();
    const double S = gap_of(st, 0, 1);
    if (S < Sc) {
      ASSERT_EQ(bridge_of(st, 0, 1), vb) << "bridge must last while S < S_c, S = " << S;
      continue;
    }
    ruptured = true;
    EXPECT_EQ(bridge_of(st, 0, 1), 0);
    EXPECT_EQ(flags_of(st, 0, 1), 0u);
    EXPECT_EQ(st.p.film[0], vb / 2);
    EXPECT_EQ(st.p.film[1], vb - vb / 2);
    const double v_rel = glm::length(st.p.v[0] - st.p.v[1]);
    EXPECT_LE(S - Sc, v_rel * prm.dt * 1.01) << "ruptured in the first step with S >= S_c";
    // The force of the rupture step: the capillary force at S, pulling 0 (at -x) towards 1.
    const double f = ref::capillary_force(f0, kR, double(vb) * prm.liquid_unit_m3, S);
    EXPECT_GT(f, 0.01 * f0);  // f(S_c)/f0 = 0.019 at this volume
    EXPECT_NEAR(st.p.f[0].x, f, 1e-4 * f);
    EXPECT_NEAR(st.p.f[1].x, -f, 1e-4 * f);
    const EventCounts ev = b->read_events();
    EXPECT_EQ(ev.ruptures, 1u);
    EXPECT_EQ(ev.formations, 0u);
  }
  EXPECT_TRUE(ruptured);
}

// §7.7 chain A-B-C (ids 0, 1, 2) along x, at rest, no gravity: A-B at a gap of 100 um, beyond S_c = 86.5 um
// of its 0.4 V_max but inside the interaction range S_c,max = 117 um (a state a run can reach), ruptures in
// the first step; B-C (gap 10 um) survives and takes B's half.
struct ChainResult {
  SystemState st;
  EventCounts ev;
  int64_t total_before;
};

ChainResult run_chain(const std::string& backend, double d_c, int64_t ab, int64_t bc) {
  const SimParams prm = wet_params(0, kVmax, d_c);
  SystemState s = empty_state(3);
  const glm::dvec3 xb(0.0);
  put_sphere(s, 1, xb, kR, kRho);
  put_sphere(s, 0, beside(xb, glm::dvec3(-1.0, 0.0, 0.0), 1e-4), kR, kRho);
  put_sphere(s, 2, beside(xb, glm::dvec3(1.0, 0.0, 0.0), 1e-5), kR, kRho);
  s.pairs.push_back(bridge_record(0, 1, ab));
  s.pairs.push_back(bridge_record(1, 2, bc));
  auto b = make_backend(backend, prm, 3);
  b->set_state(s);
  b->step(1);
  return {b->state(), b->read_events(), s.total_liquid()};
}

TEST_P(Liquid, ChainMigrationSection7Item7) {
  const int64_t V = kVmax;
  {  // d_c = 1, bridges 0.4 V_max: A's film gains 0.2 V_max, BC becomes 0.6 V_max.
    const ChainResult r = run_chain(GetParam(), 1.0, 4 * V / 10, 4 * V / 10);
    EXPECT_EQ(r.ev.ruptures, 1u);
    EXPECT_EQ(bridge_of(r.st, 0, 1), 0);
    EXPECT_EQ(r.st.p.film[0], 2 * V / 10);
    EXPECT_EQ(bridge_of(r.st, 1, 2), 6 * V / 10);
    EXPECT_EQ(r.st.p.film[1], 0);
    EXPECT_EQ(r.st.p.film[2], 0);
    EXPECT_EQ(r.st.total_liquid(), r.total_before);
  }
  {  // BC at 0.9 V_max: capped at V_max, B's film takes the 0.1 V_max overflow.
    const ChainResult r = run_chain(GetParam(), 1.0, 4 * V / 10, 9 * V / 10);
    EXPECT_EQ(bridge_of(r.st, 1, 2), V);
    EXPECT_EQ(r.st.p.film[1], V / 10);
    EXPECT_EQ(r.st.p.film[0], 2 * V / 10);
    EXPECT_EQ(r.st.total_liquid(), r.total_before);
  }
  {  // d_c = 0.8: A has no other bridge (all to its film); B gives 0.8 of its 0.2 V_max to BC, keeps the
     // rest: BC = 0.56 V_max, B's film 0.04 V_max, to the integer rule of "d_c h" (distribution_give: d_c in
     // steps of 2^-16, so within 2^-17 h + 1 unit of 0.8 h).
    const ChainResult r = run_chain(GetParam(), 0.8, 4 * V / 10, 4 * V / 10);
    const int64_t h = 2 * V / 10, give = ref::distribution_give(h, 0.8);
    EXPECT_NEAR(double(give), 0.8 * double(h), std::ldexp(double(h), -17) + 1.0);
    EXPECT_EQ(r.st.p.film[0], h);
    EXPECT_EQ(bridge_of(r.st, 1, 2), 4 * V / 10 + give);
    EXPECT_EQ(r.st.p.film[1], h - give);
    EXPECT_NEAR(double(bridge_of(r.st, 1, 2)), 0.56 * double(V), 1e-5 * double(V));
    EXPECT_NEAR(double(r.st.p.film[1]), 0.04 * double(V), 1e-5 * double(V));
    EXPECT_EQ(r.st.total_liquid(), r.total_before);
  }
}

// §7.7 with wall bridges. The drum (R = 1 cm) has a lo plate at z = -L/2; the cylinder and the plate take
// bridges. B (id 1) sits at the bottom of the drum against the plate.
//  (a) B also holds a plate bridge; A-B ruptures: B's half goes to B-C only (particle-particle ruptures share
//      over particle-particle bridges), the plate bridge is untouched.
//  (b) B's plate bridge ruptures (gap 100 um > S_c = 86.5 um); B holds A-B, B-C and a cylinder bridge, 0.4
//  V_max each:
//      the whole V_b goes to B and is shared over all three (wall bridges counted too), the odd unit to B's
//      film.
TEST_P(Liquid, ChainMigrationWithWallBridges) {
  const int64_t V = kVmax, b4 = 4 * V / 10;
  for (bool wall_rupture : {false, true}) {
    SimParams prm = wet_params(0, kVmax);
    prm.drum.radius = 0.01;
    prm.drum.length = 0.02;
    prm.drum.plate_lo.present = true;
    prm.drum.plate_lo.rotates = false;
    prm.liq_pw[kWallCylinder] = water(0, kVmax);
    prm.liq_pw[kWallPlateLo] = water(0, kVmax);
    SystemState s = empty_state(3);
    const double zb = -0.5 * prm.drum.length + kR + (wall_rupture ? 1e-4 : 0.0);
    const glm::dvec3 xb(0.0, -(prm.drum.radius - kR) + (wall_rupture ? 0.0 : 5e-4), zb);
    put_sphere(s, 1, xb, kR, kRho);
    // A and C above B (towards the axis), away from the cylinder; in (b) at B's height over the plate (no
    // touch).
    const glm::dvec3 up = wall_rupture ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
    put_sphere(s, 0, beside(xb, glm::dvec3(-0.866, 0.0, 0.0) + 0.5 * up, wall_rupture ? 1e-5 : 1e-4), kR,
               kRho);
    put_sphere(s, 2, beside(xb, glm::dvec3(0.866, 0.0, 0.0) + 0.5 * up, 1e-5), kR, kRho);
    s.pairs.push_back(bridge_record(0, 1, b4));
    s.pairs.push_back(bridge_record(1, 2, b4));
    WallRecord& plate = s.p.wall[1 * kNumWalls + kWallPlateLo];
    plate.bridge = b4;
    plate.flags = kFlagWasInContact;
    if (wall_rupture) {
      WallRecord& cyl = s.p.wall[1 * kNumWalls + kWallCylinder];
      cyl.bridge = b4;
      cyl.flags = kFlagWasInContact;
    }
    auto b = make_backend(GetParam(), prm, 3);
    b->set_state(s);
    b->step(1);
    const SystemState st = b->state();
    const EventCounts ev = b->read_events();
    EXPECT_EQ(ev.ruptures, 1u);
    EXPECT_EQ(ev.formations, 0u);
    EXPECT_EQ(st.total_liquid(), s.total_liquid());
    if (!wall_rupture) {
      EXPECT_EQ(bridge_of(st, 0, 1), 0);
      EXPECT_EQ(st.p.film[0], 2 * V / 10);
      EXPECT_EQ(bridge_of(st, 1, 2), 6 * V / 10);
      EXPECT_EQ(st.p.wall[1 * kNumWalls + kWallPlateLo].bridge, b4);
      EXPECT_EQ(st.p.film[1], 0);
    } else {
      const int64_t per = b4 / 3;  // 133333333
      EXPECT_EQ(st.p.wall[1 * kNumWalls + kWallPlateLo].bridge, 0);
      EXPECT_EQ(st.p.wall[1 * kNumWalls + kWallPlateLo].flags, 0u);
      EXPECT_EQ(bridge_of(st, 0, 1), b4 + per);
      EXPECT_EQ(bridge_of(st, 1, 2), b4 + per);
      EXPECT_EQ(st.p.wall[1 * kNumWalls + kWallCylinder].bridge, b4 + per);
      EXPECT_EQ(st.p.film[1], b4 - 3 * per);
      EXPECT_EQ(st.p.film[0], 0);
    }
  }
}

// A sphere hanging under a fixed sphere by a bridge (V_b = 1e-12 m^3, f0 = 4.2511e-4 N), gravity -y. The
// upper sphere is held: it has a huge mass (the bridge cannot move it) and after every step (every 10 steps
// while the gap is below 0.8 S_c) its position is reset and its velocity zeroed (gravity alone moves it by
// 2e-9 m in 10 steps).
//  - rho = 2500: m g = 1.03e-4 N < f0, the sphere stays attached (touching, bridge intact, at rest after 12
//  ms).
//  - rho = 15000: m g = 6.16e-4 N > f0, it falls away and the bridge ruptures in the first step with S >=
//  S_c,
//    so S_c <= S_rupture <= S_c + v dt.
TEST_P(Liquid, HangingSphere) {
  for (double rho : {2500.0, 15000.0}) {
    SimParams prm = wet_params(0, 2 * kVmax);
    prm.pp.E_star = 1e8;
    prm.pp.restitution = 0.3;
    prm.dt = 2e-6;
    prm.gravity = glm::dvec3(0.0, -9.81, 0.0);
    SystemState s = empty_state(2);
    const glm::dvec3 x0(0.0);
    put_sphere(s, 0, x0, kR, kRho);
    s.p.mass[0] = 1e20;
    s.p.inertia[0] = 1e20;
    put_sphere(s, 1, glm::dvec3(0.0, -2.0 * kR, 0.0), kR, rho);
    s.pairs.push_back(bridge_record(0, 1, kVmax));
    const bool falls = s.p.mass[1] * 9.81 > 4.2511e-4;
    ASSERT_EQ(falls, rho > 5000.0);
    auto b = make_backend(GetParam(), prm, 2);
    b->set_state(s);
    const double Sc = rupture_distance(prm.liq_pp.theta, double(kVmax) * prm.liquid_unit_m3);
    EXPECT_NEAR(Sc, 1.17453e-4, 1e-9);
    // Steps of 10 (holding the upper sphere after each) while far from S_c, single steps near it.
    bool ruptured = false;
    SystemState st;
    double S = 0.0;
    int steps = 0;
    while (steps < 6000 && !ruptured) {
      const int chunk = S < 0.8 * Sc ? 10 : 1;
      b->step(chunk);
      steps += chunk;
      st = b->state();
      S = gap_of(st, 0, 1);
      if (bridge_of(st, 0, 1) == 0) {
        ruptured = true;
        ASSERT_EQ(chunk, 1);
        EXPECT_GE(S, Sc);
        EXPECT_LE(S - Sc, std::fabs(st.p.v[1].y) * prm.dt * 1.01) << "rupture must happen at S_c";
        EXPECT_EQ(st.p.film[0] + st.p.film[1], kVmax);
      } else {
        ASSERT_LT(S, Sc);
      }
      st.p.x[0] = x0;
      st.p.v[0] = glm::dvec3(0.0);
      st.p.w[0] = glm::dvec3(0.0);
      b->set_state(st);
    }
    std::cout << "hanging sphere, rho = " << rho << ": " << (ruptured ? "ruptured" : "attached") << " after "
              << steps << " steps, gap " << S << " m\n";
    if (falls) {
      EXPECT_TRUE(ruptured) << "the heavy sphere must fall away";
      EXPECT_LT(st.p.v[1].y, 0.0);
    } else {
      EXPECT_FALSE(ruptured) << "the light sphere must stay attached";
      EXPECT_LE(gap_of(st, 0, 1), 0.0);
      EXPECT_LT(glm::length(st.p.v[1]), 1e-4);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, Liquid, ::testing::ValuesIn(backends()), BackendName());

}  // namespace
}  // namespace wetdem::test
