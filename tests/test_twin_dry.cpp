// Twin test (issue #2): the GPU system and the CPU reference on >= 2,000 random particles in a drum,
// compared step by step (each step starts both from the reference's state).
#include <gtest/gtest.h>

#include "reference/reference.h"
#include "support/gpu.h"
#include "support/lockstep.h"
#include "support/twin.h"
#include "wetdem/system.h"

namespace wetdem::test {

class TwinDry : public GpuTest {};

TEST_F(TwinDry, ForcesAndTorquesMatchReferenceEveryStep) {
  const double r_lo = 0.9e-3, r_hi = 1.0e-3;
  SimParams prm = twin_drum_params(0.03, 0.02, r_lo, false);
  SystemState s = random_drum_packing(prm, 2200, r_lo, r_hi, 7);
  ASSERT_GE(s.p.size(), 2000u);
  System gpu_sys(gpu(), prm, s.p.size());
  ref::ReferenceSystem ref_sys(prm);

  double worst_f = 0.0, worst_t = 0.0;
  size_t max_pairs = 0;
  for (int step = 0; step < 100; ++step) {
    const auto [r, g] = step_both(ref_sys, gpu_sys, s);
    double ef = norm_scaled_error(g.p.f, r.p.f), et = norm_scaled_error(g.p.t, r.p.t);
    worst_f = std::max(worst_f, ef);
    worst_t = std::max(worst_t, et);
    ASSERT_LT(ef, 1e-5) << "force, step " << step;
    ASSERT_LT(et, 1e-5) << "torque, step " << step;
    ASSERT_EQ(g.pairs.size(), r.pairs.size()) << "persistent pairs, step " << step;
    max_pairs = std::max(max_pairs, r.pairs.size());
    s = r;
  }
  EXPECT_GT(max_pairs, s.p.size());  // a dense packing: more touching pairs than particles
  std::printf("twin dry: %zu particles, up to %zu pairs, worst force error %.3g, torque error %.3g\n",
              s.p.size(), max_pairs, worst_f, worst_t);
}

}  // namespace wetdem::test
