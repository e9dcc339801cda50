#include "diagnose/commands.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "app/case/case.h"
#include "diagnose/auto_batch.h"
#include "diagnose/driver.h"
#include "diagnose/twin.h"
#include "study/executor.h"
#include "study/study_file.h"

namespace wetdem::diagnose {

namespace {

class Impl : public study::Commands {
 public:
  explicit Impl(CLI::App& cli) {
    diag_ = cli.add_subcommand("diagnose",
                               "sim-to-real diagnosis: where the model misses, which effect explains it");
    diag_->add_option("file", file_, "diagnosis file (TOML)")->required();
    diag_->footer(
        "Example: wetdem diagnose assets/diagnosis/micro/diagnose.toml --observations "
        "diag/twin/observations.csv --out diag/spread --store diag/store");
    diag_->add_option("--observations", observations_, "observation table (CSV) instead of the file's");
    diag_
        ->add_option("--replicates", replicates_,
                     "seeds per condition instead of the file's `replicates` (baseline seeds 1..R, fresh "
                     "seeds R+1..2R): more lowers the model's seed luck")
        ->check(CLI::Range(1, 100));
    diag_
        ->add_option("--escalate-replicates", escalate_,
                     "when the seed luck decides the verdict, run again at this many seeds per condition "
                     "(instead of the file's `escalate_replicates`; 0: never)")
        ->check(CLI::Range(0, 100));
    diag_
        ->add_option("--probe-seeds", probe_seeds_,
                     "seeds per probe knot instead of the file's `probe_seeds` (1..R, the baseline's first "
                     "seeds): more for effects that widen the run-to-run scatter")
        ->check(CLI::Range(1, 100));
    diag_->add_flag(
        "--check", o_.check,
        "validate the file, the table and the case of the baseline and of every candidate's probes at "
        "every condition, then stop: nothing is run or written (--out not needed)");
    add_common(diag_);
    twin_ =
        cli.add_subcommand("twin", "synthetic observations from a model with a withheld effect (validation)");
    twin_->add_option("file", file_, "twin file (TOML)")->required();
    twin_->add_flag(
        "--check", o_.check,
        "validate the file and the case at every condition (keys, ranges, the slice against the neighbour "
        "reach, the observables), then stop: nothing is run or written "
        "(--out not needed; scripts/twin_matrix.py checks every twin this way before its first run)");
    twin_->footer(
        "Example: wetdem twin assets/diagnosis/micro/twin_spread.toml --out diag/twin --store diag/store");
    add_common(twin_);
  }
  bool selected() const override { return diag_->parsed() || twin_->parsed(); }
  int execute() override {
    o_.exe = study::self_exe();
    try {
      if (o_.out.empty() && !o_.check) throw DiagnoseError("--out: required (unless --check)");
      if (diag_->parsed()) {
        DiagnosisSpec d = parse_diagnosis_file(file_, observations_);
        if (replicates_ > 0) d.replicates = replicates_;
        if (escalate_ >= 0) {
          if (escalate_ != 0 && escalate_ <= d.replicates)
            throw DiagnoseError(
                fmt::format("--escalate-replicates: {} is not more than the replicates ({}); 0 turns it off",
                            escalate_, d.replicates));
          d.escalate_replicates = escalate_;
        } else if (d.escalate_replicates <= d.replicates) {
          d.escalate_replicates =
              0;  // --replicates at or past the file's escalation: that many from the start
        }
        if (probe_seeds_ > 0) {
          if (probe_seeds_ > d.replicates)
            throw DiagnoseError(fmt::format(
                "--probe-seeds: {} is more than the replicates ({}): the probes share the baseline's seeds",
                probe_seeds_, d.replicates));
          d.probe_seeds = probe_seeds_;
        }  // the file's probe_seeds against a lower --replicates: Procedure's check
        if (o_.check) {
          const nlohmann::json j = run_diagnosis(d, o_);
          std::string names;
          for (const auto& e : j["candidates"]) names += (names.empty() ? "" : ", ") + e.get<std::string>();
          std::printf(
              "%s: %zu conditions, %zu cells, candidates %s: the file, the table and the case of every run "
              "check (nothing run)\n",
              file_.c_str(), j["conditions"].get<size_t>(), j["cells"].get<size_t>(), names.c_str());
          return 0;
        }
        choose_batch();
        const nlohmann::json j = run_diagnosis(d, o_);
        std::string named;  // "spread" or "spread + absorption" (a second effect on top of the first)
        for (const auto& e : j["effects"]) named += (named.empty() ? "" : " + ") + e.get<std::string>();
        // A tie is part of the verdict, not a detail of the report: "effect (evaporation; tied: absorption)".
        std::string tied;
        for (const auto& e : j["tied"]) tied += (tied.empty() ? "; tied: " : ", ") + e.get<std::string>();
        named += tied;
        if (!j["escalation"].is_null())
          std::printf("first pass at R = %d: %s, not decided; run again at R = %d\n",
                      j["escalation"]["from_replicates"].get<int>(),
                      j["escalation"]["verdict"].get<std::string>().c_str(),
                      j["escalation"]["to_replicates"].get<int>());
        std::printf("verdict: %s%s\nreport: %s/report.md\n", j["verdict"].get<std::string>().c_str(),
                    named.empty() ? "" : (" (" + named + ")").c_str(), o_.out.c_str());
      } else {
        const TwinSpec t = parse_twin_file(file_);
        if (o_.check) {
          const nlohmann::json j = run_twin(t, o_);
          std::printf(
              "%s: %zu conditions, %zu truth runs: the file and the case at every condition check (nothing "
              "run)\n",
              file_.c_str(), j["conditions"].get<size_t>(), j["runs"].get<size_t>());
          return 0;
        }
        choose_batch();
        run_twin(t, o_);
        std::printf("observations: %s/observations.csv (truth apart: %s/truth.json)\n", o_.out.c_str(),
                    o_.out.c_str());
      }
      return 0;
    } catch (const DiagnoseError& e) {
      std::fprintf(stderr, "wetdem: error: %s\n", e.what());
      return 2;
    } catch (const app::CaseError& e) {
      std::fprintf(stderr, "wetdem: error: %s\n", e.what());
      return 2;
    } catch (const study::StudyError& e) {
      std::fprintf(stderr, "wetdem: error: %s\n", e.what());
      return 2;
    }
  }

 private:
  // After the files are read (their errors come first), before any run: --batch, or the device's default.
  void choose_batch() {
    std::string why, why_jobs;
    try {
      study::DeviceKind kind(o_.device);  // one Vulkan context for both defaults
      o_.batch = resolve_batch(batch_, kind, &why);
      o_.jobs = int(study::resolve_jobs(jobs_, kind, &why_jobs));
    } catch (const std::runtime_error& e) {
      throw DiagnoseError(std::string("--device: ") + e.what());
    }
    if (!o_.quiet) std::printf("%s; %s\n", why.c_str(), why_jobs.c_str());
  }
  void add_common(CLI::App* c) {
    c->add_option("--out", o_.out, "output directory (required unless --check)");
    c->add_option("--store", o_.store, "run store to use and share (a study directory; default OUT/store)");
    c->add_option("--jobs", jobs_,
                  "runs at a time (default: one per CPU core, up to " +
                      std::to_string(study::kCpuAutoJobsMax) +
                      ", on a CPU device such as lavapipe; 1 on a GPU)")
        ->check(CLI::PositiveNumber);
    c->add_option("--batch", batch_,
                  "runs handed to one process as ensembles (default: 1 on a CPU device such as lavapipe, " +
                      std::to_string(kGpuAutoBatch) + " on a GPU; docs/ensembles.md)")
        ->check(CLI::PositiveNumber);
    c->add_option("--device", o_.device, "device for every run (index, name substring, gpu, cpu)");
    c->add_flag("--quiet", o_.quiet, "no progress line");
    c->add_flag(
        "--no-figures", [this](int64_t) { o_.figures = false; }, "do not plot");
  }
  CLI::App *diag_ = nullptr, *twin_ = nullptr;
  std::string file_, observations_;
  int replicates_ = 0;   // 0: the file's
  int escalate_ = -1;    // -1: the file's
  size_t jobs_ = 0;      // 0: by device (resolve_jobs)
  int probe_seeds_ = 0;  // 0: the file's
  size_t batch_ = 0;     // 0: auto (auto_batch.h)
  DiagnoseOptions o_;
};

}  // namespace

std::unique_ptr<study::Commands> add_commands(CLI::App& cli) {
  return std::make_unique<Impl>(cli);
}

}  // namespace wetdem::diagnose
