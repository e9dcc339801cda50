// Cost of the camera observables per sample against the steps between two samples (issue 9: < 5 % of a run),
// on the paper's PP2 l = 5 drum (~22k particles). A measurement, not a check: run it by hand with
//   ./build/tests/wetdem_tests --gtest_also_run_disabled_tests --gtest_filter='ObserveCost.*'
// The filled bed has no contacts yet, so 3 random bridges per particle are added to load the cluster search
// as a wet bed would; the steps are timed on the case's own device and time step.
#ifdef WETDEM_HAVE_APP
#include <gtest/gtest.h>

#include <time.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

#include "app/case/case.h"
#include "app/observe/camera.h"
#include "app/run/run.h"
#include "support/gpu.h"
#include "wetdem/observables.h"
#include "wetdem/system.h"

namespace wetdem::test {
namespace {

template <class F>
double median_seconds(int reps, F f) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) {
    const auto a = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

// Issue 19: a sample before (the whole state downloaded, compute_observables and the camera on the host) and
// after (System::sample_runs: the reductions on the device, a slim state, the camera on the host), on the PP2
// l = 5 bed after 1,000 steps of settling. Wall time, CPU time of the process (on lavapipe it includes the
// device's work, done by lavapipe's threads) and of the calling thread (the host's own work: transfers,
// conversion, reductions or not, camera).
TEST(ObserveCost, DISABLED_SampleBeforeAndAfterDeviceReductions) {
  const app::Case c = app::parse_case_file(std::string(WETDEM_SOURCE_DIR) + "/assets/pp2_l5.toml");
  app::Prepared p = app::prepare_run(c);
  const size_t n = p.state.p.size();
  System sys(gpu(), p.prm, n);
  sys.upload(p.state);
  sys.step(1000);
  const int64_t liquid = p.state.total_liquid();
  struct Cost {
    double wall = 0, proc = 0, thread = 0;
  };
  auto cpu = [](clockid_t id) {
    timespec t{};
    clock_gettime(id, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
  };
  auto measure = [&](int reps, auto f) {
    Cost best{1e9, 1e9, 1e9};
    for (int i = 0; i < reps; ++i) {
      const auto w0 = std::chrono::steady_clock::now();
      const double p0 = cpu(CLOCK_PROCESS_CPUTIME_ID), t0 = cpu(CLOCK_THREAD_CPUTIME_ID);
      f();
      const double t1 = cpu(CLOCK_THREAD_CPUTIME_ID), p1 = cpu(CLOCK_PROCESS_CPUTIME_ID);
      const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
      best.wall = std::min(best.wall, w), best.proc = std::min(best.proc, p1 - p0);
      best.thread = std::min(best.thread, t1 - t0);
    }
    return best;
  };
  size_t contacts = 0, bridges = 0;
  const Cost before = measure(5, [&] {
    const SystemState st = sys.download();
    const Observables o = compute_observables(st, p.prm);
    (void)observe::observe_camera(st, p.prm, liquid);
    contacts = o.contacts, bridges = o.bridges;
  });
  const Cost after = measure(5, [&] {
    const RunSample rs = sys.sample_runs()[0];
    (void)observe::observe_camera(rs.bed, p.prm, liquid, rs.obs.liquid_films + rs.obs.liquid_bridges);
  });
  const Cost step = measure(1, [&] { sys.step(100); });
  const double per_sample = c.run.sample_interval / p.derived.dt;
  std::printf(
      "[ObserveCost] PP2 l = 5, %zu particles, %zu contacts, %zu bridges, on %s; best of 5 (ms):\n"
      "[ObserveCost]   before (download + compute_observables + camera): wall %.1f, process CPU %.1f, thread "
      "CPU %.1f\n"
      "[ObserveCost]   after  (sample_runs + camera):                    wall %.1f, process CPU %.1f, thread "
      "CPU %.1f\n"
      "[ObserveCost]   100 steps: wall %.0f, process CPU %.0f; %.0f steps per sample\n",
      n, contacts, bridges, sys.device_name().c_str(), 1e3 * before.wall, 1e3 * before.proc,
      1e3 * before.thread, 1e3 * after.wall, 1e3 * after.proc, 1e3 * after.thread, 1e3 * step.wall,
      1e3 * step.proc, per_sample);
  EXPECT_LT(after.thread, before.thread);
}

}  // namespace
}  // namespace wetdem::test
#endif  // WETDEM_HAVE_APP
