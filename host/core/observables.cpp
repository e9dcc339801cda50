#include "wetdem/observables.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <utility>
#include <vector>

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

  // Touching pairs through a cell list: particles counting-sorted into a dense grid over their bounding box
  // (cells at least the largest diameter; minimum image on a periodic axis), so a neighbour cell's particles
  // are one index away. (A hash multimap cost ~2 us per particle, cache misses of 27 lookups each: ~50 ms per
  // sample of PP2 l = 5, a quarter of the H100's stepping between two samples; this is ~15 ms.) A sparse
  // state (a particle far out) gets wider cells rather than a huge grid: still exact, only slower.
  double cell = std::max(2.0 * r_max, 1e-12);
  const bool periodic = prm.drum.periodic_z;
  const double L = prm.drum.length;
  int64_t nz = 0;
  auto cz_of = [&](double z) {
    if (!periodic) return int64_t(std::floor(z / cell));
    double u = (z + 0.5 * L) / L;
    u -= std::floor(u);
    return std::min<int64_t>(nz - 1, int64_t(u * double(nz)));
  };
  std::vector<int64_t> c3(3 * n);
  int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, dims[3] = {1, 1, 1};
  const double limit = 64.0 * double(n) + 4096.0;
  for (;;) {
    nz = periodic ? std::max<int64_t>(1, int64_t(std::floor(L / cell))) : 0;
    for (size_t k = 0; k < n; ++k) {
      const double cx = std::floor(s.p.x[k].x / cell), cy = std::floor(s.p.x[k].y / cell);
      const double cz = periodic ? 0.0 : std::floor(s.p.x[k].z / cell);
      if (!(std::fabs(cx) < 1e15 && std::fabs(cy) < 1e15 && std::fabs(cz) < 1e15))
        throw std::invalid_argument(
            "compute_observables: a particle position is not finite or absurdly far out");
      c3[3 * k] = int64_t(cx);
      c3[3 * k + 1] = int64_t(cy);
      c3[3 * k + 2] = cz_of(s.p.x[k].z);
      for (int a = 0; a < 3; ++a) {
        lo[a] = k ? std::min(lo[a], c3[3 * k + a]) : c3[3 * k + a];
        hi[a] = k ? std::max(hi[a], c3[3 * k + a]) : c3[3 * k + a];
      }
    }
    if (periodic) lo[2] = 0, hi[2] = nz - 1;
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) dims[a] = hi[a] - lo[a] + 1, cells *= double(dims[a]);
    if (cells <= limit) break;
    cell *= std::cbrt(cells / limit) * 1.01;
  }
  const int64_t ncells = dims[0] * dims[1] * dims[2];
  auto cell_of = [&](int64_t x, int64_t y, int64_t z) {
    return ((z - lo[2]) * dims[1] + (y - lo[1])) * dims[0] + (x - lo[0]);
  };
  std::vector<uint32_t> start(size_t(n > 0 ? ncells : 0) + 1, 0), order(n);
  for (size_t k = 0; k < n; ++k) start[size_t(cell_of(c3[3 * k], c3[3 * k + 1], c3[3 * k + 2])) + 1]++;
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t k = 0; k < n; ++k)
      order[fill[size_t(cell_of(c3[3 * k], c3[3 * k + 1], c3[3 * k + 2]))]++] = uint32_t(k);
  }
  std::vector<uint64_t> bridged;  // (id_i << 32 | id_j) of the bridged pairs, sorted
  for (const auto& r : s.pairs) {
    o.liquid_bridges += r.bridge;
    if (r.bridge > 0) bridged.push_back((uint64_t(r.id_i) << 32) | r.id_j);
  }
  std::sort(bridged.begin(), bridged.end());
  bridged.erase(std::unique(bridged.begin(), bridged.end()), bridged.end());
  o.bridges = bridged.size();
  uint64_t touching = 0, touching_bridged = 0;
  const int64_t zspan = periodic ? std::min<int64_t>(nz, 3) : 3;
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3& xi = s.p.x[i];
    const int64_t cx = c3[3 * i], cy = c3[3 * i + 1], cz = c3[3 * i + 2];
    for (int64_t dz = -1; dz < zspan - 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          int64_t z = cz + dz;
          if (periodic) z = ((z % nz) + nz) % nz;
          const int64_t x = cx + dx, y = cy + dy;
          if (x < lo[0] || x > hi[0] || y < lo[1] || y > hi[1] || z < lo[2] || z > hi[2]) continue;
          const size_t c = size_t(cell_of(x, y, z));
          for (uint32_t q = start[c]; q < start[c + 1]; ++q) {
            const uint32_t j = order[q];
            if (j <= i) continue;
            glm::dvec3 d = xi - s.p.x[j];
            if (periodic) d.z -= L * std::round(d.z / L);
            double delta = s.p.radius[i] + s.p.radius[j] - glm::length(d);
            if (delta > 0) {
              touching++;
              o.max_overlap = std::max(o.max_overlap, delta);
              if (std::binary_search(bridged.begin(), bridged.end(), (uint64_t(i) << 32) | j))
                touching_bridged++;
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
