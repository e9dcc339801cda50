// Plate and centre slab angles (app/observe/slabs.h) on a bed whose layers next to the end plates lean at
// another angle than the bulk, and their absence on a periodic slice (the whole camera sample too).
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <cmath>

#include "app/observe/camera.h"
#include "app/observe/slabs.h"
#include "support/synthetic_bed.h"

namespace wetdem::test {
namespace {

DrumParams closed_drum(const BedSpec& b) {
  DrumParams d;
  d.radius = b.drum_radius;
  d.length = b.length;
  return d;
}

TEST(ObserveSlabs, PlateSlabsLeanDifferentlyFromTheCentre) {
  // 30 layers of 2 mm: the 3 layers next to each plate (the slabs, 3 d = 6 mm) at 42° and 38° (mean 40°),
  // the bulk at 30°. A flat-surfaced segment's centre of mass lies on the surface normal (app/drum/aor.h),
  // so each slab's AoR is its surface angle.
  BedSpec b;
  b.length = 0.06;
  b.jitter = 0.1;
  b.angle_of_z = [&](double z) { return z < -0.024 ? 42.0 : z > 0.024 ? 38.0 : 30.0; };
  const SystemState s = make_bed(b);
  const observe::SlabAor r = observe::slab_aor(s, closed_drum(b));
  ASSERT_TRUE(r.present);
  EXPECT_NEAR(r.thickness_m, 3 * b.d, 1e-12);
  EXPECT_NEAR(r.plate_lo_deg, 42.0, 0.3);
  EXPECT_NEAR(r.plate_hi_deg, 38.0, 0.3);
  EXPECT_NEAR(r.centre_deg, 30.0, 0.3);
  EXPECT_NEAR(r.plate_deg(), 40.0, 0.3);
  EXPECT_NEAR(r.centre_abs_deg(), 30.0, 0.3);

  // Mirror image (drum turning the other way): the same magnitudes.
  SystemState m = s;
  for (auto& x : m.p.x) x.x = -x.x;
  const observe::SlabAor q = observe::slab_aor(m, closed_drum(b));
  EXPECT_NEAR(q.plate_deg(), 40.0, 0.3);
  EXPECT_NEAR(q.plate_lo_deg, -42.0, 0.3);
  EXPECT_NEAR(q.centre_abs_deg(), 30.0, 0.3);
}

TEST(ObserveSlabs, AbsentOnAPeriodicSlice) {
  BedSpec b;
  const SystemState s = make_bed(b);
  SimParams prm;
  prm.drum.radius = b.drum_radius;
  prm.drum.length = b.length;
  prm.drum.periodic_z = true;
  EXPECT_FALSE(observe::slab_aor(s, prm.drum).present);
  const observe::CameraSample c = observe::observe_camera(s, prm, 0);
  EXPECT_TRUE(std::isnan(c.aor_plate_deg));
  EXPECT_TRUE(std::isnan(c.aor_centre_deg));
  EXPECT_TRUE(std::isnan(c.liquid_free_fraction));  // no liquid put in
  EXPECT_NEAR(c.aor_surface_deg, 30.0, 0.2);
  EXPECT_EQ(c.agglomerate_size_mean, 1.0);  // no bridges: every particle is its own cluster
  EXPECT_NEAR(c.drum_to_agglomerate_ratio, 2 * b.drum_radius / b.d, 1e-9);

  prm.drum.periodic_z = false;
  const observe::CameraSample closed = observe::observe_camera(s, prm, 0);
  EXPECT_NEAR(closed.aor_plate_deg, 30.0, 0.5);
  EXPECT_NEAR(closed.aor_centre_deg, 30.0, 0.5);
}

TEST(ObserveSlabs, FreeLiquidFractionCountsFilmsAndBridges) {
  SystemState s;
  s.p.resize(3);
  for (size_t k = 0; k < 3; ++k) set_sphere(s.p, k, {0.01 * double(k), -0.05, 0.0}, 1e-3, 900.0);
  s.p.film = {100, 50, 0};
  s.p.wall[2 * kNumWalls + kWallCylinder].bridge = 25;
  PairRecord pr;
  pr.id_i = 0, pr.id_j = 1, pr.bridge = 25;
  s.pairs.push_back(pr);
  EXPECT_EQ(observe::free_liquid(s), 200);
  SimParams prm;
  prm.drum.radius = 0.07;
  EXPECT_DOUBLE_EQ(observe::observe_camera(s, prm, 400).liquid_free_fraction, 0.5);
}

}  // namespace
}  // namespace wetdem::test
#endif  // WETDEM_HAVE_APP
