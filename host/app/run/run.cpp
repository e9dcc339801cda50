// run_case: the driver of one drum run. It calls the phases in order (prepare.cpp: prepare and fill;
// session.h: settle, rotate, sample; outputs.h and summary: write) and owns what only a command-line run
// needs: the run folder, the log, progress, checkpoints on schedule, resume, interrupts.
#include "app/run/run.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <memory>
#include <optional>

#include "app/drum/psd.h"
#include "app/output/checkpoint.h"
#include "app/output/progress.h"
#include "app/run/log.h"
#include "app/run/outputs.h"
#include "app/run/resources.h"
#include "app/run/session.h"
#include "vk/context.h"

namespace fs = std::filesystem;

namespace wetdem::app {

namespace {

volatile std::sig_atomic_t g_interrupt = 0;

std::string local_time(const char* fmt_str) {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, fmt_str, &tm);
  return buf;
}

// The run folder: a new one (refusing one that holds a run), or the folder of a run to resume.
fs::path open_run_folder(const RunOptions& opt, const Case& c) {
  if (!opt.resume_dir.empty()) {
    const fs::path dir = opt.resume_dir;
    if (fs::exists(dir / "summary.json"))
      throw CaseError("", "--resume " + dir.string() + ": the run is complete");
    return dir;
  }
  const fs::path dir =
      opt.out_dir.empty()
          ? fs::path("runs") / ((c.name.empty() ? fs::path(c.source).stem().string() : c.name) + "-" +
                                local_time("%Y%m%d-%H%M%S"))
          : fs::path(opt.out_dir);
  for (const char* f : {"summary.json", "case.toml", "checkpoint"})
    if (fs::exists(dir / f))
      throw CaseError("", "--out " + dir.string() + " already holds a run (use --resume or another --out)");
  fs::create_directories(dir);
  write_file_atomic((dir / "case.toml").string(),
                    "# resolved case (SI), written by wetdem run\n" + case_to_toml(c));
  return dir;
}

void log_setup(RunLog& log, const Prepared& prep, const Schedule& sch, bool resume) {
  const Case& c = prep.c;
  const Derived& d = prep.derived;
  log(fmt::format("wetdem {}+{} | {} | {} | case {}", WETDEM_VERSION, WETDEM_GIT,
                  local_time("%Y-%m-%d %H:%M:%S"), resume ? "resume" : "run", c.source));
  for (const std::string& note : c.notes) log("note: " + note);
  for (const std::string& note : d.notes) log("note: " + note);
  log("psd: " + prep.psd_description);
  const PsdQuantiles q = sample_quantiles(prep.diameters, PsdBasis::kVolume);
  log(fmt::format(
      "inserted: {} particles, volume-basis D10/D25/D50/D75/D90 = {:.1f}/{:.1f}/{:.1f}/{:.1f}/{:.1f} µm "
      "(scaled, l = {})",
      prep.state.p.size(), q.d10 * 1e6, q.d25 * 1e6, q.d50 * 1e6, q.d75 * 1e6, q.d90 * 1e6, c.scaling));
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
}

void log_result(RunLog& log, const nlohmann::json& s, const fs::path& dir) {
  log(aor_log_line(s));  // with tau_int, n_eff and the stationarity verdict (issue 12)
  auto num = [](const nlohmann::json& v) {
    return v.is_number() ? fmt::format("{:.4g}", v.get<double>()) : "-";
  };
  log(fmt::format("f_wet = {}, bridges {}, contacts {} (window means); {:.3g} particle-steps/s; summary: {}",
                  num(s["f_wet_mean"]), num(s["bridges_mean"]), num(s["contacts_mean"]),
                  s["particle_steps_per_s"].get<double>(), (dir / "summary.json").string()));
}

}  // namespace

void request_interrupt() {
  g_interrupt = 1;
}

RunResult run_case(const RunOptions& opt) {
  RunLog log(opt.quiet);
  // Prepare and fill: everything that depends only on the input, before any file or device.
  const Case c = resolve_case(opt);
  std::unique_ptr<vk::Context> own_ctx;
  vk::Context* ctx = opt.context;
  if (!ctx) {
    vk::ContextOptions co;
    co.device = opt.device;
    co.quiet = true;
    own_ctx = std::make_unique<vk::Context>(co);
    ctx = own_ctx.get();
  }
  // Refuse a case that cannot fit before the fill allocates anything (issue 12).
  check_resources(estimate_resources(c), {device_heap_bytes(*ctx), ctx->info().name, host_available_bytes()});
  const Prepared prep = prepare_run(c);
  const Derived& d = prep.derived;
  const size_t n = prep.state.p.size();

  const bool resume = !opt.resume_dir.empty();
  const fs::path dir = open_run_folder(opt, c);
  std::optional<Checkpoint> ckpt;
  if (resume) {
    ckpt = load_checkpoint(dir.string());
    if (ckpt->host.value("radii_hash", "") != prep.radii_hash)
      throw CaseError(
          "", "--resume: the checkpoint's particles differ from the case's fill (different build or case)");
  }
  fs::remove(dir / "FAILED.txt");
  log.open(dir / "run.log");

  RunResult result;
  result.dir = dir.string();
  try {
    log_setup(log, prep, Schedule::of(c, d.dt), resume);
    auto say = [&log](const std::string& l) { log(l); };
    std::unique_ptr<DrumSession> run = ckpt ? std::make_unique<DrumSession>(*ctx, prep, *ckpt, say)
                                            : std::make_unique<DrumSession>(*ctx, prep, say);
    const Schedule& sch = run->schedule();
    const double wall_before = ckpt ? ckpt->host.value("wall_s", 0.0) : 0.0;
    if (ckpt) {
      if (ckpt->host.value("device", "") != run->system().device_name())
        log("note: resuming on " + run->system().device_name() + ", the checkpoint came from " +
            ckpt->host.value("device", "?") + ": valid, but not bitwise equal to an uninterrupted run");
      log(fmt::format("resumed at step {} (t = {:.4g} s)", run->step(), run->time()));
    }
    log("device: " + run->system().device_name());
    const uint64_t first_step = run->step();

    RunOutputs out(dir, c, run->samples(), film_color_max(prep.state, prep.prm.liquid_unit_m3),
                   prep.prm.liquid_unit_m3);

    // Running AoR mean over the window, for the progress line.
    double aor_sum = 0;
    size_t aor_n = 0;
    const double t_from = c.run.settle + c.run.steady_state_start;
    auto window_add = [&](const Sample& s) {
      if (!s.flagged && s.time >= t_from) aor_sum += std::fabs(s.aor_signed_deg), ++aor_n;
    };
    for (const Sample& s : run->samples()) window_add(s);

    Progress progress(stdout, first_step, opt.quiet, opt.progress_tty);
    const auto t0 = std::chrono::steady_clock::now();
    auto wall_now = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    auto info = [&] {
      ProgressInfo p;
      p.step = run->step();
      p.total_steps = sch.total;
      p.sim_time = run->time();
      p.phase = run->rotating() ? "rotate" : "settle";
      const auto& ss = run->samples();
      p.aor_deg = ss.empty() || ss.back().flagged ? -1.0 : std::fabs(ss.back().aor_signed_deg);
      p.aor_mean_deg = aor_n ? aor_sum / double(aor_n) : -1.0;
      return p;
    };

    for (;;) {
      // At a step boundary, in this order: sample, snapshot, checkpoint, stop. A checkpoint is written after
      // the sample and snapshot of its step, so a resumed run does not repeat them.
      const uint64_t step = run->step();
      const bool fresh = !(ckpt && step == first_step);
      if (fresh && sch.due(step, sch.sample)) {
        const Sample& x = run->sample();
        out.append(x);
        window_add(x);
        if (opt.on_sample) opt.on_sample(x);
      }
      if (fresh && out.has_frames() && (sch.due(step, sch.snapshot) || step == 0)) out.frame(run->state());
      if (fresh && step > 0 && step < sch.total && sch.due(step, sch.checkpoint))
        save_checkpoint(dir.string(), run->checkpoint({{"wall_s", wall_before + wall_now()}}));
      if (opt.stop_after_steps && step >= opt.stop_after_steps && step < sch.total) {
        progress.finish(info());
        log(fmt::format("stopped at step {} as asked (--resume {} continues)", step, dir.string()));
        result.final_state = run->system().download();
        return result;
      }
      if (run->done()) break;
      if (g_interrupt)
        throw std::runtime_error(fmt::format(
            "interrupted at step {}; continue from the last checkpoint with wetdem run --resume {}", step,
            dir.string()));
      run->advance(sch.next_stop(step));
      progress.update(info());
    }
    progress.finish(info());

    // Write: final state, last frame, summary (last, atomically).
    SystemState fin = run->system().download();
    if (out.has_frames() && (sch.snapshot == 0 || !sch.due(run->step(), sch.snapshot)))
      out.frame(run->state());
    RunTotals t;
    t.particles = n;
    t.steps = run->step();
    t.dt = d.dt;
    t.liquid_start = run->liquid_start();
    t.liquid_end = fin.total_liquid();
    t.liquid_budget_end = fin.liquid_budget();
    t.liquid_unit_m3 = prep.prm.liquid_unit_m3;
    const double wall = wall_now();
    t.particle_steps_per_s = wall > 0 ? double(n) * double(run->step() - first_step) / wall : 0.0;
    t.wall_s = wall_before + wall;
    t.device = run->system().device_name();
    t.inserted_diameters = prep.diameters;
    t.final_state_hash = state_hash(fin);
    t.counters = run->system().counters();
    t.resumed_from_step = resume ? first_step : 0;
    result.summary = make_summary(c, d, run->samples(), t);
    if (t.liquid_start != t.liquid_end)
      log(fmt::format("WARNING: liquid not conserved: {} units at the start, {} at the end", t.liquid_start,
                      t.liquid_end));
    write_file_atomic((dir / "summary.json").string(), result.summary.dump(2) + "\n");
    // A complete run cannot be resumed: its checkpoint (device buffers, large) is dropped.
    fs::remove_all(dir / "checkpoint");
    fs::remove_all(dir / "checkpoint.old");
    log_result(log, result.summary, dir);
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
