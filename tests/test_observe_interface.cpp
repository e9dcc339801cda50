// The laboratory observables added for the flowing diagnosis (diagnosis.md §2), on synthetic beds with known
// answers: the cohesive index (interface fluctuation on a fixed laboratory grid) and the clumps a camera sees
// on the free surface.
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <cmath>

#include "app/observe/clusters.h"
#include "app/observe/interface.h"
#include "app/observe/surface.h"
#include "support/synthetic_bed.h"

namespace wetdem::test {
namespace {

using observe::interface_fluctuation;
using observe::interface_profile;

// A flat, horizontal bed: every full column's interface is the top row's height.
TEST(ObserveInterface, FlatBedProfileIsTheTopRow) {
  BedSpec b;
  b.angle_deg = 0.0;
  b.level = -0.02;
  const SystemState s = make_bed(b);
  const std::vector<double> h = interface_profile(s, b.drum_radius, b.length);
  ASSERT_FALSE(h.empty());
  size_t full = 0;
  for (double x : h)
    if (std::isfinite(x)) {
      EXPECT_NEAR(x, b.level, 1e-12);
      ++full;
    }
  EXPECT_GT(full, h.size() / 2);
  // Bins are fixed in the laboratory frame: 2R / (2 d) of them.
  EXPECT_EQ(h.size(), size_t(std::floor(2 * b.drum_radius / (2 * b.d))));
}

// The same bed at rest in every sample has no fluctuation; a surface that jumps between two levels a and b
// (an avalanching bed) has, in every column, the standard deviation of the two-level series.
TEST(ObserveInterface, FluctuationIsTheStandardDeviationOfTheInterface) {
  BedSpec b;
  b.angle_deg = 0.0;
  b.level = -0.02;
  const std::vector<double> lo = interface_profile(make_bed(b), b.drum_radius, b.length);
  b.level = -0.02 + 3 * b.d;
  const std::vector<double> hi = interface_profile(make_bed(b), b.drum_radius, b.length);
  EXPECT_EQ(interface_fluctuation({lo, lo, lo, lo}), 0.0);
  const std::vector<std::vector<double>> jumps = {lo, hi, lo, hi, lo, hi};
  // sd of {a, b, a, b, a, b} with n - 1: |b - a| sqrt(6/20) ... = |b - a| / 2 * sqrt(6/5).
  EXPECT_NEAR(interface_fluctuation(jumps), 3 * b.d / 2 * std::sqrt(6.0 / 5.0), 1e-12);
  // Too few samples, or no column present often enough: no value.
  EXPECT_TRUE(std::isnan(interface_fluctuation({lo, hi})));
  std::vector<double> empty(lo.size(), std::nan(""));
  EXPECT_TRUE(std::isnan(interface_fluctuation({empty, empty, empty, lo})));
}

// A surface tilting back and forth between two angles fluctuates most at the ends of the chord and not at its
// centre: the index averages over the central 60 % of the chord only, so it lies below the largest column's
// sd.
TEST(ObserveInterface, TiltingSurfaceAveragesTheCentralChord) {
  BedSpec b;
  b.level = -0.015;
  b.angle_deg = 25;
  const std::vector<double> a = interface_profile(make_bed(b), b.drum_radius, b.length);
  b.angle_deg = 35;
  const std::vector<double> c = interface_profile(make_bed(b), b.drum_radius, b.length);
  const double ci = interface_fluctuation({a, c, a, c});
  EXPECT_GT(ci, 0.0);
  double largest = 0;
  for (size_t k = 0; k < a.size(); ++k)
    if (std::isfinite(a[k]) && std::isfinite(c[k]))
      largest = std::max(largest, std::fabs(a[k] - c[k]) / std::sqrt(3.0));
  EXPECT_LT(ci, largest);
}

// Surface clumps: the bridge network restricted to the surface layer. Bridges below the surface (or from a
// surface particle down into the bed) do not join two surface clumps.
TEST(ObserveInterface, SurfaceClumpsCountOnlySurfaceBridges) {
  BedSpec b;
  b.angle_deg = 30;
  b.level = -0.02;
  SystemState s = make_bed(b);
  const observe::SurfaceResult sf = observe::fit_surface(s, b.drum_radius, b.length);
  ASSERT_TRUE(sf.valid);
  ASSERT_GE(sf.layer.size(), 6u);
  EXPECT_DOUBLE_EQ(observe::surface_cluster_size(s, sf.layer), 1.0) << "no bridge: clumps of one";
  // Bridge the first three layer particles in a chain, and one of them to a particle that is not in the
  // layer.
  std::vector<bool> in_layer(s.p.size(), false);
  for (size_t i : sf.layer) in_layer[i] = true;
  size_t below = 0;
  while (in_layer[below]) ++below;
  auto bridge = [&](size_t i, size_t j) {
    PairRecord r;
    r.id_i = uint32_t(std::min(i, j));
    r.id_j = uint32_t(std::max(i, j));
    r.bridge = 100;
    s.pairs.push_back(r);
  };
  bridge(sf.layer[0], sf.layer[1]);
  bridge(sf.layer[1], sf.layer[2]);
  bridge(sf.layer[2], below);
  // Equal masses: one clump of 3 and n - 3 of one: Σ n_c² / Σ n_c = (9 + n - 3) / n.
  const double n = double(sf.layer.size());
  EXPECT_NEAR(observe::surface_cluster_size(s, sf.layer), (9.0 + n - 3.0) / n, 1e-12);
  EXPECT_TRUE(std::isnan(observe::surface_cluster_size(s, {})));
}

}  // namespace
}  // namespace wetdem::test
#endif  // WETDEM_HAVE_APP
