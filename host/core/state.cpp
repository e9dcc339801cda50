#include "wetdem/state.h"

#include <algorithm>
#include <tuple>

namespace wetdem {

void ParticleArrays::resize(size_t n) {
  x.resize(n);
  v.resize(n);
  w.resize(n);
  f.resize(n);
  t.resize(n);
  radius.resize(n);
  mass.resize(n);
  inertia.resize(n);
  film.resize(n);
  pore.resize(n);
  evaporated.resize(n);
  wall.resize(n * kNumWalls);
}

SystemState concat_states(const std::vector<SystemState>& runs) {
  SystemState all;
  size_t n = 0;
  for (const SystemState& r : runs) n += r.p.size();
  all.p.resize(n);
  size_t off = 0;
  for (const SystemState& r : runs) {
    const ParticleArrays& q = r.p;
    for (size_t k = 0; k < q.size(); ++k) {
      const size_t m = off + k;
      all.p.x[m] = q.x[k], all.p.v[m] = q.v[k], all.p.w[m] = q.w[k], all.p.f[m] = q.f[k], all.p.t[m] = q.t[k];
      all.p.radius[m] = q.radius[k], all.p.mass[m] = q.mass[k], all.p.inertia[m] = q.inertia[k];
      all.p.film[m] = q.film[k];
      all.p.pore[m] = k < q.pore.size() ? q.pore[k] : 0;
      all.p.evaporated[m] = k < q.evaporated.size() ? q.evaporated[k] : 0;
      for (uint32_t w = 0; w < kNumWalls; ++w) all.p.wall[m * kNumWalls + w] = q.wall[k * kNumWalls + w];
    }
    for (PairRecord rec : r.pairs) {
      rec.id_i += uint32_t(off);
      rec.id_j += uint32_t(off);
      all.pairs.push_back(rec);
    }
    off += q.size();
  }
  if (!runs.empty()) all.time = runs[0].time, all.step = runs[0].step;
  return all;
}

std::vector<SystemState> split_state(const SystemState& all, const std::vector<size_t>& sizes) {
  std::vector<SystemState> out(sizes.size());
  size_t off = 0;
  for (size_t r = 0; r < sizes.size(); ++r) {
    ParticleArrays& q = out[r].p;
    q.resize(sizes[r]);
    for (size_t k = 0; k < sizes[r]; ++k) {
      const size_t m = off + k;
      q.x[k] = all.p.x[m], q.v[k] = all.p.v[m], q.w[k] = all.p.w[m], q.f[k] = all.p.f[m], q.t[k] = all.p.t[m];
      q.radius[k] = all.p.radius[m], q.mass[k] = all.p.mass[m], q.inertia[k] = all.p.inertia[m];
      q.film[k] = all.p.film[m];
      q.pore[k] = m < all.p.pore.size() ? all.p.pore[m] : 0;
      q.evaporated[k] = m < all.p.evaporated.size() ? all.p.evaporated[m] : 0;
      for (uint32_t w = 0; w < kNumWalls; ++w) q.wall[k * kNumWalls + w] = all.p.wall[m * kNumWalls + w];
    }
    for (const PairRecord& rec : all.pairs)
      if (rec.id_i >= off && rec.id_i < off + sizes[r]) {
        PairRecord x = rec;
        x.id_i -= uint32_t(off);
        x.id_j -= uint32_t(off);
        out[r].pairs.push_back(x);
      }
    out[r].time = all.time;
    out[r].step = all.step;
    off += sizes[r];
  }
  return out;
}

int64_t SystemState::total_liquid() const {
  return liquid_budget().total();
}

LiquidBudget SystemState::liquid_budget() const {
  LiquidBudget b;
  for (int64_t v : p.film) b.films += v;
  for (const auto& r : pairs) b.bridges += r.bridge;
  for (const auto& r : p.wall) b.bridges += r.bridge;
  for (int64_t v : p.pore) b.pores += v;
  for (int64_t v : p.evaporated) b.evaporated += v;
  return b;
}

void SystemState::canonicalize() {
  pairs.erase(std::remove_if(pairs.begin(), pairs.end(), [](const PairRecord& r) { return r.empty(); }),
              pairs.end());
  std::sort(pairs.begin(), pairs.end(), [](const PairRecord& a, const PairRecord& b) {
    return std::tie(a.id_i, a.id_j) < std::tie(b.id_i, b.id_j);
  });
}

void set_sphere(ParticleArrays& p, size_t k, glm::dvec3 x, double radius, double density) {
  const double pi = 3.14159265358979323846;
  p.x[k] = x;
  p.radius[k] = radius;
  p.mass[k] = density * 4.0 / 3.0 * pi * radius * radius * radius;
  p.inertia[k] = 0.4 * p.mass[k] * radius * radius;
}

}  // namespace wetdem
