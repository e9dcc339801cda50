#include "app/run/ensemble.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <thread>

#include "app/output/progress.h"
#include "app/run/driver.h"
#include "app/run/log.h"
#include "app/run/outputs.h"
#include "app/run/resources.h"
#include "app/run/sample.h"
#include "app/run/session.h"
#include "app/run/wall_split.h"
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
    : ctx_(&ctx), runs_(std::move(runs)), log_(std::move(log)) {
  check_batchable(runs_);
  sch_ = Schedule::of(runs_[0]->c, runs_[0]->derived.dt);
  std::vector<SystemState> states;
  for (size_t r = 0; r < runs_.size(); ++r) {
    const Prepared& p = *runs_[r];
    states.push_back(p.state);
    liquid_start_.push_back(p.state.total_liquid());
    if (auto w = capillary_timestep_warning(p.prm, p.state)) log_(r, "WARNING: " + *w);
    if (auto w = viscous_timestep_warning(p.prm, p.state)) log_(r, "WARNING: " + *w);
  }
  dt_warned_.assign(runs_.size(), 0);
  samples_.resize(runs_.size());
  make_system(&states);
}

DrumEnsemble::DrumEnsemble(vk::Context& ctx, std::vector<const Prepared*> runs, const Checkpoint& ck,
                           LogFn log)
    : ctx_(&ctx), runs_(std::move(runs)), log_(std::move(log)) {
  check_batchable(runs_);
  sch_ = Schedule::of(runs_[0]->c, runs_[0]->derived.dt);
  const nlohmann::json& members = ck.host.at("members");
  if (members.size() != runs_.size())
    throw CaseError(
        "", fmt::format("the batch's checkpoint holds {} runs, {} were given", members.size(), runs_.size()));
  step_ = ck.host.at("step").get<uint64_t>();
  for (size_t r = 0; r < runs_.size(); ++r) {
    samples_.push_back(samples_from_json(members[r].at("samples")));
    liquid_start_.push_back(members[r].at("liquid_start").get<int64_t>());
  }
  dt_warned_.assign(runs_.size(), 0);
  make_system(nullptr);
  sys_->restore(ck.system);
}

void DrumEnsemble::make_system(const std::vector<SystemState>* states) {
  std::vector<SimParams> prms;
  std::vector<size_t> sizes;
  for (const Prepared* p : runs_) {
    prms.push_back(phase_params(p->prm, sch_.rotating(step_)));
    sizes.push_back(p->state.p.size());
  }
  SystemOptions so;
  so.steps_per_submit = runs_[0]->c.run.steps_per_submit;
  sys_ = std::make_unique<System>(*ctx_, prms, sizes, so);
  if (states) sys_->upload_runs(*states);
}

Checkpoint DrumEnsemble::checkpoint(const nlohmann::json& extra,
                                    const std::vector<nlohmann::json>& member_extra) const {
  Checkpoint k;
  k.system = sys_->snapshot();
  k.host = extra;
  k.host["step"] = step_;
  k.host["time_s"] = time();
  k.host["device"] = sys_->device_name();
  nlohmann::json members = nlohmann::json::array();
  for (size_t r = 0; r < runs_.size(); ++r) {
    nlohmann::json m = r < member_extra.size() ? member_extra[r] : nlohmann::json::object();
    m["samples"] = samples_to_json(samples_[r]);
    m["liquid_start"] = liquid_start_[r];
    m["radii_hash"] = runs_[r]->radii_hash;
    m["seed"] = runs_[r]->c.run.seed;
    members.push_back(std::move(m));
  }
  k.host["members"] = std::move(members);
  return k;
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
  std::vector<RunSample> st = sys_->sample_runs();
  const SystemCounters k = sys_->counters();
  // The runs' samples are independent pure functions of what came back: computed on the host's cores at once
  // (each run's log lines and error kept and reported in run order, so the outcome does not depend on
  // timing).
  const size_t runs = runs_.size();
  std::vector<Sample> out(runs);
  std::vector<std::vector<std::string>> lines(runs);
  std::vector<std::string> errors(runs);
  auto work = [&](size_t r) {
    SampleContext x;
    x.prep = runs_[r];
    x.prm = &sys_->run_params(r);
    x.step = step_;
    x.time = time();
    x.liquid_start = liquid_start_[r];
    x.counters = k;
    bool warned = dt_warned_[r] != 0;
    try {
      out[r] = take_sample(st[r], x, warned, [&](const std::string& l) { lines[r].push_back(l); });
    } catch (const std::exception& e) {
      errors[r] = e.what();
    }
    dt_warned_[r] = warned ? 1 : 0;
  };
  // Threads pay off for large batches (a GPU's: tens of thousands of particles per run); for small ones their
  // start-up and, on a loaded machine, their scheduling cost more than the work.
  size_t particles = 0;
  for (const Prepared* p : runs_) particles += p->state.p.size();
  const size_t threads =
      particles < 20000 ? 1 : std::min<size_t>(runs, std::max(1u, std::thread::hardware_concurrency()));
  if (threads <= 1) {
    for (size_t r = 0; r < runs; ++r) work(r);
  } else {
    std::vector<std::thread> pool;
    for (size_t t = 0; t < threads; ++t)
      pool.emplace_back([&, t] {
        for (size_t r = t; r < runs; r += threads) work(r);
      });
    for (std::thread& th : pool) th.join();
  }
  for (size_t r = 0; r < runs; ++r) {
    for (const std::string& l : lines[r]) log_(r, l);
    if (!errors[r].empty()) throw std::runtime_error(errors[r]);
  }
  for (size_t r = 0; r < runs; ++r) samples_[r].push_back(std::move(out[r]));
}

std::vector<SystemState> DrumEnsemble::states() {
  std::vector<SystemState> st = sys_->download_runs();
  for (SystemState& s : st) s.time = time(), s.step = step_;
  return st;
}

std::vector<std::string> ensemble_members(const std::string& run_dir) {
  const fs::path member = fs::path(run_dir) / kEnsembleMember;
  std::ifstream f(member);
  if (!f) return {};
  try {
    const nlohmann::json j = nlohmann::json::parse(f);
    const fs::path leader = (fs::path(run_dir) / j.at("leader").get<std::string>()).lexically_normal();
    const fs::path ck = leader / kEnsembleDir;
    if (!has_checkpoint(ck.string())) return {};
    std::ifstream h(fs::exists(ck / "checkpoint" / "host.json") ? ck / "checkpoint" / "host.json"
                                                                : ck / "checkpoint.old" / "host.json");
    const nlohmann::json host = nlohmann::json::parse(h);
    std::vector<std::string> out;
    for (const nlohmann::json& m : host.at("members"))
      out.push_back((leader / m.at("dir").get<std::string>()).lexically_normal().string());
    return out;
  } catch (const std::exception&) {
    return {};
  }
}

std::vector<RunResult> run_batch(const std::vector<RunOptions>& opts, vk::Context& ctx) {
  if (opts.empty()) throw CaseError("", "a batch needs at least one run");
  // Everything that depends only on the input, before any folder.
  const bool resume = !opts[0].resume_dir.empty();
  for (const RunOptions& o : opts)
    if (o.resume_dir.empty() == resume)
      throw CaseError("", "a batch is either all fresh runs or one batch resumed from its checkpoint");
  std::vector<Case> cases;
  std::vector<std::unique_ptr<Prepared>> preps;
  std::vector<const Prepared*> view;
  ResourceEstimate need;  // the batch's runs live in one System: their memory adds up
  for (const RunOptions& o : opts) {
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
  // The batch's checkpoint (resume): it must name these folders, in this order, with these fills.
  std::optional<Checkpoint> ckpt;
  std::vector<bool> complete(k, false);
  if (resume) {
    const fs::path leader = fs::path(opts[0].resume_dir);
    ckpt = load_checkpoint((leader / kEnsembleDir).string());
    const nlohmann::json& members = ckpt->host.at("members");
    if (members.size() != k)
      throw CaseError("", fmt::format("--resume: the batch's checkpoint in {} holds {} runs, {} were given",
                                      leader.string(), members.size(), k));
    for (size_t r = 0; r < k; ++r) {
      const fs::path want = (leader / members[r].at("dir").get<std::string>()).lexically_normal();
      if (!fs::equivalent(want, fs::path(opts[r].resume_dir)))
        throw CaseError("", fmt::format("--resume: run {} of the batch's checkpoint is {}, not {}", r,
                                        want.string(), opts[r].resume_dir));
      if (members[r].value("radii_hash", "") != preps[r]->radii_hash)
        throw CaseError(
            "", "--resume " + opts[r].resume_dir +
                    ": the checkpoint's particles differ from the case's fill (different build or case)");
      // A run whose summary was written before the batch was killed: stepped again, not written again.
      complete[r] = fs::exists(fs::path(opts[r].resume_dir) / "summary.json");
    }
  }
  std::vector<fs::path> dirs;
  std::vector<std::unique_ptr<RunLog>> logs;
  for (size_t r = 0; r < k; ++r) {
    if (resume) {
      dirs.push_back(fs::path(opts[r].resume_dir));
    } else {
      dirs.push_back(open_run_folder(opts[r], cases[r]));
    }
    if (!complete[r]) fs::remove(dirs[r] / "FAILED.txt");
    logs.push_back(std::make_unique<RunLog>(true));
    logs[r]->open(dirs[r] / "run.log");
    log_setup(*logs[r], *preps[r], Schedule::of(cases[r], preps[r]->derived.dt), resume);
    (*logs[r])(fmt::format("ensemble: run {} of a batch of {} stepped together in one System", r, k));
  }
  // Every run's folder says which batch it belongs to (run 0's folder holds the batch's checkpoint).
  std::vector<nlohmann::json> member_extra(k);
  for (size_t r = 0; r < k; ++r) {
    const std::string rel = fs::relative(dirs[r], dirs[0]).lexically_normal().string();
    member_extra[r] = {{"dir", rel}};
    if (!resume)
      write_file_atomic((dirs[r] / kEnsembleMember).string(),
                        nlohmann::json{
                            {"leader", fs::relative(dirs[0], dirs[r]).lexically_normal().string()},
                            {"index", r},
                            {"runs",
                             k}}.dump(1) +
                            "\n");
  }
  const fs::path ck_dir = dirs[0] / kEnsembleDir;
  std::vector<RunResult> results(k);
  try {
    auto say = [&](size_t r, const std::string& l) { (*logs[r])(l); };
    std::unique_ptr<DrumEnsemble> ens_ptr = ckpt ? std::make_unique<DrumEnsemble>(ctx, view, *ckpt, say)
                                                 : std::make_unique<DrumEnsemble>(ctx, view, say);
    DrumEnsemble& ens = *ens_ptr;
    const Schedule& sch = ens.schedule();
    const double wall_before = ckpt ? ckpt->host.value("wall_s", 0.0) : 0.0;
    const uint64_t first_step = ens.step();
    for (size_t r = 0; r < k; ++r) {
      if (ckpt) {
        if (ckpt->host.value("device", "") != ens.system().device_name())
          (*logs[r])("note: resuming on " + ens.system().device_name() + ", the checkpoint came from " +
                     ckpt->host.value("device", "?") +
                     ": valid, but not bitwise equal to an uninterrupted run");
        (*logs[r])(fmt::format("resumed the batch at step {} (t = {:.4g} s)", ens.step(), ens.time()));
      }
      (*logs[r])("device: " + ens.system().device_name());
      results[r].dir = dirs[r].string();
    }
    std::vector<std::unique_ptr<RunOutputs>> out;
    bool frames = false;
    for (size_t r = 0; r < k; ++r) {
      const Prepared& p = *preps[r];
      out.push_back(std::make_unique<RunOutputs>(dirs[r], cases[r], ens.samples(r),
                                                 film_color_max(p.state, p.prm.liquid_unit_m3),
                                                 p.prm.liquid_unit_m3));
      frames = frames || out.back()->has_frames();
    }
    Progress progress(stdout, first_step, opts[0].quiet, opts[0].progress_tty);
    auto info = [&] {
      ProgressInfo p;
      p.step = ens.step();
      p.total_steps = sch.total;
      p.sim_time = ens.time();
      p.phase = ens.rotating() ? "rotate" : "settle";
      return p;
    };
    const auto t0 = std::chrono::steady_clock::now();
    auto wall_now = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    uint64_t saved_at = ckpt ? first_step : 0;
    auto save = [&] {
      save_checkpoint(ck_dir.string(), ens.checkpoint({{"wall_s", wall_before + wall_now()}}, member_extra));
      saved_at = ens.step();
    };
    const uint64_t stop_after = opts[0].stop_after_steps;
    WallSplit split;
    for (;;) {
      // At a step boundary, in this order: sample, snapshot, checkpoint, stop (as run_case).
      const uint64_t step = ens.step();
      const bool fresh = !(ckpt && step == first_step);
      if (fresh && sch.due(step, sch.sample))
        split.time(split.sampling, [&] {
          ens.sample();
          for (size_t r = 0; r < k; ++r) {
            out[r]->append(ens.samples(r).back());
            if (opts[r].on_sample) opts[r].on_sample(ens.samples(r).back());
          }
        });
      if (fresh && frames && (sch.due(step, sch.snapshot) || step == 0))
        split.time(split.frames, [&] {
          const std::vector<SystemState> st = ens.states();
          for (size_t r = 0; r < k; ++r)
            if (out[r]->has_frames()) out[r]->frame(st[r]);
        });
      if (fresh && step > 0 && step < sch.total && sch.due(step, sch.checkpoint))
        split.time(split.checkpoints, save);
      if (stop_after && step >= stop_after && step < sch.total) {
        if (saved_at != step) save();
        progress.finish(info());
        const std::vector<SystemState> st = ens.system().download_runs();
        for (size_t r = 0; r < k; ++r) {
          (*logs[r])(fmt::format("batch stopped at step {} as asked (resumable)", step));
          results[r].final_state = st[r];
        }
        return results;
      }
      if (ens.done()) break;
      if (interrupt_requested()) {
        // Keep everything done so far: a checkpoint at this boundary, then fail as interrupted (resumable).
        if (step > 0 && saved_at != step) save();
        throw std::runtime_error(fmt::format(
            "interrupted at step {}; the batch resumes from its checkpoint in {}", step, ck_dir.string()));
      }
      split.time(split.stepping, [&] { ens.advance(sch.next_stop(step)); });
      progress.update(info());
    }
    progress.finish(info());
    const double wall = wall_now();
    std::vector<SystemState> fin = ens.system().download_runs();
    if (frames && (sch.snapshot == 0 || !sch.due(ens.step(), sch.snapshot))) {
      const std::vector<SystemState> st = ens.states();
      for (size_t r = 0; r < k; ++r)
        if (out[r]->has_frames()) out[r]->frame(st[r]);
    }
    double all = 0;
    for (size_t r = 0; r < k; ++r) all += double(preps[r]->state.p.size());
    const double stepped = double(ens.step() - first_step);
    const double aggregate = wall > 0 ? all * stepped / wall : 0.0;
    const nlohmann::json wall_split = split.json(wall);
    for (size_t r = 0; r < k; ++r) {
      const double n = double(preps[r]->state.p.size());
      const RunTotals t = run_totals(
          *preps[r], fin[r], ens.liquid_start(r), ens.step(), wall > 0 ? n * stepped / wall : 0.0,
          wall_before + wall, ens.system().device_name(), ens.system().counters(), resume ? first_step : 0);
      const nlohmann::json extra = {
          {"ensemble", {{"runs", k}, {"index", r}, {"aggregate_particle_steps_per_s", aggregate}}},
          {"wall_split_s", wall_split}};
      results[r].completed = true;
      results[r].final_state = std::move(fin[r]);
      if (complete[r]) continue;  // written before the batch was killed: bitwise the same run
      (*logs[r])(split.line(wall) + " (the batch's)");
      results[r].summary = write_summary(dirs[r], *preps[r], ens.samples(r), t, extra, *logs[r]);
    }
    // Every summary is written: the batch's checkpoint and the member files go.
    fs::remove_all(ck_dir);
    for (size_t r = 0; r < k; ++r) fs::remove(dirs[r] / kEnsembleMember);
    return results;
  } catch (const std::exception& e) {
    // The runs of a batch fail together: FAILED.txt in every folder, never a summary.json.
    for (size_t r = 0; r < k; ++r) {
      if (complete[r]) continue;
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
