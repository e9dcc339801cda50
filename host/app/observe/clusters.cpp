#include "app/observe/clusters.h"

#include <cmath>
#include <cstdint>
#include <numeric>

namespace wetdem::observe {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Union-find with path halving; the root of a set is always its smallest index, so labels do not depend on
// the order of the pairs.
uint32_t find(std::vector<uint32_t>& parent, uint32_t a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

}  // namespace

Clusters bridge_clusters(const SystemState& s) {
  const size_t n = s.p.size();
  Clusters c;
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (const PairRecord& r : s.pairs) {
    if (r.bridge <= 0 || r.id_i >= n || r.id_j >= n) continue;
    const uint32_t a = find(parent, r.id_i), b = find(parent, r.id_j);
    if (a < b)
      parent[b] = a;
    else if (b < a)
      parent[a] = b;
  }
  c.id.resize(n);
  std::vector<uint32_t> count(n, 0);
  std::vector<double> mass(n, 0.0), vol(n, 0.0);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t root = find(parent, k);
    c.id[k] = root;
    ++count[root];
    mass[root] += s.p.mass[k];
    vol[root] += 4.0 / 3.0 * kPi * std::pow(s.p.radius[k], 3);
  }
  c.size.resize(n);
  double msum = 0, mn = 0, mv = 0;
  for (uint32_t k = 0; k < n; ++k) {
    c.size[k] = count[c.id[k]];
    if (c.id[k] != k) continue;
    ++c.count;
    c.largest = std::max<size_t>(c.largest, count[k]);
    msum += mass[k];
    mn += mass[k] * count[k];
    mv += mass[k] * vol[k];
  }
  if (msum > 0) {
    c.size_mean = mn / msum;
    c.volume_mean_m3 = mv / msum;
    c.equivalent_diameter_m = std::cbrt(6.0 * c.volume_mean_m3 / kPi);
  }
  return c;
}

double surface_cluster_size(const SystemState& s, const std::vector<size_t>& layer) {
  if (layer.empty()) return std::nan("");
  const size_t n = s.p.size();
  // Layer positions by particle (stable id order, as the pair records).
  std::vector<uint32_t> slot(n, UINT32_MAX);
  for (size_t i = 0; i < layer.size(); ++i) slot[layer[i]] = uint32_t(i);
  std::vector<uint32_t> parent(layer.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const PairRecord& r : s.pairs) {
    if (r.bridge <= 0 || r.id_i >= n || r.id_j >= n) continue;
    if (slot[r.id_i] == UINT32_MAX || slot[r.id_j] == UINT32_MAX) continue;
    const uint32_t a = find(parent, slot[r.id_i]), b = find(parent, slot[r.id_j]);
    if (a < b)
      parent[b] = a;
    else if (b < a)
      parent[a] = b;
  }
  std::vector<double> mass(layer.size(), 0.0);
  std::vector<uint32_t> count(layer.size(), 0);
  for (uint32_t i = 0; i < layer.size(); ++i) {
    const uint32_t root = find(parent, i);
    mass[root] += s.p.mass[layer[i]];
    ++count[root];
  }
  double msum = 0, mn = 0;
  for (size_t i = 0; i < layer.size(); ++i) msum += mass[i], mn += mass[i] * count[i];
  return msum > 0 ? mn / msum : std::nan("");
}

}  // namespace wetdem::observe
