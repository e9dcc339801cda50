// Agglomerates: connected components of the bridge network (diagnosis.md §2, drum.md finding 5). Two
// particles are connected when their pair record holds a bridge (V_b > 0, touching or not); wall bridges do
// not connect particles. Union-find on the host over the downloaded pair records: O(N + pairs), no device
// pass.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "wetdem/state.h"

namespace wetdem::observe {

struct Clusters {
  // Per particle (stable-id order): the cluster's label = the smallest stable id among its members (an
  // unbridged particle is its own cluster of one), and the cluster's particle count.
  std::vector<uint32_t> id, size;
  size_t count = 0;    // clusters, singletons included
  size_t largest = 0;  // particles in the largest cluster
  // Mass-weighted mean particle count, Σ_c M_c n_c / Σ_c M_c (singletons included: 1 for a dry bed).
  double size_mean = 0.0;
  // Mass-weighted mean solid volume of the clusters, Σ_c M_c V_c / Σ_c M_c (m³), V_c = Σ 4/3 π r³ of the
  // members, and the diameter of the sphere of that volume, (6 V / π)^(1/3) (m).
  double volume_mean_m3 = 0.0;
  double equivalent_diameter_m = 0.0;
};

Clusters bridge_clusters(const SystemState& s);

// Agglomerates as an image of the surface shows them (diagnosis.md §2: "clumps in the flowing layer, not the
// bridge network's components"): the bridge network restricted to the visible surface particles `layer`
// (surface.h: the surface layer of the fitted columns), i.e. the clumps a camera can pick out on the free
// surface, each held together by bridges between surface particles. The mass-weighted mean particle count
// Σ M_c n_c / Σ M_c over those clumps (1 when no two surface particles are bridged); NaN for an empty layer.
double surface_cluster_size(const SystemState& s, const std::vector<size_t>& layer);

}  // namespace wetdem::observe
