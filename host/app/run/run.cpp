#include "app/run/run.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include "app/drum/aor.h"
#include "app/output/checkpoint.h"
#include "app/drum/fill.h"
#include "app/output/gltf_writer.h"
#include "app/output/progress.h"
#include "app/drum/psd.h"
#include "app/output/vtk_writer.h"
#include "vk/context.h"
#include "wetdem/observables.h"
#include "wetdem/system.h"
#include "wetdem/timestep.h"

namespace fs = std::filesystem;

namespace wetdem::app {

namespace {

volatile std::sig_atomic_t g_interrupt = 0;

// run.log and (unless quiet) stdout. Lines before the run folder exists are kept and written once it does.
class Log {
 public:
  explicit Log(bool quiet) : quiet_(quiet) {}
  void open(const fs::path& file) {
    out_.open(file, std::ios::app);
    for (const std::string& l : pending_) out_ << l << '\n';
    pending_.clear();
    out_.flush();
  }
  void operator()(const std::string& line) {
    if (!quiet_) std::printf("%s\n", line.c_str()), std::fflush(stdout);
    if (out_.is_open())
      out_ << line << '\n', out_.flush();
    else
      pending_.push_back(line);
  }

 private:
  bool quiet_;
  std::ofstream out_;
  std::vector<std::string> pending_;
};

std::string local_time(const char* fmt_str) {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, fmt_str, &tm);
  return buf;
}

// The steps at which things happen; all are absolute step numbers, so a resumed run splits its work into the
// same System::step calls as an uninterrupted one.
struct Schedule {
  uint64_t n_settle = 0, total = 0, sample = 1, snapshot = 0, checkpoint = 0, chunk = 1000;
  static uint64_t steps(double seconds, double dt) { return uint64_t(std::llround(seconds / dt)); }
  bool rotating(uint64_t s) const { return s >= n_settle; }
  bool due(uint64_t s, uint64_t every) const { return every > 0 && s % every == 0; }
  uint64_t next_multiple(uint64_t s, uint64_t every) const { return every ? (s / every + 1) * every : total; }
  // Next step at which the driver must stop stepping to do something.
  uint64_t next_stop(uint64_t s) const {
    uint64_t n = std::min({next_multiple(s, sample), next_multiple(s, snapshot), next_multiple(s, checkpoint),
                           next_multiple(s, chunk), total});
    if (s < n_settle) n = std::min(n, n_settle);
    return n;
  }
};

SimParams phase_params(const SimParams& prm, bool rotating) {
  SimParams p = prm;
  if (!rotating) p.drum.omega = 0.0;  // settle with the drum at rest
  return p;
}

std::vector<double> liquid_m3(const SystemState& s, double unit) {
  std::vector<double> v = liquid_per_particle(s);
  for (double& x : v) x *= unit;
  return v;
}

}  // namespace

void request_interrupt() {
  g_interrupt = 1;
}

Case resolve_case(const RunOptions& opt) {
  if (opt.resume_dir.empty()) {
    if (opt.case_path.empty()) throw CaseError("", "no case file given");
    return parse_case_file(opt.case_path, opt.overrides);
  }
  const fs::path own = fs::path(opt.resume_dir) / "case.toml";
  if (!fs::exists(own))
    throw CaseError("", "--resume " + opt.resume_dir + ": no case.toml there (not a run folder)");
  Case c = parse_case_file(own.string());
  if (!opt.case_path.empty()) {
    const Case given = parse_case_file(opt.case_path, opt.overrides);
    if (case_to_json(given) != case_to_json(c))
      throw CaseError(
          "", "--resume: " + opt.case_path + " (with --set) differs from the case of " + opt.resume_dir);
  } else if (!opt.overrides.empty()) {
    throw CaseError("", "--resume continues the run's own case; --set is not allowed");
  }
  return c;
}

Prepared prepare_run(const Case& c) {
  Prepared p;
  p.c = c;
  const Psd psd(c.psd);
  p.psd_description = psd.describe();
  FillSpec fs_;
  fs_.drum_radius = 0.5 * c.drum.diameter;
  fs_.drum_length = c.drum.sim_length();
  fs_.periodic_z = c.drum.periodic_slice;
  fs_.bed_fraction = c.drum.fill;
  fs_.solid_fraction = c.drum.bed_solid_fraction;
  fs_.seed = c.run.seed;
  FillResult fill;
  try {
    fill = fill_drum(fs_, psd);
  } catch (const std::exception& e) {
    throw CaseError("drum.fill", std::string("cannot place the particles: ") + e.what());
  }
  p.prm = make_sim_params(c, fill.radius, &p.derived);
  // A periodic slice needs every interaction range below half the period (minimum image).
  if (c.drum.periodic_slice) {
    const double reach = 2.0 * p.derived.r_max + p.prm.bridge_range_pp() + p.derived.skin;
    if (!(reach < 0.5 * c.drum.slice_thickness))
      throw CaseError(
          "drum.slice_thickness",
          fmt::format(
              "must exceed twice the neighbour reach 2 r_max + S_c,max + skin = {:.4g} m, got {:.4g} m",
              reach, c.drum.slice_thickness));
  }
  const size_t n = fill.radius.size();
  SystemState& s = p.state;
  s.p.resize(n);
  for (size_t k = 0; k < n; ++k) set_sphere(s.p, k, fill.x[k], fill.radius[k], c.material.density);
  s.p.film = initial_films(c, fill.radius, p.prm.liquid_unit_m3);
  for (double r : fill.radius) p.diameters.push_back(2.0 * r);
  p.radii_hash = bytes_hash(fill.radius.data(), fill.radius.size() * sizeof(double));
  return p;
}

RunResult run_case(const RunOptions& opt) {
  Log log(opt.quiet);
  // 1. Everything that depends only on the input, before any file or device.
  const Case c = resolve_case(opt);
  Prepared prep = prepare_run(c);
  const SimParams& prm = prep.prm;
  const Derived& d = prep.derived;
  const size_t n = prep.state.p.size();

  std::unique_ptr<vk::Context> own_ctx;
  vk::Context* ctx = opt.context;
  if (!ctx) {
    vk::ContextOptions co;
    co.device = opt.device;
    co.quiet = true;
    own_ctx = std::make_unique<vk::Context>(co);
    ctx = own_ctx.get();
  }

  // 2. The run folder.
  const bool resume = !opt.resume_dir.empty();
  std::optional<Checkpoint> ckpt;
  fs::path dir;
  if (resume) {
    dir = opt.resume_dir;
    if (fs::exists(dir / "summary.json"))
      throw CaseError("", "--resume " + dir.string() + ": the run is complete");
    ckpt = load_checkpoint(dir.string());
    if (ckpt->host.value("radii_hash", "") != prep.radii_hash)
      throw CaseError(
          "", "--resume: the checkpoint's particles differ from the case's fill (different build or case)");
  } else {
    dir = opt.out_dir.empty()
              ? fs::path("runs") / ((c.name.empty() ? fs::path(c.source).stem().string() : c.name) + "-" +
                                    local_time("%Y%m%d-%H%M%S"))
              : fs::path(opt.out_dir);
    for (const char* f : {"summary.json", "case.toml", "checkpoint"})
      if (fs::exists(dir / f))
        throw CaseError("", "--out " + dir.string() + " already holds a run (use --resume or another --out)");
    fs::create_directories(dir);
    write_file_atomic((dir / "case.toml").string(),
                      "# resolved case (SI), written by wetdem run\n" + case_to_toml(c));
  }
  fs::remove(dir / "FAILED.txt");
  log.open(dir / "run.log");

  RunResult result;
  result.dir = dir.string();
  try {
    Schedule sch;
    sch.n_settle = Schedule::steps(c.run.settle, d.dt);
    sch.total = sch.n_settle + Schedule::steps(c.run.duration, d.dt);
    sch.sample = std::max<uint64_t>(1, Schedule::steps(c.run.sample_interval, d.dt));
    if (!c.output.formats.empty())
      sch.snapshot = c.output.snapshot_interval > 0
                         ? std::max<uint64_t>(1, Schedule::steps(c.output.snapshot_interval, d.dt))
                         : 0;
    sch.checkpoint = c.output.checkpoint_interval;
    sch.chunk = 5ull * c.run.steps_per_submit;  // progress and ETA at least every 5 submits

    log(fmt::format("wetdem {}+{} | {} | {} | case {}", WETDEM_VERSION, WETDEM_GIT,
                    local_time("%Y-%m-%d %H:%M:%S"), resume ? "resume" : "run", c.source));
    for (const std::string& note : c.notes) log("note: " + note);
    for (const std::string& note : d.notes) log("note: " + note);
    log("psd: " + prep.psd_description);
    const PsdQuantiles q = sample_quantiles(prep.diameters, PsdBasis::kVolume);
    log(fmt::format(
        "inserted: {} particles, volume-basis D10/D25/D50/D75/D90 = {:.1f}/{:.1f}/{:.1f}/{:.1f}/{:.1f} µm "
        "(scaled, l = {})",
        n, q.d10 * 1e6, q.d25 * 1e6, q.d50 * 1e6, q.d75 * 1e6, q.d90 * 1e6, c.scaling));
    log(fmt::format(
        "material: density {} kg/m³ (particle density: an assumption, the paper gives bulk densities), "
        "nu = {:.4g}, reduced E* = {:.4g} Pa, G* = {:.4g} Pa",
        c.material.density, d.nu, d.E_star, d.G_star));
    log(fmt::format(
        "time step: dt = {:.4g} s ({} x Rayleigh time {:.4g} s of r_min = {:.4g} m){}; skin {:.4g} m{}", d.dt,
        c.run.dt ? d.dt / d.t_rayleigh : c.run.dt_rayleigh_fraction, d.t_rayleigh, d.r_min,
        c.run.dt ? " (run.dt)" : "", d.skin, c.run.skin ? "" : " (0.3 r_min)"));
    if (c.liquid.on())
      log(fmt::format(
          "liquid: gamma x l = {:.4g} N/m, unit = V-bar_S 2^-40 = {:.4g} m³, V_min = {} units, V_max = {} "
          "units, films {}",
          d.gamma_scaled, d.liquid_unit_m3, d.v_min_units, d.v_max_units,
          c.liquid.films == FilmMode::MeanVolume ? "phi_L x V-bar_S" : "phi_L x own volume"));
    log(fmt::format(
        "schedule: {} settle + {} rotating steps, sample every {}, snapshot every {}, checkpoint every {}",
        sch.n_settle, sch.total - sch.n_settle, sch.sample, sch.snapshot, sch.checkpoint));

    SystemOptions so;
    so.steps_per_submit = c.run.steps_per_submit;
    uint64_t step = 0;
    std::vector<Sample> samples;
    int64_t liquid_start = prep.state.total_liquid();
    double wall_before = 0;
    std::unique_ptr<System> sys;
    if (ckpt) {
      step = ckpt->host.at("step").get<uint64_t>();
      samples = samples_from_json(ckpt->host.at("samples"));
      liquid_start = ckpt->host.at("liquid_start").get<int64_t>();
      wall_before = ckpt->host.value("wall_s", 0.0);
      sys = std::make_unique<System>(*ctx, phase_params(prm, sch.rotating(step)), n, so);
      sys->restore(ckpt->system);
      if (ckpt->host.value("device", "") != sys->device_name())
        log("note: resuming on " + sys->device_name() + ", the checkpoint came from " +
            ckpt->host.value("device", "?") + ": valid, but not bitwise equal to an uninterrupted run");
      log(fmt::format("resumed at step {} (t = {:.4g} s)", step, double(step) * d.dt));
    } else {
      sys = std::make_unique<System>(*ctx, phase_params(prm, sch.rotating(0)), n, so);
      sys->upload(prep.state);
    }
    log("device: " + sys->device_name());
    bool dt_warned = false;
    if (!ckpt)
      if (auto w = capillary_timestep_warning(prm, prep.state)) {
        log("WARNING: " + *w);
        dt_warned = true;
      }
    const uint64_t first_step = step;

    // timeseries.csv holds exactly the samples so far (rewritten on resume, then appended).
    const fs::path ts_path = dir / "timeseries.csv";
    {
      std::string all = timeseries_header();
      for (const Sample& s : samples) all += timeseries_row(s);
      write_file_atomic(ts_path.string(), all);
    }
    std::ofstream ts(ts_path, std::ios::app);

    // Snapshots: one colour scale for the whole run (the largest initial film), so frames compare.
    double color_max = 0;
    for (int64_t f : prep.state.p.film) color_max = std::max(color_max, double(f) * prm.liquid_unit_m3);
    std::unique_ptr<GltfSeries> gltf;
    std::unique_ptr<PvdSeries> vtk;
    for (const std::string& f : c.output.formats) {
      fs::create_directories(dir / "frames");
      if (f == "gltf")
        gltf =
            std::make_unique<GltfSeries>((dir / "frames").string(), "frame", GltfOptions{color_max, false});
      if (f == "vtk")
        vtk = std::make_unique<PvdSeries>((dir / "frames").string(), "frame",
                                          VtkOptions{VtkEncoding::kBase64, color_max});
    }
    auto snapshot = [&](uint64_t s) {
      if (!gltf && !vtk) return;
      SystemState st = sys->download();
      st.time = double(s) * d.dt;
      st.step = s;
      const ParticleFrame fr = frame_from_state(st, liquid_m3(st, prm.liquid_unit_m3));
      if (gltf) gltf->write(fr);
      if (vtk) vtk->write(fr);
    };

    double aor_sum = 0;
    size_t aor_n = 0;
    const double t_from = c.run.settle + c.run.steady_state_start;
    for (const Sample& s : samples)
      if (!s.flagged && s.time >= t_from) aor_sum += std::fabs(s.aor_signed_deg), ++aor_n;
    auto take_sample = [&](uint64_t s) {
      const SystemState st = sys->download();
      const Observables o = compute_observables(st, sys->params());
      // physics.md §6: warn (once) when dt is too large for the stiffest bridge present.
      if (!dt_warned)
        if (auto w = capillary_timestep_warning(sys->params(), st)) {
          log("WARNING: " + *w);
          dt_warned = true;
        }
      const SystemCounters k = sys->counters();
      if (!std::isfinite(o.kinetic_energy))
        throw std::runtime_error(
            fmt::format("kinetic energy is not finite at step {}: the run blew up (dt too large?)", s));
      if (k.lost_bridges > 0)
        throw std::runtime_error(
            fmt::format("{} liquid bridges were lost with pairs leaving the neighbour list", k.lost_bridges));
      if (k.escaped > 0)
        throw std::runtime_error(fmt::format("{} particles escaped the drum by step {}", k.escaped, s));
      const AorSample a = dynamic_aor(std::vector<glm::dvec3>{o.com}, {}, prm.drum.radius);
      Sample x;
      x.step = s;
      x.time = double(s) * d.dt;
      x.aor_signed_deg = a.signed_deg;
      x.com_x = o.com.x;
      x.com_y = o.com.y;
      x.flagged = a.flagged;
      x.contacts = o.contacts;
      x.bridges = o.bridges;
      x.f_wet = o.f_wet;
      x.kinetic_energy = o.kinetic_energy;
      samples.push_back(x);
      ts << timeseries_row(x);
      ts.flush();
      if (!x.flagged && x.time >= t_from) aor_sum += std::fabs(x.aor_signed_deg), ++aor_n;
      if (opt.on_sample) opt.on_sample(x);
    };

    Progress progress(stdout, first_step, opt.quiet, opt.progress_tty);
    const auto t0 = std::chrono::steady_clock::now();
    auto wall_now = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    auto info = [&](uint64_t s) {
      ProgressInfo p;
      p.step = s;
      p.total_steps = sch.total;
      p.sim_time = double(s) * d.dt;
      p.phase = sch.rotating(s) ? "rotate" : "settle";
      p.aor_deg = samples.empty() || samples.back().flagged ? -1.0 : std::fabs(samples.back().aor_signed_deg);
      p.aor_mean_deg = aor_n ? aor_sum / double(aor_n) : -1.0;
      return p;
    };

    for (;;) {
      // At a step boundary, in this order: phase switch, sample, snapshot, checkpoint, stop. A checkpoint is
      // written after the sample and snapshot of its step, so a resumed run does not repeat them.
      if (step == sch.n_settle && sch.n_settle > 0 && !(ckpt && step == first_step)) {
        // Rotation starts: a system with the turning drum takes the settled state (the device state is
        // downloaded and uploaded whole, so this is exact, and done identically in a resumed run).
        SystemState st = sys->download();
        sys = std::make_unique<System>(*ctx, phase_params(prm, true), n, so);
        sys->upload(st);
        log(fmt::format("settled at t = {:.4g} s: drum starts turning at {:.4g} rad/s", double(step) * d.dt,
                        prm.drum.omega));
      }
      const bool fresh = !(ckpt && step == first_step);
      if (fresh && sch.due(step, sch.sample)) take_sample(step);
      if (fresh && (sch.due(step, sch.snapshot) || (step == 0 && (gltf || vtk)))) snapshot(step);
      if (fresh && step > 0 && step < sch.total && sch.due(step, sch.checkpoint)) {
        Checkpoint k;
        k.system = sys->snapshot();
        k.host = {{"step", step},
                  {"time_s", double(step) * d.dt},
                  {"samples", samples_to_json(samples)},
                  {"liquid_start", liquid_start},
                  {"wall_s", wall_before + wall_now()},
                  {"radii_hash", prep.radii_hash},
                  {"device", sys->device_name()},
                  {"seed", c.run.seed},
                  {"case", case_to_json(c)}};
        save_checkpoint(dir.string(), k);
      }
      if (opt.stop_after_steps && step >= opt.stop_after_steps && step < sch.total) {
        progress.finish(info(step));
        log(fmt::format("stopped at step {} as asked (--resume {} continues)", step, dir.string()));
        result.final_state = sys->download();
        return result;
      }
      if (step >= sch.total) break;
      if (g_interrupt)
        throw std::runtime_error(
            fmt::format("interrupted at step {}; continue from the last checkpoint with "
                        "wetdem run --resume {}",
                        step, dir.string()));
      const uint64_t next = sch.next_stop(step);
      sys->step(next - step);
      step = next;
      progress.update(info(step));
    }
    progress.finish(info(step));

    // 3. End: final state, last frame, summary (last, atomically).
    SystemState fin = sys->download();
    if (sch.snapshot == 0 || !sch.due(step, sch.snapshot)) {
      if (gltf || vtk) snapshot(step);
    }
    RunTotals t;
    t.particles = n;
    t.steps = step;
    t.dt = d.dt;
    t.liquid_start = liquid_start;
    t.liquid_end = fin.total_liquid();
    t.liquid_unit_m3 = prm.liquid_unit_m3;
    const double wall = wall_now();
    t.particle_steps_per_s = wall > 0 ? double(n) * double(step - first_step) / wall : 0.0;
    t.wall_s = wall_before + wall;
    t.device = sys->device_name();
    t.inserted_diameters = prep.diameters;
    t.final_state_hash = state_hash(fin);
    t.counters = sys->counters();
    t.resumed_from_step = resume ? first_step : 0;
    result.summary = make_summary(c, d, samples, t);
    if (t.liquid_start != t.liquid_end)
      log(fmt::format("WARNING: liquid not conserved: {} units at the start, {} at the end", t.liquid_start,
                      t.liquid_end));
    write_file_atomic((dir / "summary.json").string(), result.summary.dump(2) + "\n");
    // A complete run cannot be resumed: its checkpoint (device buffers, large) is dropped.
    fs::remove_all(dir / "checkpoint");
    fs::remove_all(dir / "checkpoint.old");
    const nlohmann::json& s = result.summary;
    if (s["aor_flag"].get<bool>())
      log("AoR: flagged (bed near the drum centre: no angle reported)");
    else
      log(fmt::format("AoR = {:.2f}° ± {:.2f}° (sd {:.2f}°, {} samples over {:.4g}-{:.4g} s)",
                      s["aor_deg_mean"].get<double>(), s["aor_sem_block"].get<double>(),
                      s["aor_deg_std"].get<double>(), s["aor_samples"].get<size_t>(), t_from,
                      c.run.settle + c.run.duration));
    auto num = [](const nlohmann::json& v) {
      return v.is_number() ? fmt::format("{:.4g}", v.get<double>()) : "-";
    };
    log(fmt::format(
        "f_wet = {}, bridges {}, contacts {} (window means); {:.3g} particle-steps/s; summary: {}",
        num(s["f_wet_mean"]), num(s["bridges_mean"]), num(s["contacts_mean"]), t.particle_steps_per_s,
        (dir / "summary.json").string()));
    result.completed = true;
    result.final_state = std::move(fin);
    return result;
  } catch (const std::exception& e) {
    // A failed run: the reason in FAILED.txt and the log, never a summary.json.
    fs::remove(dir / "summary.json.tmp");
    try {
      write_file_atomic((dir / "FAILED.txt").string(), std::string(e.what()) + "\n");
    } catch (...) {
    }
    log(std::string("FAILED: ") + e.what());
    throw std::runtime_error(std::string("run failed: ") + e.what() + " (see " +
                             (dir / "FAILED.txt").string() + ")");
  }
}

}  // namespace wetdem::app
