#include "wetdem/observables.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <unordered_map>

namespace wetdem {

namespace {

// Overlap of particle k with wall w (negative = gap), same geometry as the engine (physics.md §0).
bool wall_overlap(const SystemState& s, const SimParams& prm, size_t k, uint32_t w, double& delta) {
  const glm::dvec3& x = s.p.x[k];
  const double r = s.p.radius[k];
  const DrumParams& d = prm.drum;
  if (w == kWallCylinder) {
    delta = r - (d.radius - std::hypot(x.x, x.y));
    return true;
  }
  if (d.periodic_z) return false;
  const PlateParams& pl = (w == kWallPlateLo) ? d.plate_lo : d.plate_hi;
  if (!pl.present) return false;
  delta = (w == kWallPlateLo) ? r - (x.z + 0.5 * d.length) : r - (0.5 * d.length - x.z);
  return true;
}

}  // namespace

Observables compute_observables(const SystemState& s, const SimParams& prm) {
  Observables o;
  const size_t n = s.p.size();
  double mass = 0.0;
  double r_max = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const double m = s.p.mass[k];
    o.kinetic_energy +=
        0.5 * m * glm::dot(s.p.v[k], s.p.v[k]) + 0.5 * s.p.inertia[k] * glm::dot(s.p.w[k], s.p.w[k]);
    o.com += m * s.p.x[k];
    mass += m;
    o.liquid_films += s.p.film[k];
    if (k < s.p.pore.size()) o.liquid_pores += s.p.pore[k];
    if (k < s.p.evaporated.size()) o.liquid_evaporated += s.p.evaporated[k];
    r_max = std::max(r_max, s.p.radius[k]);
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      const WallRecord& r = s.p.wall[k * kNumWalls + w];
      o.liquid_bridges += r.bridge;
      if (r.bridge > 0) o.wall_bridges++;
      double delta;
      if (wall_overlap(s, prm, k, w, delta) && delta > 0) {
        o.wall_contacts++;
        o.max_overlap = std::max(o.max_overlap, delta);
      }
    }
  }
  if (mass > 0) o.com /= mass;

  // Touching pairs: hash grid with cells of the largest diameter (minimum image on a periodic axis).
  const double cell = std::max(2.0 * r_max, 1e-12);
  const bool periodic = prm.drum.periodic_z;
  const double L = prm.drum.length;
  const int64_t nz = periodic ? std::max<int64_t>(1, int64_t(std::floor(L / cell))) : 0;
  // Exact cell keys (21 bits per axis), not a hash of the three: two of the 27 neighbour cells sharing a
  // hashed key would list their particles twice and count those contacts twice.
  auto key = [](int64_t a, int64_t b, int64_t c) {
    constexpr int64_t kOff = int64_t(1) << 20;
    if (std::max({std::llabs(a), std::llabs(b), std::llabs(c)}) >= kOff - 1)
      throw std::invalid_argument("compute_observables: a particle lies 1e6 cells from the drum axis");
    return ((a + kOff) << 42) | ((b + kOff) << 21) | (c + kOff);
  };
  auto cz_of = [&](double z) {
    if (!periodic) return int64_t(std::floor(z / cell));
    double u = (z + 0.5 * L) / L;
    u -= std::floor(u);
    return std::min<int64_t>(nz - 1, int64_t(u * double(nz)));
  };
  std::unordered_multimap<int64_t, uint32_t> grid;
  grid.reserve(n);
  for (size_t k = 0; k < n; ++k)
    grid.emplace(key(int64_t(std::floor(s.p.x[k].x / cell)), int64_t(std::floor(s.p.x[k].y / cell)),
                     cz_of(s.p.x[k].z)),
                 uint32_t(k));
  std::unordered_map<uint64_t, bool> bridged;
  for (const auto& r : s.pairs) {
    o.liquid_bridges += r.bridge;
    if (r.bridge > 0) bridged[(uint64_t(r.id_i) << 32) | r.id_j] = true;
  }
  o.bridges = bridged.size();
  uint64_t touching = 0, touching_bridged = 0;
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3& xi = s.p.x[i];
    int64_t cx = int64_t(std::floor(xi.x / cell)), cy = int64_t(std::floor(xi.y / cell)), cz = cz_of(xi.z);
    const int64_t zspan = periodic ? std::min<int64_t>(nz, 3) : 3;
    for (int64_t dz = -1; dz < zspan - 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          int64_t z = cz + dz;
          if (periodic) z = ((z % nz) + nz) % nz;
          auto range = grid.equal_range(key(cx + dx, cy + dy, z));
          for (auto it = range.first; it != range.second; ++it) {
            uint32_t j = it->second;
            if (j <= i) continue;
            glm::dvec3 d = xi - s.p.x[j];
            if (periodic) d.z -= L * std::round(d.z / L);
            double delta = s.p.radius[i] + s.p.radius[j] - glm::length(d);
            if (delta > 0) {
              touching++;
              o.max_overlap = std::max(o.max_overlap, delta);
              if (bridged.count((uint64_t(i) << 32) | j)) touching_bridged++;
            }
          }
        }
  }
  o.contacts = touching;
  o.wet_or_touching = touching + o.bridges - touching_bridged;
  o.f_wet = o.wet_or_touching > 0 ? double(o.bridges) / double(o.wet_or_touching) : 0.0;
  return o;
}

std::vector<double> liquid_per_particle(const SystemState& s) {
  const size_t n = s.p.size();
  std::vector<double> out(n);
  for (size_t k = 0; k < n; ++k) {
    double v = double(s.p.film[k]);
    for (uint32_t w = 0; w < kNumWalls; ++w) v += double(s.p.wall[k * kNumWalls + w].bridge);
    out[k] = v;
  }
  for (const auto& r : s.pairs) {
    out[r.id_i] += 0.5 * double(r.bridge);
    out[r.id_j] += 0.5 * double(r.bridge);
  }
  return out;
}

}  // namespace wetdem
