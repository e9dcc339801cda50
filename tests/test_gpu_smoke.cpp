// Smallest end-to-end checks of the GPU system: upload/download round trip and a two-particle collision.
#include <gtest/gtest.h>

#include "support/gpu.h"
#include "support/twin.h"
#include "wetdem/system.h"

namespace wetdem::test {

class GpuSmoke : public GpuTest {};

TEST_F(GpuSmoke, UploadDownloadRoundTrip) {
  SimParams prm = twin_drum_params(0.03, 0.02, 1e-3, false);
  SystemState s;
  s.p.resize(2);
  set_sphere(s.p, 0, {0.0, -0.02, 0.0}, 1e-3, 900);
  set_sphere(s.p, 1, {0.0, -0.02 + 1.99e-3, 0.0}, 1e-3, 900);
  s.p.film[1] = 12345;
  System sys(gpu(), prm, 2);
  sys.upload(s);
  quantize(s, sys.tick_size());
  sys.upload(s);
  SystemState g = sys.download();
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(g.p.x[k], s.p.x[k]);
    EXPECT_FLOAT_EQ(float(g.p.radius[k]), float(s.p.radius[k]));
  }
  EXPECT_EQ(g.p.film[1], 12345);
  try {
    sys.step(1);
  } catch (const std::exception& e) {
    FAIL() << e.what();
  }
  g = sys.download();
  EXPECT_EQ(g.step, 1u);
  // Overlapping pair: pushed apart along y.
  EXPECT_LT(g.p.f[0].y, 0.0);
  EXPECT_GT(g.p.f[1].y, 0.0);
}

}  // namespace wetdem::test
