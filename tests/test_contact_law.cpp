// Analytic checks of the contact laws (§1-§4, §6, §7 items 1, 2, 4, 5, 6 of physics.md). Pure formulas
// call tests/reference/contact_law.h; whole-step scenarios run on every backend.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "reference/contact_law.h"
#include "reference/scenario.h"
#include "support/backend.h"

namespace wetdem::test {
namespace {

using ref::ContactHistory;
using ref::ContactKinematics;

// ---- §1 Hertz, by hand: E* = 5 MPa, r = 1 mm (R* = 0.5 mm), delta = 10 um:
// k_n = (4/3) 5e6 sqrt(0.5e-3 * 1e-5) = 471.4045 N/m, F_n = k_n delta = 4.714045e-3 N.
// With e = 0.5: phi_n = 0.4817693, m* = 5.235988e-6 kg, eta_n = phi_n sqrt(m* k_n) = 2.393510e-2 kg/s,
// approaching at v_n = -0.01 m/s: F_n = 4.714045e-3 + 2.393510e-4 = 4.953396e-3 N.
TEST(ContactLaw, HertzNormalForceByHand) {
  ContactParams cp;
  cp.E_star = 5e6;
  cp.restitution = 0.5;
  EXPECT_NEAR(ref::hertz_stiffness(5e6, 0.5e-3, 1e-5), 471.40452, 1e-4);
  EXPECT_NEAR(damping_factor(0.5), 0.48176926, 1e-8);
  const double m_star = 0.5 * 2500.0 * 4.0 / 3.0 * kPi * 1e-9;
  EXPECT_NEAR(ref::hertz_normal_force(cp, 0.5e-3, m_star, 1e-5, 0.0), 4.714045e-3, 1e-9);
  EXPECT_NEAR(ref::hertz_normal_force(cp, 0.5e-3, m_star, 1e-5, -0.01), 4.953396e-3, 1e-9);
  // §1: not clipped: separating fast at small overlap gives an attractive (negative) F_n.
  EXPECT_LT(ref::hertz_normal_force(cp, 0.5e-3, m_star, 1e-9, 1.0), 0.0);
  // phi_n(0) = sqrt(5), phi_n(1) = 0.
  EXPECT_DOUBLE_EQ(damping_factor(0.0), std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(damping_factor(1.0), 0.0);
}

// Whole step, both backends: two resting spheres overlapping by 10 um along x (i = id 0 on the +x side), with
// a stored tangential spring xi = 1e-7 m along y and mu_s = 0.5 (sticking). By hand (G* = 2 MPa): k_t = 8 G*
// sqrt(R* delta) = 1131.371 N/m, F_t = -(2/3) k_t xi = -7.542472e-5 N along y; F on i = (4.714045e-3,
// -7.542472e-5, 0); c - x_i = -(r - delta/2) x = -9.95e-4 x, so T_i = (c - x_i) x F = (0, 0, 7.504760e-8) N
// m, and T_j = -(c - x_j) x F = the same (c - x_j = +9.95e-4 x).
class Hertz : public ::testing::TestWithParam<std::string> {};

TEST_P(Hertz, ForceAndTorqueByHand) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-7);
  prm.pp.mu_s = 0.5;
  const double r = 1e-3, delta = 1e-5;
  SystemState s = empty_state(2);
  put_sphere(s, 0, glm::dvec3(r - 0.5 * delta, 0.0, 0.0), r, 2500.0);
  put_sphere(s, 1, glm::dvec3(-r + 0.5 * delta, 0.0, 0.0), r, 2500.0);
  PairRecord rec;
  rec.id_i = 0;
  rec.id_j = 1;
  rec.spring_t = glm::dvec3(0.0, 1e-7, 0.0);
  s.pairs.push_back(rec);
  auto b = make_backend(GetParam(), prm, 2);
  b->set_state(s);
  b->step(1);  // F = 0 and v = 0 before the step: nothing moves, forces are those of the initial geometry
  const SystemState st = b->state();
  const double tol_f = 1e-6 * 4.714045e-3;
  EXPECT_NEAR(st.p.f[0].x, 4.714045e-3, tol_f);
  EXPECT_NEAR(st.p.f[0].y, -7.542472e-5, tol_f);
  EXPECT_NEAR(st.p.f[0].z, 0.0, tol_f);
  EXPECT_NEAR(st.p.f[1].x, -4.714045e-3, tol_f);
  EXPECT_NEAR(st.p.f[1].y, 7.542472e-5, tol_f);
  const double tol_t = 1e-6 * 7.504760e-8;
  EXPECT_NEAR(st.p.t[0].z, 7.504760e-8, tol_t);
  EXPECT_NEAR(st.p.t[1].z, 7.504760e-8, tol_t);
  EXPECT_NEAR(st.p.t[0].x, 0.0, tol_t);
  EXPECT_NEAR(st.p.t[0].y, 0.0, tol_t);
}

INSTANTIATE_TEST_SUITE_P(Backends, Hertz, ::testing::ValuesIn(backends()), BackendName());

// ---- §6 / §7.6 Rayleigh time: r = 1 mm, rho = 2500, E = 1e7, nu = 0.3, G = E/(2(1+nu)) = 3.846e6 Pa.
TEST(ContactLaw, RayleighTime) {
  const double G = 1e7 / (2.0 * 1.3);
  EXPECT_NEAR(G, 3.846e6, 1e3);
  EXPECT_NEAR(rayleigh_time(1e-3, 2500.0, G, 0.3), 8.654e-5, 0.0005e-5);
}

// ---- §7.1 pull-off force: equal spheres r = 1 mm (R_h = 1 mm), gamma = 0.072, theta = 20 deg.
TEST(Capillary, PullOffForceSection7Item1) {
  const LiquidParams l = water(0, 1);
  const double r = 1e-3;
  const double f0 = ref::pull_off_force(ref::harmonic_radius(r, r), l.gamma, l.theta);
  EXPECT_NEAR(f0, 4.2511e-4, 0.00005e-4);
  // Sphere-wall: R_h = 2 r_i doubles f0.
  EXPECT_NEAR(ref::pull_off_force(2.0 * r, l.gamma, l.theta), 2.0 * 4.2511e-4, 0.0001e-4);
  // f = f0 at any overlap (delta >= 0), whatever the volume.
  EXPECT_DOUBLE_EQ(ref::capillary_force(f0, 1e-3, 1e-12, 0.0), f0);
  EXPECT_DOUBLE_EQ(ref::capillary_force(f0, 1e-3, 1e-12, -1e-5), f0);
  EXPECT_DOUBLE_EQ(ref::capillary_force(f0, 1e-3, 0.0, 1e-6), 0.0);
}

// ---- §7.2 rupture distance: same spheres, V_b = 1e-12 m^3.
TEST(Capillary, RuptureDistanceSection7Item2) {
  const LiquidParams l = water(0, 1);
  const double V = 1e-12, R_h = 1e-3;
  const double Sc = rupture_distance(l.theta, V);
  EXPECT_NEAR(Sc, 1.17453e-4, 0.000005e-4);
  EXPECT_NEAR(Sc * std::sqrt(R_h / V), 3.7142, 0.00005);
  const double f0 = ref::pull_off_force(R_h, l.gamma, l.theta);
  EXPECT_NEAR(ref::capillary_force(f0, R_h, V, Sc) / f0, 0.025388, 0.0000005);
}

// Whole step, both backends: a bridge at delta = 0 pulls with f0 between two spheres and with 2 f0 between a
// sphere and a plate (R_h = 2 r_i), along the normal (attraction).
class PullOff : public ::testing::TestWithParam<std::string> {};

TEST_P(PullOff, PairAndWallAtContact) {
  SimParams prm = dry_params(5e6, 2e6, 0.5, 1e-7);
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, 2'000'000'000);
  prm.drum.radius = 0.02;
  prm.drum.length = 0.02;
  prm.drum.plate_lo.present = true;
  prm.drum.plate_lo.rotates = false;
  prm.liq_pw[kWallPlateLo] = water(0, 2'000'000'000);
  const double r = 1e-3;
  SystemState s = empty_state(3);
  put_sphere(s, 0, glm::dvec3(r, 0.0, 0.0), r, 2500.0);
  put_sphere(s, 1, glm::dvec3(-r, 0.0, 0.0), r, 2500.0);
  put_sphere(s, 2, glm::dvec3(0.005, 0.0, -0.01 + r), r, 2500.0);  // on the lo plate
  PairRecord rec;
  rec.id_i = 0;
  rec.id_j = 1;
  rec.bridge = 1'000'000'000;  // 1e-12 m^3
  rec.flags = kFlagWasInContact;
  s.pairs.push_back(rec);
  s.p.wall[2 * kNumWalls + kWallPlateLo].bridge = 1'000'000'000;
  s.p.wall[2 * kNumWalls + kWallPlateLo].flags = kFlagWasInContact;
  auto b = make_backend(GetParam(), prm, 3);
  b->set_state(s);
  b->step(1);
  const SystemState st = b->state();
  const double f0 = 4.2511e-4;
  EXPECT_NEAR(st.p.f[0].x, -f0, 1e-3 * f0);  // on i (+x side), towards j
  EXPECT_NEAR(st.p.f[1].x, f0, 1e-3 * f0);
  EXPECT_NEAR(st.p.f[2].z, -2.0 * f0, 2e-3 * f0);  // towards the plate
  EXPECT_EQ(bridge_of(st, 0, 1), 1'000'000'000);
  EXPECT_EQ(st.p.wall[2 * kNumWalls + kWallPlateLo].bridge, 1'000'000'000);
}

INSTANTIATE_TEST_SUITE_P(Backends, PullOff, ::testing::ValuesIn(backends()), BackendName());

// ---- §7.4 sliding friction (Mindlin with history), on the law itself: delta and F_n fixed.
struct SlidingSetup {
  ContactParams cp;
  double k_t, f_n, m_star = 1e-5;
  glm::dvec3 n{1.0, 0.0, 0.0};
  SlidingSetup() {
    cp.G_star = 2e6;
    cp.mu_s = 0.3;
    k_t = ref::tangential_stiffness(cp.G_star, 0.5e-3, 1e-5);
    f_n = 4.714045e-3;
  }
};

TEST(Sliding, InitialSlopeSaturationAndReversal) {
  SlidingSetup su;
  const double dt = 1e-6, v = 0.01;  // tangential displacement v dt = 1e-8 m per step
  const glm::dvec3 vt(0.0, v, 0.0);
  const double limit = su.cp.mu_s * su.f_n;
  glm::dvec3 xi(0.0);
  // Initial slope: |F_t| grows by (2/3) k_t per metre of tangential displacement.
  glm::dvec3 f_prev = ref::sliding_friction(su.cp, su.k_t, su.m_star, su.f_n, su.n, vt, dt, xi);
  EXPECT_NEAR(-f_prev.y / (v * dt), 2.0 / 3.0 * su.k_t, 1e-9 * su.k_t);
  const glm::dvec3 f_next = ref::sliding_friction(su.cp, su.k_t, su.m_star, su.f_n, su.n, vt, dt, xi);
  EXPECT_NEAR(-(f_next.y - f_prev.y) / (v * dt), 2.0 / 3.0 * su.k_t, 1e-6 * su.k_t);
  // Saturation at mu_s |F_n|, opposing the motion, for as long as the motion goes on.
  glm::dvec3 f(0.0);
  int steps_to_slide = 0;
  for (int k = 0; k < 2000; ++k) {
    f = ref::sliding_friction(su.cp, su.k_t, su.m_star, su.f_n, su.n, vt, dt, xi);
    ASSERT_LE(glm::length(f), limit * (1.0 + 1e-12));
    if (steps_to_slide == 0 && glm::length(f) >= limit * (1.0 - 1e-12)) steps_to_slide = k + 3;
  }
  EXPECT_GT(steps_to_slide, 0);
  EXPECT_NEAR(f.y, -limit, 1e-12 * limit);
  // Truncated spring: |xi| = mu_s |F_n| / ((2/3) k_t), not the 2000+ steps of displacement.
  EXPECT_NEAR(glm::length(xi), limit / (2.0 / 3.0 * su.k_t), 1e-12);
  // Reversal starts from the truncated spring: the first reverse step lowers |F_t| by (2/3) k_t v dt, and the
  // force reaches -limit after 2 limit / ((2/3) k_t v dt) steps (plus one for rounding).
  const glm::dvec3 f_rev = ref::sliding_friction(su.cp, su.k_t, su.m_star, su.f_n, su.n, -vt, dt, xi);
  EXPECT_NEAR(f_rev.y, -limit + 2.0 / 3.0 * su.k_t * v * dt, 1e-9 * limit);
  const double steps_back = 2.0 * limit / (2.0 / 3.0 * su.k_t * v * dt);
  int k = 1;
  glm::dvec3 fr = f_rev;
  while (fr.y < limit * (1.0 - 1e-12) && k < 10000) {
    fr = ref::sliding_friction(su.cp, su.k_t, su.m_star, su.f_n, su.n, -vt, dt, xi);
    ++k;
  }
  EXPECT_NEAR(double(k), steps_back, 1.01);
}

// §7.4: a rigid rotation of a touching pair (both spheres turning with Omega about the pair's centre, spins
// = Omega) gives v_t = 0 at the contact, and rotating xi into the new tangent plane keeps |xi|: after a full
// turn the spring has the same length and is still tangent.
TEST(Sliding, RigidRotationKeepsSpringLength) {
  ContactParams cp;
  cp.E_star = 5e6;
  cp.G_star = 2e6;
  cp.mu_s = 10.0;  // far from sliding: only the rotation acts on the spring
  const double r = 1e-3, delta = 1e-5, m = 1e-5;
  const glm::dvec3 Omega(0.3, -0.2, 1.0);
  const glm::dvec3 axis = glm::normalize(Omega);
  const double wmag = glm::length(Omega);
  const double dt = 2.0 * kPi / (wmag * 2000.0);  // a full turn in 2000 steps
  const glm::dvec3 e0 = glm::normalize(glm::cross(axis, glm::dvec3(1.0, 0.0, 0.0)));
  ContactHistory h;
  h.spring_t = 3e-7 * glm::normalize(glm::cross(axis, e0)) + 1e-7 * axis;  // tangent to n = e0
  const double len0 = glm::length(h.spring_t);
  const int steps = int(std::ceil(2.0 * kPi / (wmag * dt)));
  for (int k = 1; k <= steps; ++k) {
    const double a = wmag * dt * k;
    // e(a) = e0 rotated by a about the axis (Rodrigues; e0 is perpendicular to the axis).
    const glm::dvec3 e = std::cos(a) * e0 + std::sin(a) * glm::cross(axis, e0);
    const glm::dvec3 xi = 0.5 * (2.0 * r - delta) * e, xj = -xi;  // centre of rotation at the origin
    const ContactKinematics kin =
        ref::pair_kinematics(xi - xj, r, r, m, m, glm::cross(Omega, xi), glm::cross(Omega, xj), Omega, Omega);
    ASSERT_LT(glm::length(kin.v_rel), 1e-15);
    ref::evaluate_contact(cp, LiquidParams{}, 1e-21, 0.0, dt, kin, h);
    ASSERT_NEAR(glm::length(h.spring_t), len0, 1e-12 * len0) << "step " << k;
    ASSERT_NEAR(glm::dot(h.spring_t, kin.n), 0.0, 1e-12 * len0);
  }
}

// ---- §7.5 rolling resistance: the pure torque never exceeds mu_r R* |F_n|, under random spin histories.
TEST(Rolling, TorqueNeverExceedsLimit) {
  ContactParams cp;
  cp.mu_r = 0.05;
  cp.eta_r = 1e-4;
  const double R_star = 0.5e-3, f_n = 4.714045e-3, dt = 1e-6;
  const double k_t = ref::tangential_stiffness(2e6, R_star, 1e-5);
  const double limit = cp.mu_r * R_star * f_n;
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 50.0);
  glm::dvec3 n(0.0, 1.0, 0.0), xi(0.0);
  int capped = 0;
  for (int k = 0; k < 5000; ++k) {
    if (k % 100 == 0)
      n = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));  // the contact turns now and then
    const glm::dvec3 w(g(rng), g(rng), g(rng));
    const glm::dvec3 t = ref::rolling_torque(cp, k_t, R_star, f_n, n, w, dt, xi);
    ASSERT_LE(glm::length(t), limit * (1.0 + 1e-12)) << "step " << k;
    ASSERT_NEAR(glm::dot(t, n), 0.0, 1e-12 * limit);  // rolling, not torsion
    if (glm::length(t) > limit * (1.0 - 1e-9)) ++capped;
  }
  EXPECT_GT(capped, 100);  // the cap was reached, so the bound was exercised
}

// §7.5 whole step, both backends: a sphere resting on the bottom of the turning drum and co-rotating with it
// (v = Omega z x x, omega = Omega z) feels no rolling torque: v_r = -R* n x (omega - Omega z) = 0. Sliding
// friction is off so that nothing else changes its spin. A sphere that does not spin feels the capped torque.
class RollingWall : public ::testing::TestWithParam<std::string> {};

TEST_P(RollingWall, CoRotatingSphereFeelsNoRollingTorque) {
  for (bool corotating : {true, false}) {
    SimParams prm = dry_params(5e6, 2e6, 0.5, 2e-6);
    prm.gravity = glm::dvec3(0.0, -9.81, 0.0);
    prm.drum.radius = 0.01;
    prm.drum.length = 0.1;
    prm.drum.omega = 2.0;
    for (auto& w : prm.pw) w.mu_r = 0.1;
    const double r = 1e-3, rho = 2500.0;
    SystemState s = empty_state(1);
    const glm::dvec3 x(0.0, -(prm.drum.radius - r), 0.0);
    const glm::dvec3 W(0.0, 0.0, prm.drum.omega);
    put_sphere(s, 0, x, r, rho, glm::cross(W, x), corotating ? W : glm::dvec3(0.0));
    auto b = make_backend(GetParam(), prm, 1);
    b->set_state(s);
    double max_t = 0.0, max_cap = 0.0;
    int touching = 0;
    for (int k = 0; k < 300; ++k) {
      b->step(1);
      const SystemState st = b->state();
      const double delta = r - (prm.drum.radius - glm::length(glm::dvec2(st.p.x[0])));
      const double m = st.p.mass[0];
      max_cap = std::max(max_cap, 0.1 * r * m * 9.81 * 10.0);  // generous: |F_n| stays ~ m g
      if (delta > 0.0) {
        ++touching;
        max_t = std::max(max_t, glm::length(st.p.t[0]));
      }
    }
    ASSERT_GT(touching, 100) << "the sphere must rest on the wall";
    if (corotating) {
      EXPECT_LE(max_t, 1e-6 * max_cap) << "co-rotating sphere felt a rolling torque";
    } else {
      EXPECT_GT(max_t, 1e-3 * max_cap) << "a sphere not spinning with the drum must feel rolling resistance";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, RollingWall, ::testing::ValuesIn(backends()), BackendName());

}  // namespace
}  // namespace wetdem::test
