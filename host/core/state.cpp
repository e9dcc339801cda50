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
