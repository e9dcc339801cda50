// wetdem_bench: throughput of the real run on the shipped cases (not a test). Each case is brought into
// rotation through the run phases (bench/steady.h, cached), then N steps are timed on the wall clock and
// again with a GPU timestamp before every pass. Reports particle-steps/s, per-pass shares, the rebuild
// interval, contacts, bridges, neighbour entries, device bytes per particle and the step's memory traffic
// against the device's bandwidth (bench/traffic.h). docs/benchmark.md defines every column.
#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include <sys/resource.h>
// Under callgrind (valgrind --tool=callgrind --instr-atstart=no), --timed-only counts instructions in the
// timed steps only: a measure of the work that the machine's load does not change. No-ops otherwise.
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define WETDEM_TIMED_BEGIN() CALLGRIND_START_INSTRUMENTATION
#define WETDEM_TIMED_END()        \
  CALLGRIND_STOP_INSTRUMENTATION; \
  CALLGRIND_DUMP_STATS
#else
#define WETDEM_TIMED_BEGIN()
#define WETDEM_TIMED_END()
#endif

#include "app/drum/scenarios.h"
#include "app/run/resources.h"
#include "app/run/session.h"
#include "bench/steady.h"
#include "bench/table.h"
#include "bench/traffic.h"
#include "vk/context.h"
#include "wetdem/system.h"
#include "wetdem/version.h"

using namespace wetdem;
namespace fs = std::filesystem;

namespace {

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

std::string default_cache() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    return (fs::path(x) / "wetdem" / "bench").string();
  if (const char* h = std::getenv("HOME"); h && *h)
    return (fs::path(h) / ".cache" / "wetdem" / "bench").string();
  return ".wetdem-bench-cache";
}

struct Options {
  uint64_t steps = 1000, warmup = 0;
  bool warmup_given = false;
  std::vector<size_t> ensembles;  // also time ensembles of this many copies of the steady drum
  double bandwidth_gbs = 0;
  bench::SteadyOptions steady;
  // --timed-only: one System restored from the steady state with these options, timed, nothing else (for
  // instruction counts under callgrind, where the machine's load does not enter).
  bool timed_only = false;
  SystemOptions timed_options;
  // --skin-mm: also time the same steady state with these neighbour-list skins (one run, and the largest
  // ensemble). The rebuild schedule does not change a run's results (ARCHITECTURE.md), so this is a pure
  // speed lever: fewer rebuilds against more entries per particle.
  std::vector<double> skins_mm;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds of this process, every thread (lavapipe's workers included): on a loaded machine the wall
// clock moves with the other jobs, the CPU time much less.
double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Wall and CPU seconds of `steps` steps.
struct Timed {
  double wall = 0, cpu = 0;
};
Timed time_steps(System& sys, uint64_t steps, bool count_instructions = false) {
  const double c0 = process_cpu_s();
  const auto t0 = std::chrono::steady_clock::now();
  if (count_instructions) {
    WETDEM_TIMED_BEGIN();
  }
  sys.step(steps);
  if (count_instructions) {
    WETDEM_TIMED_END();
  }
  return {seconds_since(t0), process_cpu_s() - c0};
}

nlohmann::json bench_case(vk::Context& ctx, const app::Case& c, const std::string& variant, const Options& o,
                          const bench::Log& log) {
  bench::Steady st = bench::reach_steady(ctx, c, o.steady, log);
  const app::Prepared& prep = *st.prep;
  const size_t n = prep.state.p.size();
  const double dt = prep.derived.dt;
  const uint64_t warmup = o.warmup_given ? o.warmup : prep.c.run.steps_per_submit;
  nlohmann::json j;
  j["case"] = prep.c.name.empty() ? fs::path(prep.c.source).stem().string() : prep.c.name;
  j["file"] = prep.c.source;
  j["variant"] = variant;
  j["wet"] = prep.c.liquid.on();
  j["particles"] = n;
  j["dt_s"] = dt;
  j["periodic_slice"] = prep.c.drum.periodic_slice;

  // Where the timed steps start: the same for both paths below (the log line reads it).
  const uint64_t start_step = st.step + warmup;
  j["timing"] = {{"start_step", start_step},
                 {"start_time_s", double(start_step) * dt},
                 {"settle_s", st.settle_s},
                 {"rotation_s", double(start_step) * dt - st.settle_s},
                 {"steady_state_start_s", prep.c.run.steady_state_start},
                 {"rotation_fraction_of_steady_start",
                  prep.c.run.steady_state_start > 0
                      ? (double(start_step) * dt - st.settle_s) / prep.c.run.steady_state_start
                      : 1.0},
                 {"revolutions", (double(start_step) * dt - st.settle_s) * prep.c.drum.omega /
                                     (2.0 * 3.14159265358979323846)},
                 {"warmup_steps", warmup},
                 {"steps", o.steps},
                 {"from_cache", st.from_cache},
                 {"prepare_wall_s", st.prepare_wall_s},
                 {"cache", st.cache_path}};
  if (o.timed_only) {
    SystemOptions so = o.timed_options;
    so.steps_per_submit = prep.c.run.steps_per_submit;
    app::DrumSession s(ctx, prep, st.ck, [](const std::string&) {});
    System sys(ctx, s.system().params(), n, so);
    sys.restore(st.ck.system);
    sys.step(warmup);
    const uint64_t r0 = sys.counters().rebuilds;
    const Timed t = time_steps(sys, o.steps, true);
    const uint64_t rebuilds = sys.counters().rebuilds - r0;
    log(fmt::format(
        "{} {}: timed only, {} steps: {:.3g} s wall, {:.3g} s CPU ({:.3g} ms CPU per step), "
        "{:.1f} dispatches per step, {} rebuilds (one per {:.3g} steps)",
        prep.c.name, variant, o.steps, t.wall, t.cpu, 1e3 * t.cpu / double(o.steps),
        sys.counters().dispatches_per_step, rebuilds, rebuilds ? double(o.steps) / double(rebuilds) : 0.0));
    j["rebuilds"] = rebuilds;
    j["particle_steps_per_s"] = double(n) * double(o.steps) / t.wall;
    j["cpu_s_per_step"] = t.cpu / double(o.steps);
    j["dispatches_per_step"] = sys.counters().dispatches_per_step;
    j["timing"]["wall_s"] = t.wall;
    return j;
  }
  // Wall clock: the run's own session resumed from the steady state (the case's steps_per_submit).
  double wall = 0, cpu = 0;
  uint64_t rebuilds = 0, liquid_steps = 0;
  Observables obs;
  SystemCounters ctr;
  DeviceMemory mem;
  SimParams rotating_prm;
  double context_bytes = 0;
  {
    app::DrumSession s(ctx, prep, st.ck, [](const std::string&) {});
    System& sys = s.system();
    rotating_prm = sys.params();
    sys.step(warmup);  // records the command buffers; not timed
    const SystemCounters c0 = sys.counters();
    const Timed t = time_steps(sys, o.steps);
    wall = t.wall;
    cpu = t.cpu;
    ctr = sys.counters();
    rebuilds = ctr.rebuilds - c0.rebuilds;
    liquid_steps = ctr.liquid_steps - c0.liquid_steps;
    log(fmt::format("{} {}: timed {} steps: {:.3g} s wall, {:.3g} s CPU ({:.3g} ms CPU per step)",
                    prep.c.name, variant, o.steps, wall, cpu, 1e3 * cpu / double(o.steps)));
    obs = sys.observables();
    mem = sys.device_memory();
    context_bytes = double(ctx.device_bytes());  // this session's system is the only one alive
  }
  const double pss = double(n) * double(o.steps) / wall;
  const auto interval = bench::rebuild_interval(o.steps, rebuilds);
  j["timing"]["wall_s"] = wall;
  j["particle_steps_per_s"] = pss;
  j["steps_per_s"] = double(o.steps) / wall;
  j["cpu_s_per_step"] = cpu / double(o.steps);
  j["cpu_particle_steps_per_s"] = double(n) * double(o.steps) / cpu;
  j["dispatches_per_step"] = ctr.dispatches_per_step;
  j["liquid_pass_fraction"] = double(liquid_steps) / double(o.steps);
  j["rebuilds"] = rebuilds;
  j["rebuild_interval_steps"] = interval ? nlohmann::json(*interval) : nlohmann::json(nullptr);
  j["contacts"] = obs.contacts;
  j["bridges"] = obs.bridges;
  j["neighbour_entries"] = ctr.entries;
  j["entries_per_particle"] = double(ctr.entries) / double(n);
  const app::ResourceEstimate est = app::estimate_resources(prep.c);  // what `wetdem check` says, to compare
  j["estimate"] = {{"entries_in_list_per_particle", est.entries_in_list},
                   {"entries_allocated_per_particle", est.entries_per_particle},
                   {"device_bytes_per_particle", est.device_bytes / est.particles}};

  // Device memory from the real buffer sizes.
  const double cap_per_set = 0.5 * double(mem.entry_capacity);
  bench::ElementBytes eb;
  eb.particle_set = 0.5 * double(mem.particle_sets) / double(n);
  eb.particle_scratch = double(mem.particle_scratch) / double(n);
  eb.entry_set = cap_per_set > 0 ? 0.5 * double(mem.entry_sets) / cap_per_set : 0.0;
  eb.entry_scratch = cap_per_set > 0 ? double(mem.entry_scratch) / cap_per_set : 0.0;
  const double epp = double(ctr.entries) / double(n);
  j["memory"] = {
      {"particle_set_bytes_per_particle", eb.particle_set},
      {"particle_scratch_bytes_per_particle", eb.particle_scratch},
      {"entry_set_bytes_per_entry", eb.entry_set},
      {"entry_scratch_bytes_per_entry", eb.entry_scratch},
      {"entry_capacity_per_particle", cap_per_set / double(n)},
      {"bytes_per_particle_at_measured_entries", bench::bytes_per_particle(eb, epp)},
      {"system_bytes", mem.total()},
      {"system_bytes_per_particle", double(mem.total()) / double(n)},
      {"context_bytes", context_bytes},
      {"context_bytes_per_particle", context_bytes / double(n)},
  };

  // Traffic against bandwidth.
  const bench::Traffic t = bench::step_traffic(eb, double(n), double(ctr.entries), interval);
  bench::Bandwidth bw = bench::default_bandwidth(ctx.info().name);
  if (o.bandwidth_gbs > 0) bw = {o.bandwidth_gbs, "--bandwidth"};
  nlohmann::json jt = {{"bytes_per_step", t.per_step},
                       {"bytes_every_step", t.every_step},
                       {"bytes_per_rebuild", t.per_rebuild},
                       {"bytes_per_particle_step", t.per_particle_step},
                       {"achieved_gbs", t.per_step * double(o.steps) / wall / 1e9},
                       {"bandwidth_gbs", bw.gbs},
                       {"bandwidth_source", bw.source}};
  if (bw.gbs > 0) {
    jt["roofline_particle_steps_per_s"] = bw.gbs * 1e9 / t.per_particle_step;
    jt["fraction_of_roofline"] = pss / (bw.gbs * 1e9 / t.per_particle_step);
  }
  j["traffic"] = jt;

  // The same steps with the rebuild chain recorded, gated, into every step (SystemOptions::split_rebuilds
  // off): the speed-up of split rebuilds measured in this run, on this device.
  // A System in the timed run's state after its warm-up, with other options (the replays below).
  // With other parameters (another skin: the restored list was built with the case's, so the first step
  // rebuilds it with the new one).
  auto replay = [&](SystemOptions so, const SimParams* prm = nullptr) {
    so.steps_per_submit = prep.c.run.steps_per_submit;
    auto sys = std::make_unique<System>(ctx, prm ? *prm : rotating_prm, n, so);
    sys->restore(st.ck.system);
    if (prm) sys->force_rebuild();
    sys->step(warmup);
    return sys;
  };
  // Levers (docs/benchmark.md "Levers"): the same steps from the same state with one SystemOptions switch
  // turned back; rate and CPU time of each against the timed run's.
  auto lever = [&](SystemOptions so) {
    auto sys = replay(so);
    const uint64_t r0 = sys->counters().rebuilds;
    const Timed tl = time_steps(*sys, o.steps);
    const double r = double(n) * double(o.steps) / tl.wall;
    return nlohmann::json{{"particle_steps_per_s", r},
                          {"rebuilds", sys->counters().rebuilds - r0},
                          {"cpu_s_per_step", tl.cpu / double(o.steps)},
                          {"dispatches_per_step", sys->counters().dispatches_per_step},
                          {"speedup", pss / r},
                          {"cpu_speedup", tl.cpu / cpu}};
  };
  {
    SystemOptions so;
    so.split_rebuilds = false;
    j["gated_rebuilds"] = lever(so);
    j["gated_rebuilds"]["split_speedup"] = j["gated_rebuilds"]["speedup"];
  }
  j["levers"] = nlohmann::json::object();
  {
    SystemOptions so;
    so.fused_step = false;
    j["levers"]["fused_step"] = lever(so);
  }
  if (prep.c.liquid.on()) {
    SystemOptions so;
    so.liquid_gate = false;
    j["levers"]["liquid_gate"] = lever(so);
  }
  {
    // The one-dispatch sort of a bed of up to one tile (2,048 particles): off, the multi-pass sort.
    SystemOptions so;
    so.one_tile_sort = false;
    j["levers"]["one_tile_sort"] = lever(so);
  }
  {
    // The skin test's rule: the classic max displacement > skin/2 in the lab frame (the drum frame and the
    // two largest displacements off, each, then both).
    for (auto [name, frame, two] :
         {std::tuple{"skin_drum_frame", false, true}, std::tuple{"skin_top_two", true, false},
          std::tuple{"skin_rule", false, false}}) {
      SystemOptions so;
      so.skin_drum_frame = frame;
      so.skin_top_two = two;
      j["levers"][name] = lever(so);
    }
  }
  {
    // The planner's threshold: split rebuilds at any interval (the default records the gated chain into
    // every step while rebuilds come less than split_min_interval steps apart).
    SystemOptions so;
    so.split_min_interval = 1.0;
    j["levers"]["split_min_interval"] = lever(so);
  }

  // k runs of this drum from its steady state with parameters `prm`, stepped together in one System; run r's
  // sliding friction is scaled by 1 + 1e-3 r so that the runs part ways. Aggregate particle-steps/s.
  std::optional<SystemState> start;
  auto time_ensemble = [&](size_t k, const SimParams& prm, uint64_t* ens_rebuilds) {
    if (!start) {
      app::DrumSession s(ctx, prep, st.ck, [](const std::string&) {});
      start = s.system().download();
    }
    std::vector<SimParams> prms(k, prm);
    for (size_t r = 0; r < k; ++r) prms[r].pp.mu_s *= 1.0 + 1e-3 * double(r);
    SystemOptions so;
    so.steps_per_submit = prep.c.run.steps_per_submit;
    System ens(ctx, prms, std::vector<size_t>(k, n), so);
    ens.upload_runs(std::vector<SystemState>(k, *start));
    ens.step(warmup);
    const auto t0 = std::chrono::steady_clock::now();
    ens.step(o.steps);
    const double agg = double(k) * double(n) * double(o.steps) / seconds_since(t0);
    if (ens_rebuilds) *ens_rebuilds = ens.counters().rebuilds;
    return agg;
  };

  // Ensembles (docs/ensembles.md): its ratio to the one run timed above (same device, same run).
  if (!o.ensembles.empty()) {
    j["ensembles"] = nlohmann::json::array();
    for (size_t k : o.ensembles) {
      uint64_t ens_rebuilds = 0;
      const double agg = time_ensemble(k, rotating_prm, &ens_rebuilds);
      j["ensembles"].push_back({{"runs", k},
                                {"particles", k * n},
                                {"particle_steps_per_s", agg},
                                {"speedup_over_one_run", agg / pss},
                                {"rebuilds", ens_rebuilds}});
      log(fmt::format("ensemble of {} x {}: {:.3g} particle-steps/s ({:.2f}x one run)", k, n, agg,
                      agg / pss));
    }
  }

  // Skins: the same steps from the same state with another neighbour-list skin, one run and the largest
  // ensemble.
  if (!o.skins_mm.empty()) {
    const size_t k = o.ensembles.empty() ? 0 : *std::max_element(o.ensembles.begin(), o.ensembles.end());
    j["skins"] = nlohmann::json::array();
    for (double mm : o.skins_mm) {
      SimParams q = rotating_prm;
      q.skin = 1e-3 * mm;
      auto one = replay(SystemOptions{}, &q);
      const SystemCounters c0 = one->counters();
      const Timed t1 = time_steps(*one, o.steps);
      const uint64_t rb = one->counters().rebuilds - c0.rebuilds;
      const auto iv = bench::rebuild_interval(o.steps, rb);
      nlohmann::json e = {{"skin_m", q.skin},
                          {"skin_over_r_min", q.skin / prep.derived.r_min},
                          {"particle_steps_per_s", double(n) * double(o.steps) / t1.wall},
                          {"speedup_over_case_skin", double(n) * double(o.steps) / t1.wall / pss},
                          {"rebuilds", rb},
                          {"rebuild_interval_steps", iv ? nlohmann::json(*iv) : nlohmann::json(nullptr)},
                          {"entries_per_particle", double(one->counters().entries) / double(n)}};
      one.reset();
      if (k > 0) e["ensemble"] = {{"runs", k}, {"particle_steps_per_s", time_ensemble(k, q, nullptr)}};
      log(
          fmt::format("skin {:.3g} mm ({:.2f} r_min): {:.3g} particle-steps/s ({:.2f}x the case's skin), "
                      "rebuild every {} steps, {:.1f} entries/particle{}",
                      mm, e["skin_over_r_min"].get<double>(), e["particle_steps_per_s"].get<double>(),
                      e["speedup_over_case_skin"].get<double>(), iv ? fmt::format("{:.1f}", *iv) : "-",
                      e["entries_per_particle"].get<double>(),
                      k > 0 ? fmt::format("; ensemble of {}: {:.3g} aggregate", k,
                                          e["ensemble"]["particle_steps_per_s"].get<double>())
                            : ""));
      j["skins"].push_back(e);
    }
  }

  // Per pass: the same steps from the same state with a timestamp before every pass.
  {
    SystemOptions so;
    so.profile_passes = true;
    auto prof = replay(so);
    prof->reset_pass_timings();
    prof->step(o.steps);
    auto passes = prof->pass_timings();
    double total = 0;
    for (auto& p : passes) total += p.seconds;
    std::sort(passes.begin(), passes.end(), [](auto& a, auto& b) { return a.seconds > b.seconds; });
    j["passes"] = nlohmann::json::array();
    for (auto& p : passes)
      j["passes"].push_back({{"name", p.name},
                             {"seconds_per_step", p.seconds / double(o.steps)},
                             {"share", total > 0 ? p.seconds / total : 0.0},
                             {"dispatches", p.dispatches}});
    j["profiled_gpu_seconds_per_step"] = total / double(o.steps);
  }
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "wetdem_bench: particle-steps per second of real runs in rotation, per pass (docs/benchmark.md)"};
  app.footer(
      "Example: wetdem_bench assets/studies/micro/micro_case.toml --variants wet --steps 1000 --ensemble 8");
  std::vector<std::string> cases{"assets/demo.toml", "assets/demo_closed.toml", "assets/pp2_l5.toml",
                                 "assets/pp2_l3.toml", "assets/pp1_l3.toml"};
  std::vector<std::string> variants{"wet", "dry"}, sets;
  std::string device, json_path;
  Options o;
  bool no_cache = false;
  uint64_t soak_steps = 0;
  o.steady.cache_dir = default_cache();
  app.add_option("cases", cases, "case files (default: the shipped benchmark set)");
  app.add_option("--variants", variants, "wet (as shipped) and/or dry (liquid.content = 0)")->delimiter(',');
  app.add_option("--set", sets, "override a case key for every case: dotted.key=value");
  app.add_option("--steps", o.steps, "timed steps per case (default 1000)");
  app.add_option("--warmup", o.warmup, "untimed steps after the steady state (default: one submit)");
  app.add_option("--settle-s", o.steady.settle_s,
                 "simulated seconds of settling (default: the case's run.settle)");
  app.add_option("--rotate-s", o.steady.rotate_s,
                 "simulated seconds of rotation before timing (default: the case's run.steady_state_start)");
  app.add_option("--cache", o.steady.cache_dir,
                 "folder of the steady-state checkpoints (default ~/.cache/wetdem/bench)");
  app.add_flag("--no-cache", no_cache, "prepare every case again and keep nothing");
  app.add_option("--bandwidth", o.bandwidth_gbs, "device memory bandwidth in GB/s (default: by device name)");
  app.add_option("--device", device, "device: index, name substring, cpu or gpu");
  app.add_option("--json", json_path, "write the results as JSON");
  app.add_option("--ensemble", o.ensembles,
                 "also time ensembles of these many copies of each drum in one System, e.g. 8,32")
      ->delimiter(',');
  app.add_flag("--timed-only", o.timed_only,
               "time one System restored from the steady state with the options below, nothing else");
  app.add_option("--fused-step", o.timed_options.fused_step, "with --timed-only: SystemOptions::fused_step");
  app.add_option("--skin-drum-frame", o.timed_options.skin_drum_frame,
                 "with --timed-only: SystemOptions::skin_drum_frame");
  app.add_option("--skin-top-two", o.timed_options.skin_top_two,
                 "with --timed-only: SystemOptions::skin_top_two");
  app.add_option("--liquid-gate", o.timed_options.liquid_gate,
                 "with --timed-only: SystemOptions::liquid_gate");
  app.add_option("--one-tile-sort", o.timed_options.one_tile_sort,
                 "with --timed-only: SystemOptions::one_tile_sort");
  app.add_option("--split-min-interval", o.timed_options.split_min_interval,
                 "with --timed-only: SystemOptions::split_min_interval");
  app.add_option("--skin-mm", o.skins_mm,
                 "also time the same steady state with these neighbour-list skins in mm, e.g. 0.38,0.76")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  app.add_option("--soak", soak_steps,
                 "instead: liquid-conservation soak of this many steps (physics.md §7.8)");
  CLI11_PARSE(app, argc, argv);
  o.warmup_given = app.count("--warmup") > 0;
  if (no_cache) o.steady.cache_dir.clear();

  try {
    vk::ContextOptions co;
    co.device = device;
    co.quiet = true;
    vk::Context ctx(co);
    if (soak_steps > 0) return soak(ctx, soak_steps, 2000);
    // Every case and override is checked before any work.
    std::vector<std::pair<app::Case, std::string>> todo;
    for (const std::string& v : variants) {
      if (v != "wet" && v != "dry") throw app::CaseError("--variants", "wet or dry, got " + v);
      for (const std::string& f : cases) {
        std::vector<std::string> s = sets;
        if (v == "dry") s.push_back("liquid.content=0");
        todo.emplace_back(app::parse_case_file(f, s), v);
        // Every --skin-mm must fit the case's geometry (a periodic slice holds twice the neighbour reach).
        for (double mm : o.skins_mm) {
          app::Case q = todo.back().first;
          q.run.skin = 1e-3 * mm;
          try {
            app::check_reach(q);
          } catch (const app::CaseError& e) {
            throw app::CaseError("--skin-mm", fmt::format("{} mm does not fit {}: {}", mm, f, e.what()));
          }
        }
      }
    }
    nlohmann::json out;
    out["device"] = ctx.info().describe();
    out["device_name"] = ctx.info().name;
    out["code_version"] = code_version();
    out["runs"] = nlohmann::json::array();
    auto log = [](const std::string& l) { fmt::print("{}\n", l), std::fflush(stdout); };
    log("device: " + ctx.info().describe());
    for (const auto& [c, v] : todo) {
      nlohmann::json j = bench_case(ctx, c, v, o, log);
      log(fmt::format("{} {}: {:.3g} particle-steps/s over {} steps from t = {:.3g} s ({:.3g} s of rotation)",
                      j["case"].get<std::string>(), v, j["particle_steps_per_s"].get<double>(), o.steps,
                      j["timing"]["start_time_s"].get<double>(), j["timing"]["rotation_s"].get<double>()));
      out["runs"].push_back(j);
      if (!json_path.empty()) std::ofstream(json_path) << out.dump(2) << "\n";  // partial results survive
    }
    if (o.timed_only) return 0;
    fmt::print("\ndevice: {}", ctx.info().describe());
    bench::print_table(out["runs"]);
  } catch (const app::CaseError& e) {
    fmt::print(stderr, "wetdem_bench: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "wetdem_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
