// Size segregation at the free surface (app/observe/segregation.h; drum.md finding 7): the mean radius of the
// surface layer over the mean radius of the bed, on synthetic beds with a known answer.
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "app/observe/segregation.h"
#include "app/observe/surface.h"
#include "support/synthetic_bed.h"

namespace wetdem::test {
namespace {

BedSpec spec() {
  BedSpec b;
  b.angle_deg = 35.0;
  return b;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / double(v.size());
}

TEST(ObserveSegregation, EqualSpheresGiveOne) {
  const SystemState s = make_bed(spec());
  const observe::SurfaceResult sf = observe::fit_surface(s, 0.07, spec().length);
  ASSERT_TRUE(sf.valid);
  EXPECT_NEAR(observe::surface_size_ratio(s, sf), 1.0, 1e-12);  // sums of equal radii in another order
}

TEST(ObserveSegregation, LargeParticlesOnTopGiveTheirRatio) {
  // The top row (the monolayer the surface fit takes per column) holds particles 1.2 times larger; the
  // positions stay on the grid, so the fitted layer is exactly that row.
  SystemState s = make_bed(spec());
  const glm::dvec2 n = normal(spec().angle_deg);
  const double top_h = spec().level;
  size_t big = 0;
  for (size_t k = 0; k < s.p.size(); ++k) {
    const double h = s.p.x[k].x * n.x + s.p.x[k].y * n.y;
    if (std::fabs(h - top_h) < 1e-9) s.p.radius[k] *= 1.2, ++big;
  }
  ASSERT_GT(big, 50u);
  const observe::SurfaceResult sf = observe::fit_surface(s, 0.07, spec().length);
  ASSERT_TRUE(sf.valid);
  for (size_t k : sf.layer) ASSERT_NEAR(s.p.radius[k], 1.2e-3, 1e-12) << "the layer is the top row";
  EXPECT_NEAR(observe::surface_size_ratio(s, sf), 1.2e-3 / mean(s.p.radius), 1e-12);
  EXPECT_GT(observe::surface_size_ratio(s, sf), 1.15);
}

TEST(ObserveSegregation, RandomRadiiOnFixedPositionsGiveAboutOne) {
  // Radii drawn independently of position (uniform in [0.8, 1.2] r): no segregation; the ratio is 1 within
  // the sampling error of the layer's mean (about 0.115 r / sqrt(layer size)).
  SystemState s = make_bed(spec());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.8e-3, 1.2e-3);
  for (double& r : s.p.radius) r = u(rng);
  const observe::SurfaceResult sf = observe::fit_surface(s, 0.07, spec().length);
  ASSERT_TRUE(sf.valid);
  const double err = 0.115 / std::sqrt(double(sf.layer.size()));
  EXPECT_NEAR(observe::surface_size_ratio(s, sf), 1.0, 5.0 * err) << sf.layer.size() << " in the layer";
}

TEST(ObserveSegregation, NoSurfaceNoRatio) {
  BedSpec b = spec();
  b.level = 0.06;  // the drum nearly full: centre of mass near the axis, bed flagged
  const SystemState s = make_bed(b);
  const observe::SurfaceResult sf = observe::fit_surface(s, 0.07, b.length);
  EXPECT_FALSE(sf.valid);
  EXPECT_TRUE(std::isnan(observe::surface_size_ratio(s, sf)));
}

}  // namespace
}  // namespace wetdem::test
#endif
