// compute_observables counts touching and bridged pairs on a hand-built state whose answer is known: a chain
// of three touching particles, one bridge of a touching pair, one bridge of a separated pair (f_wet = bridged
// / |touching ∪ bridged|), and a pair touching across the periodic boundary only.
#include <gtest/gtest.h>

#include <cmath>

#include "wetdem/observables.h"
#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {
namespace {

SimParams drum(bool periodic) {
  SimParams p;
  p.drum.radius = 0.05;
  p.drum.length = 0.02;
  p.drum.periodic_z = periodic;
  return p;
}

TEST(ObservablesCount, ChainWithBridgesGivesKnownFwet) {
  SystemState s;
  s.p.resize(4);
  const double r = 1e-3;
  // A-B and B-C overlap by 0.1 r; D sits 0.5 r from C's surface (separated).
  set_sphere(s.p, 0, {0.0, -0.02, 0.0}, r, 900);
  set_sphere(s.p, 1, {1.9 * r, -0.02, 0.0}, r, 900);
  set_sphere(s.p, 2, {3.8 * r, -0.02, 0.0}, r, 900);
  set_sphere(s.p, 3, {6.3 * r, -0.02, 0.0}, r, 900);
  PairRecord ab, cd;
  ab.id_i = 0, ab.id_j = 1, ab.bridge = 100;
  cd.id_i = 2, cd.id_j = 3, cd.bridge = 50;
  s.pairs = {ab, cd};
  const Observables o = compute_observables(s, drum(false));
  EXPECT_EQ(o.contacts, 2u);         // A-B, B-C
  EXPECT_EQ(o.bridges, 2u);          // A-B (touching), C-D (separated)
  EXPECT_EQ(o.wet_or_touching, 3u);  // A-B, B-C, C-D
  EXPECT_DOUBLE_EQ(o.f_wet, 2.0 / 3.0);
  EXPECT_EQ(o.liquid_bridges, 150);
  EXPECT_NEAR(o.max_overlap, 0.1 * r, 1e-12);
}

TEST(ObservablesCount, PairAcrossThePeriodicBoundaryTouchesOnlyWhenPeriodic) {
  SystemState s;
  s.p.resize(2);
  const double r = 1e-3, L = 0.02;
  set_sphere(s.p, 0, {0.0, -0.02, 0.5 * L - 0.95 * r}, r, 900);
  set_sphere(s.p, 1, {0.0, -0.02, -0.5 * L + 0.95 * r}, r, 900);
  EXPECT_EQ(compute_observables(s, drum(true)).contacts, 1u);
  EXPECT_EQ(compute_observables(s, drum(false)).contacts, 0u);
}

TEST(ObservablesCount, DenseRandomBedAndAFarOutlierMatchBruteForce) {
  // The cell list against an O(n^2) count: a dense random bed of unequal spheres with bridges on a third of
  // the nearby pairs, in a closed and in a periodic drum, then with one particle 30 m out (the grid then
  // widens its cells instead of growing huge: the counts must not change).
  for (bool periodic : {false, true}) {
    const SimParams prm = drum(periodic);
    SystemState s;
    const size_t n = 600;
    s.p.resize(n + 1);
    uint64_t seed = 12345;
    auto uni = [&] {
      seed = seed * 6364136223846793005ull + 1442695040888963407ull;
      return double(seed >> 11) / double(1ull << 53);
    };
    for (size_t k = 0; k < n; ++k)
      set_sphere(s.p, k, {0.03 * (uni() - 0.5), 0.03 * (uni() - 0.5), 0.02 * (uni() - 0.5)},
                 0.8e-3 + 0.6e-3 * uni(), 900);
    set_sphere(s.p, n, {0.01, 0.0, 0.0}, 1e-3, 900);
    auto brute = [&](size_t m, uint64_t& touching, uint64_t& touching_bridged) {
      touching = touching_bridged = 0;
      for (size_t i = 0; i < m; ++i)
        for (size_t j = i + 1; j < m; ++j) {
          glm::dvec3 d = s.p.x[i] - s.p.x[j];
          if (periodic) d.z -= prm.drum.length * std::round(d.z / prm.drum.length);
          if (s.p.radius[i] + s.p.radius[j] - glm::length(d) > 0) {
            ++touching;
            for (const PairRecord& r : s.pairs)
              if (r.id_i == i && r.id_j == j && r.bridge > 0) ++touching_bridged;
          }
        }
    };
    s.pairs.clear();
    for (uint32_t i = 0; i < n; ++i)
      for (uint32_t j = i + 1; j < n; ++j)
        if (glm::length(s.p.x[i] - s.p.x[j]) < 3e-3 && (i + j) % 3 == 0) {
          PairRecord r;
          r.id_i = i, r.id_j = j, r.bridge = 7;
          s.pairs.push_back(r);
        }
    for (bool outlier : {false, true}) {
      if (outlier) s.p.x[n] = {30.0, 0.0, 0.0};
      uint64_t touching = 0, wet = 0;
      brute(n + 1, touching, wet);
      const Observables o = compute_observables(s, prm);
      EXPECT_GT(touching, 100u);
      EXPECT_EQ(o.contacts, touching) << "periodic " << periodic << ", outlier " << outlier;
      EXPECT_EQ(o.bridges, s.pairs.size());
      EXPECT_EQ(o.wet_or_touching, touching + s.pairs.size() - wet) << "periodic " << periodic;
    }
  }
}

}  // namespace
}  // namespace wetdem
