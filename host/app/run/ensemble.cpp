#include "app/run/ensemble.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "app/output/progress.h"
#include "app/run/driver.h"
#include "app/run/log.h"
#include "app/run/outputs.h"
#include "app/run/resources.h"
#include "app/run/sample.h"
#include "app/run/session.h"
#include "vk/context.h"
#include "wetdem/timestep.h"

namespace fs = std::filesystem;

namespace wetdem::app {

namespace {

// What a batch's runs must share to be stepped together, checked before any folder or device work.
void check_batchable(const std::vector<const Prepared*>& runs) {
  if (runs.empty()) throw CaseError("", "a batch needs at least one run");
  const Prepared& a = *runs[0];
  const Schedule s0 = Schedule::of(a.c, a.derived.dt);
  for (size_t r = 1; r < runs.size(); ++r) {
    const Prepared& b = *runs[r];
    auto need = [&](bool same, const std::string& key, const std::string& what) {
      if (!same)
        throw CaseError(key, fmt::format("run {} of the batch ({}) cannot be stepped with run 0 ({}): {}", r,
                                         b.c.source, a.c.source, what));
    };
    need(b.derived.dt == a.derived.dt, "run.dt",
         fmt::format("dt {:.6g} s vs {:.6g} s (dt follows the smallest particle of each fill; give run.dt to "
                     "batch fills of different seeds)",
                     b.derived.dt, a.derived.dt));
    const DrumParams &d = b.prm.drum, &e = a.prm.drum;
    need(d.radius == e.radius && d.length == e.length, "drum", "another drum size");
    need(d.periodic_z == e.periodic_z && d.plate_lo.present == e.plate_lo.present &&
             d.plate_hi.present == e.plate_hi.present,
         "drum.periodic_slice", "a periodic slice and a drum with plates");
    const Schedule s = Schedule::of(b.c, b.derived.dt);
    need(s.n_settle == s0.n_settle && s.total == s0.total, "run.duration", "another settle or duration");
    need(s.sample == s0.sample && s.snapshot == s0.snapshot, "run.sample_interval",
         "another sample or snapshot interval");
  }
}

}  // namespace

DrumEnsemble::DrumEnsemble(vk::Context& ctx, std::vector<const Prepared*> runs, LogFn log)
    : runs_(std::move(runs)), log_(std::move(log)) {
  check_batchable(runs_);
  sch_ = Schedule::of(runs_[0]->c, runs_[0]->derived.dt);
  std::vector<SimParams> prms;
  std::vector<size_t> sizes;
  std::vector<SystemState> states;
  for (size_t r = 0; r < runs_.size(); ++r) {
    const Prepared& p = *runs_[r];
    prms.push_back(phase_params(p.prm, sch_.rotating(0)));
    sizes.push_back(p.state.p.size());
    states.push_back(p.state);
    liquid_start_.push_back(p.state.total_liquid());
    if (auto w = capillary_timestep_warning(p.prm, p.state)) log_(r, "WARNING: " + *w);
    if (auto w = viscous_timestep_warning(p.prm, p.state)) log_(r, "WARNING: " + *w);
  }
  dt_warned_.assign(runs_.size(), 0);
  samples_.resize(runs_.size());
  SystemOptions so;
  so.steps_per_submit = runs_[0]->c.run.steps_per_submit;
  sys_ = std::make_unique<System>(ctx, prms, sizes, so);
  sys_->upload_runs(states);
}

double DrumEnsemble::time() const {
  return double(step_) * runs_[0]->derived.dt;
}

void DrumEnsemble::advance(uint64_t to) {
  if (to <= step_) return;
  if (to > sch_.next_stop(step_))
    throw std::logic_error("DrumEnsemble::advance past the next scheduled stop");
  sys_->step(to - step_);
  step_ = to;
  if (step_ == sch_.n_settle && sch_.n_settle > 0)
    for (size_t r = 0; r < runs_.size(); ++r) {
      sys_->set_run_params(r, phase_params(runs_[r]->prm, true));  // as DrumSession::advance does
      log_(r, fmt::format("settled at t = {:.4g} s: drum starts turning at {:.4g} rad/s", time(),
                          runs_[r]->prm.drum.omega));
    }
}

void DrumEnsemble::sample() {
  const std::vector<SystemState> st = sys_->download_runs();
  const SystemCounters k = sys_->counters();
  for (size_t r = 0; r < runs_.size(); ++r) {
    SampleContext x;
    x.prep = runs_[r];
    x.prm = &sys_->run_params(r);
    x.step = step_;
    x.time = time();
    x.liquid_start = liquid_start_[r];
    x.counters = k;
    bool warned = dt_warned_[r] != 0;
    samples_[r].push_back(take_sample(st[r], x, warned, [&](const std::string& l) { log_(r, l); }));
    dt_warned_[r] = warned ? 1 : 0;
  }
}

std::vector<SystemState> DrumEnsemble::states() {
  std::vector<SystemState> st = sys_->download_runs();
  for (SystemState& s : st) s.time = time(), s.step = step_;
  return st;
}

std::vector<RunResult> run_batch(const std::vector<RunOptions>& opts, vk::Context& ctx) {
  // Everything that depends only on the input, before any folder.
  std::vector<Case> cases;
  std::vector<std::unique_ptr<Prepared>> preps;
  std::vector<const Prepared*> view;
  ResourceEstimate need;  // the batch's runs live in one System: their memory adds up
  for (const RunOptions& o : opts) {
    if (!o.resume_dir.empty() || o.stop_after_steps)
      throw CaseError("", "a batch runs fresh runs only (no --resume, no stop_after_steps)");
    cases.push_back(resolve_case(o));
    const ResourceEstimate e = estimate_resources(cases.back());
    need.particles += e.particles;
    need.device_bytes += e.device_bytes;
    need.host_bytes += e.host_bytes;
    need.steps = std::max(need.steps, e.steps);
    need.particle_steps += e.particle_steps;
    need.entries_in_list = std::max(need.entries_in_list, e.entries_in_list);
    need.entries_per_particle = std::max(need.entries_per_particle, e.entries_per_particle);
    need.driver_key = e.driver_key;
  }
  check_resources(need, {device_heap_bytes(ctx), ctx.info().name, host_available_bytes()});
  for (const Case& c : cases) {
    preps.push_back(std::make_unique<Prepared>(prepare_run(c)));
    view.push_back(preps.back().get());
  }
  check_batchable(view);
  const size_t k = opts.size();
  std::vector<fs::path> dirs;
  std::vector<std::unique_ptr<RunLog>> logs;
  for (size_t r = 0; r < k; ++r) {
    dirs.push_back(open_run_folder(opts[r], cases[r]));
    fs::remove(dirs[r] / "FAILED.txt");
    logs.push_back(std::make_unique<RunLog>(true));
    logs[r]->open(dirs[r] / "run.log");
    log_setup(*logs[r], *preps[r], Schedule::of(cases[r], preps[r]->derived.dt), false);
    (*logs[r])(fmt::format("ensemble: run {} of a batch of {} stepped together in one System", r, k));
  }
  std::vector<RunResult> results(k);
  try {
    DrumEnsemble ens(ctx, view, [&](size_t r, const std::string& l) { (*logs[r])(l); });
    const Schedule& sch = ens.schedule();
    for (size_t r = 0; r < k; ++r) {
      (*logs[r])("device: " + ens.system().device_name());
      results[r].dir = dirs[r].string();
    }
    std::vector<std::unique_ptr<RunOutputs>> out;
    bool frames = false;
    for (size_t r = 0; r < k; ++r) {
      const Prepared& p = *preps[r];
      out.push_back(std::make_unique<RunOutputs>(dirs[r], cases[r], std::vector<Sample>{},
                                                 film_color_max(p.state, p.prm.liquid_unit_m3),
                                                 p.prm.liquid_unit_m3));
      frames = frames || out.back()->has_frames();
    }
    Progress progress(stdout, 0, opts[0].quiet, opts[0].progress_tty);
    auto info = [&] {
      ProgressInfo p;
      p.step = ens.step();
      p.total_steps = sch.total;
      p.sim_time = ens.time();
      p.phase = ens.rotating() ? "rotate" : "settle";
      return p;
    };
    const auto t0 = std::chrono::steady_clock::now();
    for (;;) {
      const uint64_t step = ens.step();
      if (sch.due(step, sch.sample)) {
        ens.sample();
        for (size_t r = 0; r < k; ++r) {
          out[r]->append(ens.samples(r).back());
          if (opts[r].on_sample) opts[r].on_sample(ens.samples(r).back());
        }
      }
      if (frames && (sch.due(step, sch.snapshot) || step == 0)) {
        const std::vector<SystemState> st = ens.states();
        for (size_t r = 0; r < k; ++r)
          if (out[r]->has_frames()) out[r]->frame(st[r]);
      }
      if (ens.done()) break;
      if (interrupt_requested()) throw std::runtime_error(fmt::format("interrupted at step {}", step));
      ens.advance(sch.next_stop(step));
      progress.update(info());
    }
    progress.finish(info());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<SystemState> fin = ens.system().download_runs();
    if (frames && (sch.snapshot == 0 || !sch.due(ens.step(), sch.snapshot))) {
      const std::vector<SystemState> st = ens.states();
      for (size_t r = 0; r < k; ++r)
        if (out[r]->has_frames()) out[r]->frame(st[r]);
    }
    double all = 0;
    for (size_t r = 0; r < k; ++r) all += double(preps[r]->state.p.size());
    const double aggregate = wall > 0 ? all * double(ens.step()) / wall : 0.0;
    for (size_t r = 0; r < k; ++r) {
      const double n = double(preps[r]->state.p.size());
      const RunTotals t = run_totals(*preps[r], fin[r], ens.liquid_start(r), ens.step(),
                                     wall > 0 ? n * double(ens.step()) / wall : 0.0, wall,
                                     ens.system().device_name(), ens.system().counters(), 0);
      const nlohmann::json extra = {
          {"ensemble", {{"runs", k}, {"index", r}, {"aggregate_particle_steps_per_s", aggregate}}}};
      results[r].summary = write_summary(dirs[r], *preps[r], ens.samples(r), t, extra, *logs[r]);
      results[r].completed = true;
      results[r].final_state = std::move(fin[r]);
    }
    return results;
  } catch (const std::exception& e) {
    // The runs of a batch fail together: FAILED.txt in every folder, never a summary.json.
    for (size_t r = 0; r < k; ++r) {
      fs::remove(dirs[r] / "summary.json.tmp");
      try {
        write_file_atomic((dirs[r] / "FAILED.txt").string(), std::string(e.what()) + "\n");
      } catch (...) {
      }
      (*logs[r])(std::string("FAILED (the batch): ") + e.what());
    }
    throw std::runtime_error(std::string("batch failed: ") + e.what() + " (see " +
                             (dirs[0] / "FAILED.txt").string() + ")");
  }
}

}  // namespace wetdem::app
