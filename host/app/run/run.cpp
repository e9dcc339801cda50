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
#include "app/run/driver.h"
#include "app/run/figures.h"
#include "app/run/log.h"
#include "app/run/outputs.h"
#include "app/run/resources.h"
#include "app/run/session.h"
#include "app/run/wall_split.h"
#include "vk/context.h"
#include "wetdem/version.h"

namespace fs = std::filesystem;

namespace wetdem::app {

namespace {

volatile std::sig_atomic_t g_interrupt = 0;

}  // namespace

void request_interrupt() {
  g_interrupt = 1;
}

bool interrupt_requested() {
  return g_interrupt != 0;
}

void clear_interrupt() {
  g_interrupt = 0;
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

    const double color_max = film_color_max(prep.state, prep.prm.liquid_unit_m3);
    RunOutputs out(dir, c, run->samples(), color_max, prep.prm.liquid_unit_m3);

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

    WallSplit split;
    for (;;) {
      // At a step boundary, in this order: sample, snapshot, checkpoint, stop. A checkpoint is written after
      // the sample and snapshot of its step, so a resumed run does not repeat them.
      const uint64_t step = run->step();
      const bool fresh = !(ckpt && step == first_step);
      if (fresh && sch.due(step, sch.sample))
        split.time(split.sampling, [&] {
          const Sample& x = run->sample();
          out.append(x);
          window_add(x);
          if (opt.on_sample) opt.on_sample(x);
        });
      if (fresh && out.has_frames() && (sch.due(step, sch.snapshot) || step == 0))
        split.time(split.frames, [&] { out.frame(run->state()); });
      if (fresh && step > 0 && step < sch.total && sch.due(step, sch.checkpoint))
        split.time(split.checkpoints, [&] {
          save_checkpoint(dir.string(), run->checkpoint({{"wall_s", wall_before + wall_now()}}));
        });
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
      split.time(split.stepping, [&] { run->advance(sch.next_stop(step)); });
      progress.update(info());
    }
    progress.finish(info());

    // Write: final state, last frame, summary (last, atomically).
    SystemState fin = run->system().download();
    if (out.has_frames() && (sch.snapshot == 0 || !sch.due(run->step(), sch.snapshot)))
      out.frame(run->state());
    const double wall = wall_now();
    const RunTotals t =
        run_totals(prep, fin, run->liquid_start(), run->step(),
                   wall > 0 ? double(n) * double(run->step() - first_step) / wall : 0.0, wall_before + wall,
                   run->system().device_name(), run->system().counters(), resume ? first_step : 0);
    auto figures = [&](nlohmann::json& s) {  // issue 21: the run's figures, listed in summary.json
      if (!opt.figures) return;
      add_figures(dir, prep, fin, color_max, opt.python,
                  opt.plot_script.empty() ? default_plot_run_script() : opt.plot_script, s);
    };
    log(split.line(wall));
    result.summary =
        write_summary(dir, prep, run->samples(), t, {{"wall_split_s", split.json(wall)}}, log, figures);
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
