// Small helpers the reference and backend tests share to build parameters and states (tests only).
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <random>
#include <string>

#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem::test {

inline constexpr double kPi = 3.14159265358979323846;

// Test-name generator for INSTANTIATE_TEST_SUITE_P over backends(): the backend's name.
struct BackendName {
  template <class Info>
  std::string operator()(const Info& info) const {
    return info.param;
  }
};

// Unit round-off of a backend's arithmetic, for tolerances of conservation tests: the reference computes in
// double precision, the GPU system in float32.
inline double unit_roundoff(const std::string& backend) {
  return backend == "reference" ? 0x1p-52 : 0x1p-23;
}

// One material for particles and all walls: E*, G* given directly (§1 allows it), no friction, no gravity,
// a large drum with no plates so that nothing touches a wall unless a test puts it there.
inline SimParams dry_params(double E_star = 5e6, double G_star = 2e6, double restitution = 0.5,
                            double dt = 1e-6) {
  SimParams prm;
  prm.dt = dt;
  prm.gravity = glm::dvec3(0.0);
  prm.pp.E_star = E_star;
  prm.pp.G_star = G_star;
  prm.pp.restitution = restitution;
  for (auto& w : prm.pw) w = prm.pp;
  prm.drum.radius = 1.0;
  prm.drum.length = 2.0;
  prm.drum.omega = 0.0;
  prm.drum.plate_lo.present = prm.drum.plate_hi.present = false;
  return prm;
}

// Liquid of §7 items 1-2: gamma = 0.072 N/m, theta = 20 deg; volumes in units of 1e-21 m^3.
inline LiquidParams water(int64_t v_min, int64_t v_max, double d_c = 1.0) {
  LiquidParams l;
  l.enabled = true;
  l.gamma = 0.072;
  l.theta = 20.0 * kPi / 180.0;
  l.v_min = v_min;
  l.v_max = v_max;
  l.d_c = d_c;
  return l;
}

inline SystemState empty_state(size_t n) {
  SystemState s;
  s.p.resize(n);
  return s;
}

inline void put_sphere(SystemState& s, size_t k, glm::dvec3 x, double r, double rho,
                       glm::dvec3 v = glm::dvec3(0.0), glm::dvec3 w = glm::dvec3(0.0)) {
  set_sphere(s.p, k, x, r, rho);
  s.p.v[k] = v;
  s.p.w[k] = w;
}

// A pair record of particles i and j that were in contact, carrying a bridge of v liquid units (0: dry).
inline PairRecord bridge_record(uint32_t i, uint32_t j, int64_t v) {
  PairRecord r;
  r.id_i = i;
  r.id_j = j;
  r.bridge = v;
  r.flags = kFlagWasInContact;
  return r;
}

// Hertz contact duration for impact speed v (undamped): t_c = 2.9432 delta_max / v with
// delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) (energy balance on F = (4/3) E* sqrt(R*) delta^(3/2)).
inline double hertz_contact_time(double m_star, double R_star, double E_star, double v) {
  const double dmax = std::pow(15.0 * m_star * v * v / (16.0 * E_star * std::sqrt(R_star)), 0.4);
  return 2.9432 * dmax / v;
}

// Kinetic energy, translational + rotational.
inline double kinetic_energy(const SystemState& s) {
  double e = 0.0;
  for (size_t k = 0; k < s.p.size(); ++k)
    e += 0.5 * s.p.mass[k] * glm::dot(s.p.v[k], s.p.v[k]) +
         0.5 * s.p.inertia[k] * glm::dot(s.p.w[k], s.p.w[k]);
  return e;
}

// Total liquid as Σ V_f + Σ V_b (units), independent of SystemState::total_liquid.
inline int64_t liquid_sum(const SystemState& s) {
  int64_t t = 0;
  for (int64_t f : s.p.film) t += f;
  for (const auto& r : s.pairs) t += r.bridge;
  for (const auto& r : s.p.wall) t += r.bridge;
  return t;
}

inline const PairRecord* find_pair(const SystemState& s, uint32_t i, uint32_t j) {
  for (const auto& r : s.pairs)
    if (r.id_i == i && r.id_j == j) return &r;
  return nullptr;
}
inline int64_t bridge_of(const SystemState& s, uint32_t i, uint32_t j) {
  const PairRecord* r = find_pair(s, i, j);
  return r ? r->bridge : 0;
}
inline uint32_t flags_of(const SystemState& s, uint32_t i, uint32_t j) {
  const PairRecord* r = find_pair(s, i, j);
  return r ? r->flags : 0;
}

}  // namespace wetdem::test
