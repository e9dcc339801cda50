// Synthetic drum beds with known answers for the camera observables (tests/test_observe_*.cpp): particles on
// a simple cubic grid of spacing d filling the circular segment below a plane surface inclined at a set
// angle, in the drum frame of app/drum/aor.h (axis z, gravity -y; a surface at angle a rises towards +x, its
// normal n = (-sin a, cos a) points from the bed to the drum axis).
#pragma once

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "wetdem/state.h"

namespace wetdem::test {

struct BedSpec {
  double drum_radius = 0.07;
  double length = 0.02;     // axial extent; z layers at -L/2 + d/2 + i d
  double d = 2e-3;          // particle diameter = grid spacing
  double angle_deg = 30.0;  // surface inclination
  double level = -0.025;    // signed distance of the top row's centres from the axis along n (< 0: below)
  double jitter = 0.0;      // uniform position noise ±jitter·d on each coordinate
  unsigned seed = 1;
  // Angle of the z layer at z (default: angle_deg everywhere): beds whose slabs lean differently.
  std::function<double(double)> angle_of_z;
};

// Grid points (u_i, h_j, z_k) with u_i = (i + ½) d symmetric about 0 and h_j = level - j d, mapped to
// x = u t + h n; those whose sphere fits inside the drum are kept. Velocities zero, density 900 kg/m³.
inline SystemState make_bed(const BedSpec& b) {
  std::mt19937_64 rng(b.seed);
  std::uniform_real_distribution<double> jit(-b.jitter * b.d, b.jitter * b.d);
  std::vector<glm::dvec3> xs;
  const double r = 0.5 * b.d;
  const int nz = static_cast<int>(std::floor(b.length / b.d + 1e-9));
  const int nu = static_cast<int>(std::ceil(b.drum_radius / b.d));
  for (int k = 0; k < nz; ++k) {
    const double z = -0.5 * b.length + (k + 0.5) * b.d;
    const double a = (b.angle_of_z ? b.angle_of_z(z) : b.angle_deg) * 3.14159265358979323846 / 180.0;
    const glm::dvec2 t(std::cos(a), std::sin(a)), n(-std::sin(a), std::cos(a));
    for (int j = 0; b.level - j * b.d > -b.drum_radius; ++j)
      for (int i = -nu; i < nu; ++i) {
        const double u = (i + 0.5) * b.d, h = b.level - j * b.d;
        glm::dvec2 p = u * t + h * n;
        if (std::hypot(p.x, p.y) > b.drum_radius - r) continue;
        glm::dvec3 x(p.x, p.y, z);
        if (b.jitter > 0) x += glm::dvec3(jit(rng), jit(rng), jit(rng));
        xs.push_back(x);
      }
  }
  SystemState s;
  s.p.resize(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) set_sphere(s.p, i, xs[i], r, 900.0);
  return s;
}

// Frame of the bed's surface: u = x.t, h = x.n.
inline glm::dvec2 tangent(double angle_deg) {
  const double a = angle_deg * 3.14159265358979323846 / 180.0;
  return {std::cos(a), std::sin(a)};
}
inline glm::dvec2 normal(double angle_deg) {
  const double a = angle_deg * 3.14159265358979323846 / 180.0;
  return {-std::sin(a), std::cos(a)};
}

}  // namespace wetdem::test
