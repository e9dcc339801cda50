#include "study/commands.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "app/drum/psd.h"
#include "app/output/summary.h"
#include "app/run/stop_signals.h"
#include "study/calibrate.h"
#include "study/collect.h"
#include "study/executor.h"
#include "study/parallel.h"
#include "study/probe.h"
#include "study/prune.h"
#include "study/refine.h"
#include "study/reuse.h"
#include "study/slurm.h"

namespace wetdem::study {

namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string default_dir(const StudySpec& s) {
  return (fs::path("studies") / s.name).string();
}

// Particles and steps of a run, estimated from the PSD model as `wetdem check` does (the run draws its own).
std::pair<double, double> size_of(const app::Case& c) {
  const Psd psd(c.psd);
  const double v = kPi * 0.25 * c.drum.diameter * c.drum.diameter * c.drum.sim_length();
  const double n = c.drum.fill * v * c.drum.bed_solid_fraction / psd.mean_volume();
  const double tr = rayleigh_time(0.5 * psd.d_min(), c.material.density,
                                  c.material.G / c.material.stiffness_reduction, c.material.nu);
  const double dt = c.run.dt ? *c.run.dt : c.run.dt_rayleigh_fraction * tr;
  return {n, std::round((c.run.settle + c.run.duration) / dt)};
}

class Impl : public Commands {
 public:
  explicit Impl(CLI::App& cli) {
    study_ = cli.add_subcommand("study", "studies: many runs of a case over a grid, locally or on Slurm");
    study_->require_subcommand(1);
    study_->footer("Example: wetdem study run assets/studies/micro/micro.toml --out studies/micro");
    plan_ = study_->add_subcommand("plan", "list the runs of a study file, their size and estimated cost");
    plan_->add_option("study", file_, "study file (TOML)")->required();
    plan_->footer("Example: wetdem study plan assets/studies/micro/micro.toml");
    plan_->add_option("--out", dir_,
                      "study directory whose completed runs are counted (default studies/<name>)");
    plan_->add_option("--throughput", throughput_,
                      "particle-steps per second for the estimate (default: the "
                      "mean of the study's completed runs)");
    plan_->add_flag(
        "--probe", probe_,
        "measure this device on the study's first batch (a few hundred steps) and estimate from it");
    plan_->add_option("--batch", batch_, "runs per ensemble, as study run --batch (default 1)")
        ->check(CLI::PositiveNumber);
    plan_->add_option("--probe-steps", probe_steps_, "steps timed by --probe (default 200)");
    plan_->add_option("--device", device_, "device for --probe");
    plan_->add_option("--budget", budget_,
                      "seconds available: say which batches fit and how long the rest takes");
    plan_->add_option("--json", json_, "write the probe and the estimate to this file");
    plan_->add_option("--reuse", reuse_, "count runs complete in this study directory (same hash) as done");

    run_ = study_->add_subcommand("run", "run what is missing; progress line with ETA");
    run_->add_option("study", file_, "study file (TOML)")->required();
    run_->footer("Example: wetdem study run assets/studies/micro/micro.toml --out studies/micro");
    run_->add_option("--out", dir_, "study directory (default studies/<name>)");
    run_->add_option("--jobs", jobs_,
                     "runs at a time (default: one per CPU core, up to " + std::to_string(kCpuAutoJobsMax) +
                         ", on a CPU device such as lavapipe; 1 on a GPU)")
        ->check(CLI::PositiveNumber);
    run_->add_option("--device", device_, "device for every run (index, name substring, gpu, cpu)");
    run_->add_option("--batch", batch_,
                     "hand up to K runs to one process, stepped together as ensembles (docs/ensembles.md; "
                     "default 1)")
        ->check(CLI::PositiveNumber);
    run_->add_flag("--retry-failed", retry_, "rerun runs that failed (FAILED.txt) before");
    run_->add_option("--reuse", reuse_,
                     "another study directory: its complete runs with the same hash (same resolved case, "
                     "seed and code version) are copied, not recomputed (repeatable)");
    run_->add_flag("--no-collect", no_collect_, "do not collect when the runs are done");
    run_->add_flag("--calibrate", calibrate_after_,
                   "calibrate after collecting (the study has observations)");

    one_ = study_->add_subcommand("run-one", "run one run of a planned study (what a Slurm array task does)");
    one_->add_option("dir", dir_, "study directory")->required();
    one_->footer("Example: wetdem study run-one studies/micro --index 0");
    one_->add_option("--index", index_, "run index (0-based, as in index.json)")->required();
    one_->add_option("--device", device_, "device");
    one_->add_flag("--quiet", quiet_, "no progress on stdout");

    batch_cmd_ =
        study_->add_subcommand("run-batch", "run some runs of a planned study as ensembles, in this process");
    batch_cmd_->add_option("dir", dir_, "study directory")->required();
    batch_cmd_->footer("Example: wetdem study run-batch studies/micro --index 0,1,2,3");
    batch_cmd_->add_option("--index", indices_, "run indices, comma-separated (0-based, as in index.json)")
        ->required()
        ->delimiter(',');
    batch_cmd_->add_option("--device", device_, "device");
    batch_cmd_->add_flag("--quiet", quiet_, "no progress on stdout");

    slurm_ = study_->add_subcommand("slurm", "write a Slurm job array for the missing runs");
    slurm_->add_option("study", file_, "study file (TOML)")->required();
    slurm_->footer(
        "Example: wetdem study slurm assets/studies/pp2_l5.toml --partition gpu --gpus-per-task 1 --submit");
    slurm_->add_option("--out", dir_, "study directory (default studies/<name>)");
    slurm_->add_option("--partition", so_.partition, "Slurm partition");
    slurm_->add_option("--time", so_.time, "time limit per task (Slurm format, e.g. 02:00:00)");
    slurm_->add_option("--gpus-per-task", so_.gpus_per_task, "GPUs per task (default: none requested)");
    slurm_->add_option("--max-parallel", so_.max_parallel, "at most K tasks at once (%K)");
    slurm_
        ->add_option("--batch", so_.batch,
                     "one task per batch of up to K runs stepped together as an ensemble (run-batch; "
                     "the batches of study run --batch K)")
        ->check(CLI::PositiveNumber);
    slurm_->add_option("--device", so_.device, "device for every run");
    slurm_->add_flag("--retry-failed", so_.retry_failed, "include runs that failed before");
    slurm_->add_flag("--submit", submit_, "submit with sbatch");

    collect_ = study_->add_subcommand("collect", "runs.csv, points.csv, figures and report.md of a study");
    collect_->add_option("dir", dir_, "study directory")->required();
    collect_->footer("Example: wetdem study collect studies/micro");
    collect_->add_flag("--no-figures", no_figures_, "tables and report only");

    prune_ = study_->add_subcommand(
        "prune", "list what a run store holds; with --yes remove the runs of other run versions");
    prune_->add_option("dir", dir_, "run store: a study directory, or a twin's or diagnosis's --store")
        ->required();
    prune_->footer("Example: wetdem study prune diag/store   (then --yes; docs/studies.md, \"Run store\")");
    prune_->add_flag("--yes", yes_,
                     "remove the complete runs this binary never reuses (another run version); without it, "
                     "only list them");

    cal_ = cli.add_subcommand("calibrate", "fit the study's axes to its observation table (chi2, emulator)");
    cal_->add_option("dir", dir_, "study directory")->required();
    cal_->footer("Example: wetdem calibrate studies/micro");
    cal_->add_option("--observations", co_.observations, "observation table (default: the study's)");
    cal_->add_option("--fit", co_.fit, "fitted axes (default: the study's [observations].fit)");
    cal_->add_option("--refine", refine_,
                     "add and run the K most promising new fit values, then calibrate again");
    cal_->add_option("--jobs", jobs_, "runs at a time for --refine (default as study run --jobs)")
        ->check(CLI::PositiveNumber);
    cal_->add_option("--device", device_, "device for --refine runs");
  }

  bool selected() const override { return study_->parsed() || cal_->parsed(); }

  int execute() override {
    try {
      if (plan_->parsed()) return plan();
      if (run_->parsed()) return run();
      if (one_->parsed()) return run_one_cmd();
      if (batch_cmd_->parsed()) return run_batch_cmd();
      if (slurm_->parsed()) return slurm();
      if (collect_->parsed()) return collect_cmd();
      if (prune_->parsed()) return prune_cmd();
      if (cal_->parsed()) return calibrate_cmd();
    } catch (const StudyError& e) {
      std::fprintf(stderr, "wetdem: error: %s\n", e.what());
      return 2;
    } catch (const app::CaseError& e) {
      std::fprintf(stderr, "wetdem: error: %s\n", e.what());
      return 2;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "wetdem: error: %s\n", e.what());
      return 1;
    }
    return 2;
  }

 private:
  // --jobs, or one per core on a CPU device and 1 on a GPU (parallel.h); the log says which.
  int jobs_of_device() {
    std::string why;
    size_t k = 0;
    try {
      k = resolve_jobs(jobs_, device_, &why);
    } catch (const std::runtime_error& e) {
      throw StudyError(std::string("--device: ") + e.what());
    }
    if (!quiet_) std::printf("%s\n", why.c_str());
    jobs_ = k;
    return int(k);
  }
  int plan() {
    const StudySpec s = parse_study_file(file_);
    const std::vector<PlannedRun> runs = expand(s);
    const std::string dir = dir_.empty() ? default_dir(s) : dir_;
    // Throughput: given, or the stepping rate of the completed runs in the study directory (probe.h,
    // MeasuredRate: a batch's runs count at their batch's aggregate rate); runs older than wall_split_s fall
    // back to the mean of their particle_steps_per_s.
    double tp = throughput_;
    std::string tp_src = "--throughput";
    if (!(tp > 0)) {
      const std::vector<nlohmann::json> done = complete_summaries(dir);
      const MeasuredRate m = measured_rate(done, "");
      if (m.runs) {
        tp = m.particle_steps_per_s;
        tp_src = fmt::format("stepping rate of {} completed runs in {}, batches of {}", m.runs, dir,
                             batch_range(m));
      } else {
        double sum = 0;
        size_t n = 0;
        for (const nlohmann::json& j : done)
          if (j.value("particle_steps_per_s", 0.0) > 0) sum += j.value("particle_steps_per_s", 0.0), ++n;
        tp = n ? sum / double(n) : 0;
        tp_src = fmt::format("mean particle_steps_per_s of {} completed runs in {}", n, dir);
      }
    }
    std::printf("study %s: %zu points x %zu seeds = %zu runs (base %s)\n", s.name.c_str(), s.points.size(),
                s.seeds.size(), runs.size(), s.base.c_str());
    std::printf("%5s %5s %6s %-16s %-10s %9s %9s  %s\n", "index", "point", "seed", "hash", "state",
                "particles", "steps", "values");
    double ps_todo = 0, ps_all = 0;
    size_t done = 0;
    for (const PlannedRun& r : runs) {
      const auto [n, steps] = size_of(r.resolved);
      const RunState st = state_with_reuse(dir, r.hash);
      std::string vals;
      for (const AxisValue& a : r.values) vals += (vals.empty() ? "" : ", ") + a.key + " = " + a.written;
      std::printf("%5zu %5zu %6llu %-16s %-10s %9.0f %9.0f  %s\n", r.index, r.point,
                  (unsigned long long)r.seed, r.hash.c_str(), state_name(st), n, steps, vals.c_str());
      ps_all += n * steps;
      if (st == RunState::Complete)
        ++done;
      else
        ps_todo += n * steps;
    }
    std::printf("%zu of %zu runs complete; %.3g particle-steps to compute (%.3g in all)\n", done, runs.size(),
                ps_todo, ps_all);
    print_other_version_runs(dir, runs);
    if (probe_) return probe_and_estimate(s, runs, dir);
    if (tp > 0)
      std::printf(
          "estimated cost: %.3g s of device time at %.3g particle-steps/s (%s); excludes start-up, "
          "filling and output\n",
          ps_todo / tp, tp, tp_src.c_str());
    else
      std::printf(
          "estimated cost: unknown (no completed run in %s to measure throughput; give "
          "--throughput or run one run first)\n",
          dir.c_str());
    return 0;
  }

  // The census of a store, and with --yes the removal of the runs of other run versions (prune.h).
  int prune_cmd() {
    const StoreCensus c = take_census(dir_);
    std::printf("run store %s:\n%s", dir_.c_str(), describe_census(c).c_str());
    if (c.removable.empty()) {
      std::printf("nothing to remove: every complete run is of this binary's run version\n");
      return 0;
    }
    if (!yes_) {
      std::printf(
          "%zu complete runs are of another run version: this binary never reuses them (the binaries "
          "that made them would). Remove them with --yes.\n",
          c.removable.size());
      return 0;
    }
    const uint64_t freed = prune_runs(dir_, c);
    std::printf("removed %zu runs of other run versions: %.1f MB freed\n", c.removable.size(), freed / 1e6);
    return 0;
  }

  // The summaries of the complete runs in DIR/runs.
  static std::vector<nlohmann::json> complete_summaries(const std::string& dir) {
    std::vector<nlohmann::json> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(dir) / "runs", ec)) {
      std::ifstream f(e.path() / "summary.json");
      if (!f) continue;
      try {
        out.push_back(nlohmann::json::parse(f));
      } catch (const std::exception&) {
      }
    }
    return out;
  }

  static std::string batch_range(const MeasuredRate& m) {
    return m.batch_min == m.batch_max ? fmt::format("{}", m.batch_min)
                                      : fmt::format("{}-{}", m.batch_min, m.batch_max);
  }

  // For each --reuse directory: its complete runs that are this study's but of another run version (reuse.h).
  void print_other_version_runs(const std::string& dir, const std::vector<PlannedRun>& runs) const {
    if (reuse_.empty()) return;
    std::vector<PlannedRun> todo;
    for (const PlannedRun& r : runs)
      if (state_with_reuse(dir, r.hash) != RunState::Complete) todo.push_back(r);
    for (const std::string& other : reuse_) {
      const std::string note = other_version_note(other, other_version_runs(other, todo));
      if (!note.empty()) std::printf("%s\n", note.c_str());
    }
  }

  // A run's state in DIR, or complete when a --reuse directory holds it complete (study run copies it).
  RunState state_with_reuse(const std::string& dir, const std::string& hash) const {
    const RunState st = run_state((fs::path(dir) / "runs" / hash).string());
    if (st == RunState::Complete) return st;
    for (const std::string& other : reuse_)
      if (run_state((fs::path(other) / "runs" / hash).string()) == RunState::Complete)
        return RunState::Complete;
    return st;
  }

  // --probe: the device measured on the first batch of the runs still to compute, then the estimate.
  int probe_and_estimate(const StudySpec& s, const std::vector<PlannedRun>& runs, const std::string& dir) {
    std::vector<PlannedRun> todo;
    for (const PlannedRun& r : runs)
      if (state_with_reuse(dir, r.hash) != RunState::Complete) todo.push_back(r);
    nlohmann::json j = {
        {"study", s.name}, {"runs", runs.size()}, {"to_compute", todo.size()}, {"batch", batch_}};
    if (todo.empty()) {
      std::printf("nothing to compute: every run is complete\n");
    } else {
      const ProbeResult p = probe(todo, batch_, probe_steps_, device_);
      std::printf(
          "probe on %s: %zu runs (%zu particles) stepped together, %llu steps at %.3g ms per step: %.3g "
          "particle-steps/s; a sample of the batch %.3g ms; set-up %.3g s per run\n",
          p.device.c_str(), p.runs, p.particles, (unsigned long long)p.steps, 1e3 * p.step_s,
          p.particle_steps_per_s, 1e3 * p.sample_s, p.setup_s_per_run);
      // Runs already complete on this device measured the turning bed; their stepping rate replaces the
      // probe's (probe.h, MeasuredRate).
      const std::vector<nlohmann::json> done = complete_summaries(dir);
      const MeasuredRate m = measured_rate(done, p.device);
      const Estimate e = estimate(todo, batch_, m.runs ? at_rate(p, m.particle_steps_per_s) : p);
      if (m.runs) {
        const Estimate raw = estimate(todo, batch_, p);
        std::printf(
            "measured: %zu complete runs on %s (batches of %s) stepped at %.3g particle-steps/s, %.2fx "
            "the probe; the estimate uses their rate (the probe's alone: %.0f s)\n",
            m.runs, p.device.c_str(), batch_range(m).c_str(), m.particle_steps_per_s,
            m.particle_steps_per_s / std::max(1e-30, p.particle_steps_per_s), raw.total_s());
        j["measured"] = to_json(m);
        j["estimate_probe_only"] = to_json(raw);
      }
      std::printf(
          "estimate: %zu runs in %zu batches of up to %zu, %.3g particle-steps: %.0f s (%.1f min) = set-up "
          "%.0f s + steps %.0f s + samples %.0f s (%s: a guide, not a promise)\n",
          e.runs, e.batches, batch_, e.particle_steps, e.total_s(), e.total_s() / 60.0, e.setup_s, e.step_s,
          e.sample_s,
          m.runs ? "steps at the rate of the complete runs, samples and set-up as probed"
                 : "measured on the first steps of a freshly filled bed");
      if (budget_ > 0) {
        double t = 0;
        size_t fit = 0;
        for (double b : e.batch_s) {
          if (t + b > budget_) break;
          t += b, ++fit;
        }
        if (fit == e.batches)
          std::printf("budget %.0f s: everything fits (%.0f s)\n", budget_, e.total_s());
        else
          std::printf(
              "budget %.0f s: does NOT fit: the %zu runs take %.0f s (%.1f min); %zu of %zu batches fit "
              "(%.0f s); "
              "the rest needs %.0f s more\n",
              budget_, e.runs, e.total_s(), e.total_s() / 60.0, fit, e.batches, t, e.total_s() - t);
        j["budget_s"] = budget_;
        j["batches_in_budget"] = fit;
      }
      j["probe"] = to_json(p);
      j["estimate"] = to_json(e);
    }
    if (!json_.empty()) app::write_file_atomic(json_, j.dump(2) + "\n");
    return 0;
  }

  int run() {
    const StudySpec s = parse_study_file(file_);
    const std::vector<PlannedRun> runs = expand(s);  // every override validated before anything runs
    const std::string dir = dir_.empty() ? default_dir(s) : dir_;
    const StoreLock lock(dir);  // the plan is this process's until its runs are done
    write_plan(dir, s, runs);
    // Runs another study already computed: the same hash is the same computation (study_file.h), copied.
    for (const std::string& other : reuse_) {
      size_t copied = 0;
      for (const PlannedRun& r : runs) {
        const fs::path from = fs::path(other) / "runs" / r.hash, to = fs::path(dir) / "runs" / r.hash;
        if (run_state(to.string()) == RunState::Complete || run_state(from.string()) != RunState::Complete)
          continue;
        fs::remove_all(to);
        fs::create_directories(to.parent_path());
        fs::copy(from, to, fs::copy_options::recursive);
        ++copied;
      }
      std::printf("reused %zu complete runs of %s\n", copied, other.c_str());
    }
    print_other_version_runs(dir, runs);
    app::install_stop_signals(request_study_interrupt);
    ExecOptions eo;
    eo.jobs = jobs_of_device();
    eo.batch = batch_;
    eo.device = device_;
    eo.retry_failed = retry_;
    eo.exe = self_exe();
    const ExecReport r = run_study(dir, eo);
    for (const std::string& f : r.failures) std::printf("  %s\n", f.c_str());
    // Overhead: wall time of the study not spent inside the runs' own timed loops (their wall_time_s), i.e.
    // planning, process and device start-up, set-up and bookkeeping. With N jobs the runs overlap: divide by
    // N.
    const double outside = r.wall_s - r.run_wall_s / double(std::max<size_t>(1, jobs_));
    std::printf(
        "study %s: %zu runs, %zu already complete, %zu computed now, %zu failed, %zu stopped; wall %.1f s, "
        "inside run processes %.1f s, inside the runs (their wall_time_s) %.1f s: overhead %.1f s "
        "(%.1f %%)\n",
        s.name.c_str(), r.total, r.already_complete, r.completed, r.failed + r.skipped_failed, r.stopped,
        r.wall_s, r.process_wall_s, r.run_wall_s, outside, r.wall_s > 0 ? 100.0 * outside / r.wall_s : 0.0);
    if (r.interrupted) {
      std::printf("interrupted: finished runs are kept; `wetdem study run` again continues the others\n");
      return 1;
    }
    if (!no_collect_) {
      collect(dir);
      std::printf("collected: %s/report.md\n", dir.c_str());
      if (calibrate_after_) {
        const Calibration c = calibrate(dir, co_);
        write_calibration(dir, c);
        std::printf("calibrated: %s/calibration/calibration.md\n", dir.c_str());
      }
    }
    return r.failed + r.skipped_failed ? 1 : 0;
  }

  int run_batch_cmd() {
    app::install_stop_signals(request_study_interrupt);
    const std::vector<OneResult> r = run_batch_of(dir_, indices_, device_, quiet_);
    int failed = 0;
    for (size_t q = 0; q < r.size(); ++q)
      if (!r[q].skipped && !r[q].completed) {
        std::fprintf(stderr, "wetdem: run %zu: %s\n", indices_[q], r[q].error.c_str());
        ++failed;
      }
    return failed ? 1 : 0;
  }

  int run_one_cmd() {
    app::install_stop_signals(request_study_interrupt);
    const OneResult r = run_one(dir_, index_, device_, quiet_);
    if (r.skipped) {
      std::printf("run %zu: already complete\n", index_);
      return 0;
    }
    if (!r.completed) {
      std::fprintf(stderr, "wetdem: run %zu: %s\n", index_, r.error.c_str());
      return 1;
    }
    return 0;
  }

  int slurm() {
    const StudySpec s = parse_study_file(file_);
    const std::vector<PlannedRun> runs = expand(s);
    const std::string dir = fs::absolute(dir_.empty() ? default_dir(s) : dir_).string();
    // Held while the plan and the script are written; the array's jobs read index.json later, so a store
    // submitted to Slurm is not planned into by another process until the array is done (docs/studies.md).
    const StoreLock lock(dir);
    write_plan(dir, s, runs);
    const SlurmScript sc = write_slurm(dir, so_);
    if (sc.indices.empty()) {
      std::printf("study %s: every run is complete; nothing to submit (collect: wetdem study collect %s)\n",
                  s.name.c_str(), dir.c_str());
      return 0;
    }
    if (sc.batches.empty())
      std::printf("wrote %s: %zu array tasks (%s)\n", sc.path.c_str(), sc.indices.size(),
                  array_spec(sc.indices).c_str());
    else
      std::printf("wrote %s: %zu array tasks, one per batch of up to %zu runs\n", sc.path.c_str(),
                  sc.batches.size(), so_.batch);
    if (!submit_) {
      std::printf("%s\n", sc.sbatch_line.c_str());
      return 0;
    }
    std::printf("submitted job %s\n", submit_slurm(sc).c_str());
    return 0;
  }

  int collect_cmd() {
    CollectOptions o;
    o.figures = !no_figures_;
    const Collected c = collect(dir_, o);
    size_t complete = 0;
    for (const std::string& s : c.states) complete += s == "complete";
    std::printf("%s: %zu of %zu runs complete; wrote runs.csv, points.csv, report.md%s\n", dir_.c_str(),
                complete, c.states.size(), o.figures ? ", figures/" : "");
    return 0;
  }

  int calibrate_cmd() {
    if (refine_ > 0) {
      app::install_stop_signals(request_study_interrupt);
      RefineOptions ro;
      ro.k = refine_;
      ro.jobs = jobs_of_device();
      ro.device = device_;
      ro.calibrate = co_;
      const std::string added = refine(dir_, ro);
      std::printf("%s", added.c_str());
    }
    const Calibration c = calibrate(dir_, co_);
    const std::string md = write_calibration(dir_, c);
    CollectOptions o;
    collect(dir_, o);  // the figures include the calibration's chi2 curve or map
    std::printf("%s\nwrote %s/calibration/ (calibration.md, calibration.json, chi2.csv, emulator.csv)\n",
                md.c_str(), dir_.c_str());
    return 0;
  }

  CLI::App *study_ = nullptr, *plan_ = nullptr, *run_ = nullptr, *one_ = nullptr, *batch_cmd_ = nullptr,
           *slurm_ = nullptr, *collect_ = nullptr, *prune_ = nullptr, *cal_ = nullptr;
  std::string file_, dir_, device_, json_;
  double throughput_ = 0, budget_ = 0;
  uint64_t probe_steps_ = 200;
  bool probe_ = false;
  size_t jobs_ = 0;  // 0: by device (parallel.h)
  size_t index_ = 0, refine_ = 0, batch_ = 1;
  std::vector<size_t> indices_;
  std::vector<std::string> reuse_;
  bool retry_ = false, no_collect_ = false, calibrate_after_ = false, quiet_ = false, submit_ = false,
       no_figures_ = false, yes_ = false;
  SlurmOptions so_;
  CalibrateOptions co_;
};

}  // namespace

std::unique_ptr<Commands> add_commands(CLI::App& cli) {
  return std::make_unique<Impl>(cli);
}

}  // namespace wetdem::study
