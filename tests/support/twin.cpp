#include "support/twin.h"

#include <algorithm>

#include "app/drum/scenarios.h"

namespace wetdem::test {

SimParams twin_drum_params(double radius, double length, double r_min, bool periodic) {
  SimParams prm;
  set_polypropylene_contacts(prm, 0.8, 0.3, r_min, 900.0);
  prm.drum.radius = radius;
  prm.drum.length = length;
  prm.drum.omega = 0.5236;  // 5 rpm
  prm.drum.periodic_z = periodic;
  prm.skin = 0.2 * r_min;
  return prm;
}

SystemState random_drum_packing(const SimParams& prm, size_t n, double r_lo, double r_hi, uint64_t seed,
                                double speed) {
  std::mt19937_64 rng(seed);
  auto uni = [&](double a, double b) { return a + (b - a) * (double(rng() >> 11) * 0x1.0p-53); };
  SystemState s;
  s.p.resize(n);
  const double R = prm.drum.radius, L = prm.drum.length;
  const double a = (r_lo + r_hi) * 0.99;  // lattice spacing: about half the neighbours overlap
  size_t k = 0;
  // Fill lattice sites from the bottom of the drum up, inside the cylinder, until n particles are placed.
  const int nx = int(2 * R / a), nz = int(L / a);
  for (int iy = 0; k < n && iy < nx; ++iy)
    for (int iz = 0; k < n && iz < nz; ++iz)
      for (int ix = 0; k < n && ix < nx; ++ix) {
        glm::dvec3 x(-R + a * (ix + 0.5), -R + a * (iy + 0.5), -0.5 * L + a * (iz + 0.5));
        double r = uni(r_lo, r_hi);
        // Allow a slight wall overlap so that wall contacts are exercised too.
        if (std::hypot(x.x, x.y) > R - 0.99 * r) continue;
        if (!prm.drum.periodic_z && (x.z < -0.5 * L + 0.99 * r || x.z > 0.5 * L - 0.99 * r)) continue;
        x += glm::dvec3(uni(-1, 1), uni(-1, 1), uni(-1, 1)) * (0.003 * r);
        set_sphere(s.p, k, x, r, 900.0);
        s.p.v[k] = glm::dvec3(uni(-1, 1), uni(-1, 1), uni(-1, 1)) * speed;
        s.p.w[k] = glm::dvec3(uni(-1, 1), uni(-1, 1), uni(-1, 1)) * 20.0;
        ++k;
      }
  if (k < n) s.p.resize(k);
  return s;
}

void quantize(SystemState& s, double tick) {
  for (size_t k = 0; k < s.p.size(); ++k) {
    for (int a = 0; a < 3; ++a) s.p.x[k][a] = std::round(s.p.x[k][a] / tick) * tick;
    s.p.radius[k] = std::round(s.p.radius[k] / tick) * tick;
  }
}

double norm_scaled_error(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  double scale = 1e-300, err = 0.0;
  for (size_t k = 0; k < b.size(); ++k) {
    scale = std::max(scale, glm::length(b[k]));
    err = std::max(err, glm::length(a[k] - b[k]));
  }
  return err / scale;
}

}  // namespace wetdem::test
