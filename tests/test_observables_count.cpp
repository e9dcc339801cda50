// compute_observables counts touching and bridged pairs on a hand-built state whose answer is known: a chain
// of three touching particles, one bridge of a touching pair, one bridge of a separated pair (f_wet = bridged
// / |touching ∪ bridged|), and a pair touching across the periodic boundary only.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace wetdem
