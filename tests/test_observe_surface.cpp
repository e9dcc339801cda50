// Camera observables of the free surface (app/observe/surface.h) on synthetic beds with known answers: the
// fitted angle of a noisy plane surface, the downhill speed of a rigidly rotating bed (ω times the distance
// of the surface layer from the axis), and the depth where a set velocity profile changes sign.
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <cmath>

#include "app/drum/aor.h"
#include "app/observe/surface.h"
#include "support/synthetic_bed.h"

namespace wetdem::test {
namespace {

using observe::fit_surface;
using observe::SurfaceResult;

TEST(ObserveSurface, NoisyPlaneSurfaceAngleWithinTwoTenthsOfADegree) {
  for (double angle : {20.0, 35.0, 50.0, -30.0}) {
    BedSpec b;
    b.angle_deg = angle;
    b.jitter = 0.25;  // every coordinate ±0.5 mm on 2 mm particles
    b.seed = 7 + unsigned(std::fabs(angle));
    const SystemState s = make_bed(b);
    const SurfaceResult r = fit_surface(s, b.drum_radius, b.length);
    ASSERT_TRUE(r.valid) << angle;
    EXPECT_NEAR(r.angle_deg, angle, 0.2) << angle;
    EXPECT_GE(r.columns, 15u);
    EXPECT_LT(r.angle_se_deg, 0.2) << angle;
    // Third source: the centre of mass of a flat-surfaced segment lies on the surface's normal through the
    // axis (app/drum/aor.h), so the two angles agree on this bed.
    EXPECT_NEAR(dynamic_aor(s, b.drum_radius).signed_deg, angle, 0.3) << angle;
  }
}

TEST(ObserveSurface, SurfaceAngleIsNotTheCentreOfMassAngle) {
  // A plane surface at 30° over a bed whose deep part is cut away on the +x side: the centre of mass moves to
  // -x (its angle drops well below 30°) while the surface, and the fitted angle, stay at 30°.
  BedSpec b;
  b.angle_deg = 30.0;
  b.jitter = 0.1;
  SystemState full = make_bed(b);
  SystemState s;
  std::vector<size_t> keep;
  const glm::dvec2 t = tangent(30.0), n = normal(30.0);
  for (size_t k = 0; k < full.p.size(); ++k) {
    const glm::dvec2 p(full.p.x[k].x, full.p.x[k].y);
    if (glm::dot(p, t) > 0.0 && glm::dot(p, n) < b.level - 0.012) continue;  // cut below 6 rows, u > 0
    keep.push_back(k);
  }
  s.p.resize(keep.size());
  for (size_t i = 0; i < keep.size(); ++i)
    set_sphere(s.p, i, full.p.x[keep[i]], full.p.radius[keep[i]], 900.0);
  const SurfaceResult r = fit_surface(s, b.drum_radius, b.length);
  ASSERT_TRUE(r.valid);
  EXPECT_LT(r.com_angle_deg, 25.0);
  EXPECT_NEAR(r.angle_deg, 30.0, 0.2);
}

TEST(ObserveSurface, RigidRotationGivesOmegaTimesSurfaceRadius) {
  // Rigid rotation v = ω z × x: the component along a line at distance ρ from the axis is ω ρ everywhere on
  // it, so the surface layer (the top grid row, at ρ = |level|) moves uphill at ω ρ with the drum (ω > 0)
  // and downhill at |ω| ρ against it.
  for (double omega : {2.0, -3.0}) {
    BedSpec b;
    b.angle_deg = 35.0;
    b.level = -0.021;
    SystemState s = make_bed(b);
    for (size_t k = 0; k < s.p.size(); ++k) s.p.v[k] = omega * glm::dvec3(-s.p.x[k].y, s.p.x[k].x, 0.0);
    const SurfaceResult r = fit_surface(s, b.drum_radius, b.length);
    ASSERT_TRUE(r.valid);
    EXPECT_NEAR(r.angle_deg, 35.0, 1e-9);
    EXPECT_NEAR(r.height_m, b.level, 1e-12);
    EXPECT_NEAR(r.downhill_speed_mps, -omega * 0.021, 1e-12) << omega;
    if (omega > 0)
      EXPECT_EQ(r.flowing_layer_depth_m, 0.0);  // the surface itself goes uphill: no flowing layer
    else
      EXPECT_TRUE(std::isnan(r.flowing_layer_depth_m));  // downhill at every depth: no sign change in the bed
  }
}

// Velocity along the surface, downhill speed U (1 - δ/δ0) at depth δ below the top row: changes sign at δ0.
SystemState sheared_bed(const BedSpec& b, double U, double delta0) {
  SystemState s = make_bed(b);
  const glm::dvec2 t = tangent(b.angle_deg), n = normal(b.angle_deg);
  for (size_t k = 0; k < s.p.size(); ++k) {
    const double depth = b.level - glm::dot(glm::dvec2(s.p.x[k].x, s.p.x[k].y), n);
    const double v = U * (1.0 - depth / delta0);
    s.p.v[k] = glm::dvec3(-v * t.x, -v * t.y, 0.0);  // downhill = -t for a positive angle
  }
  return s;
}

TEST(ObserveSurface, FlowingLayerDepthIsWhereDownhillVelocityChangesSign) {
  BedSpec b;
  b.angle_deg = 40.0;
  const double delta0 = 3.3 * b.d;
  const SurfaceResult r = fit_surface(sheared_bed(b, 0.2, delta0), b.drum_radius, b.length);
  ASSERT_TRUE(r.valid);
  EXPECT_NEAR(r.downhill_speed_mps, 0.2, 1e-12);       // the top row is the surface layer
  EXPECT_NEAR(r.flowing_layer_depth_m, delta0, 1e-9);  // linear profile: interpolation is exact

  // The same with ±0.2 d of position noise: within half a diameter.
  b.jitter = 0.2;
  const SurfaceResult q = fit_surface(sheared_bed(b, 0.2, delta0), b.drum_radius, b.length);
  ASSERT_TRUE(q.valid);
  EXPECT_NEAR(q.flowing_layer_depth_m, delta0, 0.5 * b.d);
  EXPECT_NEAR(q.downhill_speed_mps, 0.2, 0.03);
}

TEST(ObserveSurface, NearCentredBedHasNoSurface) {
  SystemState s;
  s.p.resize(2);
  set_sphere(s.p, 0, {0.001, 0.0, 0.0}, 1e-3, 900.0);
  set_sphere(s.p, 1, {-0.001, 0.0, 0.0}, 1e-3, 900.0);
  EXPECT_FALSE(fit_surface(s, 0.07, 0.02).valid);
  EXPECT_FALSE(fit_surface(SystemState{}, 0.07, 0.02).valid);
}

}  // namespace
}  // namespace wetdem::test
#endif  // WETDEM_HAVE_APP
