// wetdem_bench: throughput of the GPU step on a filled drum (not a test). Fills the paper's drum (D = 0.14 m,
// L = 0.18 m, 5 rpm) with N polydisperse PP2-like particles (the PSD scaled so that N particles make a 36.5 %
// bed), lets it settle, then times steps: particle-steps per second for the whole step (wall clock) and for
// each pass (GPU timestamps, one profiled run). Ratios between passes are measured in one run.
#include <fmt/core.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/drum/fill.h"
#include "app/drum/psd.h"
#include "app/drum/scenarios.h"
#include "vk/context.h"
#include "wetdem/system.h"

using namespace wetdem;

namespace {

struct Setup {
  SimParams prm;
  SystemState state;
  double scale = 1.0;
};

Setup make_drum(size_t n, bool wet, uint64_t seed) {
  const double R = 0.07, L = 0.18, fill = 0.365;
  // Particle count scales as l^-3: pick l so that the 36.5 % bed holds n particles.
  const size_t n1 = particles_for_fill(Psd(psd_pp2(1.0)), R, L, fill);
  Setup s;
  s.scale = std::cbrt(double(n1) / double(n));
  Psd psd(psd_pp2(s.scale));
  FillSpec fs;
  fs.drum_radius = R;
  fs.drum_length = L;
  fs.count = n;
  fs.seed = seed;
  FillResult fr = fill_drum(fs, psd);
  const double rho = 900.0;
  SimParams& prm = s.prm;
  set_polypropylene_contacts(prm, 0.8, 0.3, *std::min_element(fr.radius.begin(), fr.radius.end()), rho);
  prm.drum.radius = R;
  prm.drum.length = L;
  prm.drum.omega = 5.0 * 2.0 * 3.14159265358979 / 60.0;
  s.state.p.resize(fr.x.size());
  double vs = 0.0;
  for (size_t k = 0; k < fr.x.size(); ++k) {
    set_sphere(s.state.p, k, fr.x[k], fr.radius[k], rho);
    vs += 4.0 / 3.0 * 3.14159265358979 * std::pow(fr.radius[k], 3);
  }
  vs /= double(fr.x.size());
  if (wet) {  // PP2 calibrated set: V_min = 10 %, V_max = 1 % of the mean volume, 10 vol % liquid as films
    prm.liquid_unit_m3 = vs * std::ldexp(1.0, -40);
    prm.liq_pp.enabled = true;
    prm.liq_pp.gamma = 0.0217 * s.scale;
    prm.liq_pp.theta = 30.0 * 3.14159265358979 / 180.0;
    prm.liq_pp.v_min = int64_t(0.10 * std::ldexp(1.0, 40));
    prm.liq_pp.v_max = int64_t(0.01 * std::ldexp(1.0, 40));
    for (size_t k = 0; k < fr.x.size(); ++k) {
      double v = 4.0 / 3.0 * 3.14159265358979 * std::pow(fr.radius[k], 3);
      s.state.p.film[k] = int64_t(0.10 * v / prm.liquid_unit_m3);
    }
  }
  return s;
}

// physics.md §7.8 at full length: the agitated wet slice of tests/test_liquid_soak.cpp for `steps` steps,
// total liquid compared exactly every 10,000 steps, events counted.
int soak(vk::Context& ctx, uint64_t steps, size_t n) {
  Scenario sc = tumbling_wet_slice(n, 3);
  System sys(ctx, sc.prm, sc.state.p.size());
  sys.upload(sc.state);
  const int64_t total = sc.state.total_liquid();
  uint64_t formations = 0, ruptures = 0, done = 0;
  auto t0 = std::chrono::steady_clock::now();
  while (done < steps) {
    const uint64_t k = std::min<uint64_t>(10000, steps - done);
    sys.step(k);
    done += k;
    EventCounts e = sys.read_events();
    formations += e.formations;
    ruptures += e.ruptures;
    const int64_t now = sys.download().total_liquid();
    double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fmt::print("soak: {} / {} steps, {} formations, {} ruptures, liquid {} ({}), {:.0f} steps/s\n", done,
               steps, formations, ruptures, now, now == total ? "exact" : "CHANGED", double(done) / el);
    std::fflush(stdout);  // progress lines must reach a log file as they happen
    if (now != total) return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"wetdem_bench: particle-steps per second of the GPU step, per pass"};
  std::vector<size_t> sizes{20000, 100000};
  uint64_t steps = 200, settle = 400;
  std::string device, json_path;
  bool dry = false;
  uint64_t soak_steps = 0;
  app.add_option("--n", sizes, "particle counts")->delimiter(',');
  app.add_option("--steps", steps, "timed steps per size");
  app.add_option("--settle", settle, "untimed steps before timing (the bed forms contacts)");
  app.add_option("--device", device, "device: index, name substring, cpu or gpu");
  app.add_flag("--dry", dry, "no liquid (default: wet, PP2 calibrated bridges)");
  app.add_option("--json", json_path, "write the results as JSON");
  app.add_option("--soak", soak_steps,
                 "instead: liquid-conservation soak of this many steps (physics.md §7.8)");
  CLI11_PARSE(app, argc, argv);

  try {
    vk::ContextOptions co;
    co.device = device;
    vk::Context ctx(co);
    if (soak_steps > 0) return soak(ctx, soak_steps, 2000);
    nlohmann::json out;
    out["device"] = ctx.info().describe();
    out["wet"] = !dry;
    for (size_t n : sizes) {
      Setup s = make_drum(n, !dry, 1);
      SystemOptions so;
      so.steps_per_submit = 100;
      System sys(ctx, s.prm, s.state.p.size(), so);
      sys.upload(s.state);
      sys.step(settle);
      auto t0 = std::chrono::steady_clock::now();
      sys.step(steps);
      double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      Observables o = sys.observables();
      SystemCounters c = sys.counters();

      // Per pass: a second run of the same steps with a timestamp before every pass.
      so.profile_passes = true;
      System prof(ctx, s.prm, s.state.p.size(), so);
      prof.upload(sys.download());
      prof.step(steps);
      auto passes = prof.pass_timings();
      double total = 0.0;
      for (auto& p : passes) total += p.seconds;
      std::sort(passes.begin(), passes.end(), [](auto& a, auto& b) { return a.seconds > b.seconds; });

      const double pss = double(n) * double(steps) / wall;
      fmt::print(
          "\n{} particles (PP2 scaled x{:.2f}), {} steps, dt {:.3g} s, {} contacts, {} bridges, {} "
          "rebuilds\n",
          n, s.scale, steps, s.prm.dt, o.contacts, o.bridges, c.rebuilds);
      std::fflush(stdout);
      fmt::print("  step: {:.3g} particle-steps/s ({:.3g} s wall per step) on {}\n", pss,
                 wall / double(steps), ctx.info().name);
      nlohmann::json jn;
      jn["particles"] = n;
      jn["steps"] = steps;
      jn["particle_steps_per_s"] = pss;
      jn["contacts"] = o.contacts;
      jn["bridges"] = o.bridges;
      jn["rebuilds"] = c.rebuilds;
      if (total > 0) {
        fmt::print("  {:<20} {:>12} {:>8} {:>16}\n", "pass", "s/step", "share", "particle-steps/s");
        for (auto& p : passes) {
          double per_step = p.seconds / double(steps);
          fmt::print("  {:<20} {:>12.3g} {:>7.1f}% {:>16.3g}\n", p.name, per_step, 100.0 * p.seconds / total,
                     double(n) / per_step);
          jn["passes"][p.name] = {{"seconds_per_step", per_step}, {"share", p.seconds / total}};
        }
      } else {
        fmt::print("  (no GPU timestamps on this device: per-pass times unavailable)\n");
      }
      out["runs"].push_back(jn);
    }
    if (!json_path.empty()) std::ofstream(json_path) << out.dump(2) << "\n";
  } catch (const std::exception& e) {
    fmt::print(stderr, "wetdem_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
