// Measurement, not a check (issue 12 point 5), disabled in CI; run it with
//   WETDEM_DEVICE=cpu ./build/tests/wetdem_tests --gtest_also_run_disabled_tests
//     --gtest_filter='Measure.DISABLED_Float32KickLossOnRestingWetBed'
// How much of the half-kick increment dv = ½ Δt (F/m + g) float32 velocities lose on a resting wet bed: the
// demo slice settled for 0.25 s (its own settle), then the state's float32 velocities and forces. For every
// particle and component: the float32 result fl(v + fl(dv)) against the exact v + dv (double). Results in the
// docs/model.md ("Known differences from MercuryDPM").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/run/run.h"
#include "support/gpu.h"

namespace wetdem {
namespace {

TEST(Measure, DISABLED_Float32KickLossOnRestingWetBed) {
  const std::string out = testing::TempDir() + "/wetdem_measure_f32";
  std::filesystem::remove_all(out);
  app::RunOptions o;
  o.case_path = std::string(WETDEM_SOURCE_DIR) + "/assets/demo.toml";
  o.overrides = {"run.duration=\"0.002 s\"", "run.steady_state_start=\"0.001 s\"",
                 "run.sample_interval=\"0.001 s\"", "output.formats=[]", "output.snapshot_interval=\"0 s\""};
  o.out_dir = out;
  o.quiet = true;
  o.context = &test::gpu();
  const app::RunResult r = app::run_case(o);
  const SystemState& s = r.final_state;
  const double dt = r.summary["dt_s"].get<double>();
  const glm::dvec3 g(0.0, -9.81, 0.0);
  double sum_inc = 0, sum_loss = 0, max_v = 0, sum_v = 0;
  size_t lost_all = 0, comps = 0;
  glm::dvec3 p_loss(0.0), p_inc(0.0);
  double p_scale = 0;
  for (size_t k = 0; k < s.p.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      const float v = float(s.p.v[k][c]);
      const float dv32 = 0.5f * float(dt) * (float(s.p.f[k][c]) / float(s.p.mass[k]) + float(g[c]));
      const double dv = 0.5 * dt * (s.p.f[k][c] / s.p.mass[k] + g[c]);
      const double exact = double(v) + dv;
      const double got = double(v + dv32);
      const double loss = got - exact;
      ++comps;
      sum_inc += std::fabs(dv);
      sum_loss += std::fabs(loss);
      if (dv != 0.0 && got == double(v)) ++lost_all;
      p_loss[c] += s.p.mass[k] * loss;
      p_inc[c] += s.p.mass[k] * dv;
      p_scale += s.p.mass[k] * std::fabs(double(v));
    }
    max_v = std::max(max_v, glm::length(s.p.v[k]));
    sum_v += glm::length(s.p.v[k]);
  }
  std::printf(
      "particles %zu, dt %.4g s, mean |v| %.3g m/s, max |v| %.3g m/s\n"
      "mean |dv| per half kick %.3g m/s, mean |float32 loss| %.3g m/s: %.3g of the increment\n"
      "components whose whole increment is lost: %zu of %zu (%.3g)\n"
      "|sum m loss| per half kick %.3g kg m/s; sum m |v| %.3g kg m/s: ratio %.3g per half kick\n",
      s.p.size(), dt, sum_v / double(s.p.size()), max_v, sum_inc / double(comps), sum_loss / double(comps),
      sum_loss / sum_inc, lost_all, comps, double(lost_all) / double(comps), glm::length(p_loss), p_scale,
      glm::length(p_loss) / p_scale);
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace wetdem
