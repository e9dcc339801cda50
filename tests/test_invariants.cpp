// Invariants of whole runs, on every backend: energy of an elastic frictionless gas, momentum of an isolated
// system, a packed bed staying at rest, exact liquid conservation in a tumbling wet packing (§5, §7.8).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "reference/contact_law.h"
#include "reference/scenario.h"
#include "support/backend.h"

namespace wetdem::test {
namespace {

class Invariants : public ::testing::TestWithParam<std::string> {};

// Spheres of radius r on a cubic lattice of spacing `spacing` inside a drum (cylinder radius R, |z| < L/2),
// keeping `margin` from every wall; at most n of them.
std::vector<glm::dvec3> lattice_in_drum(const DrumParams& d, double r, double spacing, double margin,
                                        size_t n, double y_max = 1e9) {
  std::vector<glm::dvec3> out;
  const int m = int(d.radius / spacing) + 1;
  const int mz = int(0.5 * d.length / spacing) + 1;
  for (int iy = -m; iy <= m; ++iy)
    for (int iz = -mz; iz <= mz; ++iz)
      for (int ix = -m; ix <= m; ++ix) {
        const glm::dvec3 x(ix * spacing, iy * spacing, iz * spacing + (d.periodic_z ? 0.25 * spacing : 0.0));
        if (out.size() >= n || x.y > y_max) continue;
        if (std::sqrt(x.x * x.x + x.y * x.y) > d.radius - r - margin) continue;
        if (std::fabs(x.z) > 0.5 * d.length - r - margin) continue;
        out.push_back(x);
      }
  return out;
}

// Kinetic energy plus the elastic energy of every Hertz contact (pairs and walls), §1.
double total_energy(const SystemState& s, const SimParams& prm) {
  double e = kinetic_energy(s);
  const size_t n = s.p.size();
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const double ri = s.p.radius[i], rj = s.p.radius[j];
      const double delta = ri + rj - glm::length(s.p.x[i] - s.p.x[j]);
      if (delta > 0.0) e += ref::hertz_energy(prm.pp.E_star, ri * rj / (ri + rj), delta);
    }
    const glm::dvec3& x = s.p.x[i];
    const double r = s.p.radius[i];
    const double dc = r - (prm.drum.radius - std::sqrt(x.x * x.x + x.y * x.y));
    if (dc > 0.0) e += ref::hertz_energy(prm.pw[kWallCylinder].E_star, r, dc);
    const double dlo = r - (x.z + 0.5 * prm.drum.length), dhi = r - (0.5 * prm.drum.length - x.z);
    if (dlo > 0.0) e += ref::hertz_energy(prm.pw[kWallPlateLo].E_star, r, dlo);
    if (dhi > 0.0) e += ref::hertz_energy(prm.pw[kWallPlateHi].E_star, r, dhi);
  }
  return e;
}

// Elastic frictionless gas (e = 1 so phi_n = 0, mu = 0, no gravity) of 200 spheres (r = 0.5 mm) in a closed
// drum with fixed plates: kinetic + Hertz energy within 1e-3 over 1e4 steps (dt = t_c/50 at the rms speed).
TEST_P(Invariants, ElasticGasKeepsEnergy) {
  SimParams prm = dry_params(5e6, 2e6, 1.0, 2e-6);
  prm.drum.radius = 0.005;
  prm.drum.length = 0.01;
  prm.drum.plate_lo = {true, false};
  prm.drum.plate_hi = {true, false};
  const double r = 0.5e-3;
  const auto pos = lattice_in_drum(prm.drum, r, 1.25e-3, 1e-4, 200);
  ASSERT_EQ(pos.size(), 200u);
  SystemState s = empty_state(pos.size());
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 0.5);
  for (size_t k = 0; k < pos.size(); ++k)
    put_sphere(s, k, pos[k], r, 2500.0, glm::dvec3(g(rng), g(rng), g(rng)),
               glm::dvec3(g(rng), g(rng), g(rng)) * 100.0);
  auto b = make_backend(GetParam(), prm, s.p.size());
  b->set_state(s);
  const double e0 = total_energy(s, prm);
  double worst = 0.0;
  uint64_t contacts_seen = 0;
  for (int block = 0; block < 20; ++block) {
    b->step(500);
    const SystemState st = b->state();
    worst = std::max(worst, std::fabs(total_energy(st, prm) - e0) / e0);
    for (size_t i = 0; i < st.p.size(); ++i) contacts_seen += glm::length(st.p.f[i]) > 0.0 ? 1 : 0;
  }
  std::cout << "elastic gas: max relative energy error " << worst << " (" << contacts_seen
            << " particle samples under load)\n";
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(contacts_seen, 0u);
}

// An isolated system (no walls within reach, no gravity) of 60 wet, frictional, damped spheres thrown
// together: linear and angular momentum (about the origin, spins included) are conserved to round-off, since
// every pair force is equal and opposite and T_i + T_j + x_i x F - x_j x F = 0 (§0).
TEST_P(Invariants, IsolatedSystemConservesMomentum) {
  SimParams prm = dry_params(5e6, 2e6, 0.3, 2e-6);
  prm.pp.mu_s = 0.5;
  prm.pp.mu_r = 0.1;
  prm.pp.phi_t = 0.2;
  prm.pp.eta_r = 1e-6;
  prm.liquid_unit_m3 = 1e-21;
  prm.liq_pp = water(0, 100'000'000);
  const double r = 1e-3;
  DrumParams box;
  box.radius = 0.006;
  box.length = 0.012;
  const auto pos = lattice_in_drum(box, r, 2.05e-3, 0.0, 60);
  ASSERT_EQ(pos.size(), 60u);
  SystemState s = empty_state(pos.size());
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 0.05);
  const glm::dvec3 offset(0.003, -0.002, 0.001);
  for (size_t k = 0; k < pos.size(); ++k) {
    const glm::dvec3 x = pos[k] + offset;
    put_sphere(s, k, x, r * (0.8 + 0.004 * double(k % 50)), 2500.0,
               -30.0 * (x - offset) + glm::dvec3(g(rng), g(rng), g(rng)),
               glm::dvec3(g(rng), g(rng), g(rng)) * 100.0);
    s.p.film[k] = 50'000'000;
  }
  auto momenta = [](const SystemState& st, glm::dvec3& P, glm::dvec3& L, double& scale_p, double& scale_l) {
    P = L = glm::dvec3(0.0);
    scale_p = scale_l = 0.0;
    for (size_t k = 0; k < st.p.size(); ++k) {
      P += st.p.mass[k] * st.p.v[k];
      L += st.p.mass[k] * glm::cross(st.p.x[k], st.p.v[k]) + st.p.inertia[k] * st.p.w[k];
      scale_p += st.p.mass[k] * glm::length(st.p.v[k]);
      scale_l += st.p.mass[k] * glm::length(st.p.x[k]) * glm::length(st.p.v[k]) +
                 st.p.inertia[k] * glm::length(st.p.w[k]);
    }
  };
  glm::dvec3 P0, L0;
  double sp0, sl0;
  momenta(s, P0, L0, sp0, sl0);
  auto b = make_backend(GetParam(), prm, s.p.size());
  b->set_state(s);
  const int steps = 3000;
  b->step(steps);
  const SystemState st = b->state();
  glm::dvec3 P, L;
  double sp, sl;
  momenta(st, P, L, sp, sl);
  const EventCounts ev = b->read_events();
  std::cout << "isolated system: " << st.pairs.size() << " pair records, " << ev.formations
            << " formations, |dP|/scale " << glm::length(P - P0) / sp0 << ", |dL|/scale "
            << glm::length(L - L0) / sl0 << "\n";
  EXPECT_GT(ev.formations, 20u);  // the spheres did collide
  // Round-off grows with the number of force evaluations summed; allow 1e3 ulps of the momentum scale.
  const double eps = 1e3 * unit_roundoff(GetParam());
  EXPECT_LT(glm::length(P - P0), eps * sp0);
  EXPECT_LT(glm::length(L - L0), eps * sl0);
}

// A small frictional bed at rest in the drum (gravity, e = 0.3, mu_s = 0.5, mu_r = 0.1) stays at rest: over
// 0.05 s the largest speed stays below 1e-4 of what free fall would reach (4.9e-5 m/s).
// The bed is settled once, by the CPU reference, and the same settled state (positions, springs, last forces)
// goes to every backend: settling is chaotic (a sphere perched on top may take a long time to roll off), so
// settling on each backend would test the path, not the rest. Settling: 0.1 s free, then every millisecond
// all velocities are halved until the largest speed has stayed below 1e-7 m/s for 10 ms in a row.
SystemState settled_bed(const SimParams& prm) {
  const double r = 1e-3;
  const auto pos = lattice_in_drum(prm.drum, r, 2.1e-3, 5e-5, 30);
  SystemState s = empty_state(pos.size());
  for (size_t k = 0; k < pos.size(); ++k) put_sphere(s, k, pos[k], r * (0.9 + 0.01 * double(k % 10)), 2500.0);
  auto b = make_backend("reference", prm, s.p.size());
  b->set_state(s);
  b->step(10000);
  int calm = 0;
  for (int ms = 0; ms < 1000 && calm < 10; ++ms) {
    b->step(100);
    SystemState st = b->state();
    double v = 0.0;
    for (size_t i = 0; i < st.p.size(); ++i) {
      v = std::max(v, glm::length(st.p.v[i]));
      st.p.v[i] *= 0.5;
      st.p.w[i] *= 0.5;
    }
    calm = v < 1e-7 ? calm + 1 : 0;
    b->set_state(st);
  }
  if (calm < 10) return SystemState{};
  return b->state();
}

TEST_P(Invariants, PackedBedStaysAtRest) {
  SimParams prm = dry_params(5e6, 2e6, 0.3, 1e-5);
  prm.gravity = glm::dvec3(0.0, -9.81, 0.0);
  prm.pp.mu_s = 0.5;
  prm.pp.mu_r = 0.1;
  for (auto& w : prm.pw) w = prm.pp;
  prm.drum.radius = 0.006;
  prm.drum.length = 0.006;
  prm.drum.periodic_z = true;
  static const SystemState bed = settled_bed(prm);  // shared by the backends
  ASSERT_EQ(bed.p.size(), 30u) << "the reference did not settle the bed";
  uint64_t touching_walls = 0;
  for (const auto& w : bed.p.wall) touching_walls += w.spring_t != glm::dvec3(0.0) ? 1 : 0;
  auto b = make_backend(GetParam(), prm, bed.p.size());
  b->set_state(bed);
  double vmax = 0.0;
  for (int k = 0; k < 50; ++k) {
    b->step(100);
    const SystemState st = b->state();
    for (size_t i = 0; i < st.p.size(); ++i) vmax = std::max(vmax, glm::length(st.p.v[i]));
  }
  const SystemState st = b->state();
  double ymax = -1.0, shift = 0.0;
  for (size_t i = 0; i < st.p.size(); ++i) {
    ymax = std::max(ymax, st.p.x[i].y);
    glm::dvec3 d = st.p.x[i] - bed.p.x[i];
    d.z -= prm.drum.length * std::round(d.z / prm.drum.length);
    shift = std::max(shift, glm::length(d));
  }
  std::cout << "packed bed: " << st.p.size() << " spheres (" << bed.pairs.size() << " pair records, "
            << touching_walls << " loaded wall contacts), max speed at rest " << vmax
            << " m/s, largest shift " << shift << " m, top at y = " << ymax << "\n";
  EXPECT_GT(bed.pairs.size(), 30u);     // a packing, not a loose heap
  EXPECT_LT(ymax, 0.0021);              // settled below the top row of the starting lattice (y = 2.1 mm)
  EXPECT_LT(vmax, 1e-4 * 9.81 * 0.05);  // free fall would reach 0.49 m/s in 0.05 s
  EXPECT_LT(shift, 1e-4 * 0.5 * 9.81 * 0.05 * 0.05);  // and 12 mm in that time
}

// §5 / §7.8: a wet packing tumbling in the turning drum (periodic slice, particle-particle and cylinder
// bridges, d_c = 0.9) with liquid events every step keeps Σ films + Σ bridges exactly, as integers.
TEST_P(Invariants, TumblingWetPackingConservesLiquidExactly) {
  SimParams prm = dry_params(5e6, 2e6, 0.3, 1e-5);
  prm.gravity = glm::dvec3(0.0, -9.81, 0.0);
  prm.pp.mu_s = 0.5;
  prm.pp.mu_r = 0.05;
  for (auto& w : prm.pw) w = prm.pp;
  prm.drum.radius = 0.008;  // the GPU grid wants the interaction distance below R/4
  prm.drum.length = 0.006;
  prm.drum.periodic_z = true;
  prm.drum.omega = 20.0;  // Froude number Omega^2 R / g = 0.33: cascading, not centrifuging
  const double r = 1e-3;
  const double vbar = 4.0 / 3.0 * kPi * r * r * r;
  const int64_t one = int64_t(1) << 40;  // V-bar_S = 2^40 units
  prm.liquid_unit_m3 = vbar / double(one);
  prm.liq_pp = water(one / 1000, one / 50, 0.9);
  prm.liq_pw[kWallCylinder] = water(one / 1000, one / 50, 1.0);
  prm.liq_pp.gamma = prm.liq_pw[kWallCylinder].gamma = 0.01;  // weak cohesion (f0 ~ 0.6 m g): the bed flows
  const auto pos = lattice_in_drum(prm.drum, r, 2.05e-3, 5e-5, 30);
  SystemState s = empty_state(pos.size());
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 0.1);
  for (size_t k = 0; k < pos.size(); ++k) {
    // Thrown in with random velocities (0.1 m/s): many touches and separations early on.
    put_sphere(s, k, pos[k], r * (0.9 + 0.01 * double(k % 10)), 2500.0, glm::dvec3(g(rng), g(rng), g(rng)));
    s.p.film[k] = int64_t(rng() % uint64_t(one / 40));
  }
  const int64_t total0 = s.total_liquid();
  auto b = make_backend(GetParam(), prm, s.p.size());
  b->set_state(s);
  EventCounts sum;
  for (int block = 0; block < 60; ++block) {
    b->step(200);
    const SystemState st = b->state();
    ASSERT_EQ(liquid_sum(st), total0) << "after " << (block + 1) * 200 << " steps";
    for (int64_t f : st.p.film) ASSERT_GE(f, 0);
    for (const auto& pr : st.pairs) ASSERT_LE(pr.bridge, prm.liq_pp.v_max);
    const EventCounts ev = b->read_events();
    sum.formations += ev.formations;
    sum.ruptures += ev.ruptures;
  }
  const SystemState st = b->state();
  uint64_t bridges = 0, wall_bridges = 0;
  for (const auto& pr : st.pairs) bridges += pr.bridge > 0 ? 1 : 0;
  for (const auto& w : st.p.wall) wall_bridges += w.bridge > 0 ? 1 : 0;
  RecordProperty("formations", std::to_string(sum.formations));
  RecordProperty("ruptures", std::to_string(sum.ruptures));
  std::cout << "tumbling wet packing, 12000 steps: " << sum.formations << " formations, " << sum.ruptures
            << " ruptures, " << bridges << " bridges and " << wall_bridges
            << " wall bridges at the end, liquid " << total0 << " units conserved exactly\n";
  EXPECT_GT(sum.formations, 10u);
  EXPECT_GT(sum.ruptures, 10u);
}

INSTANTIATE_TEST_SUITE_P(Backends, Invariants, ::testing::ValuesIn(backends()), BackendName());

}  // namespace
}  // namespace wetdem::test
