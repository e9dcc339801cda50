// The local executor on real (tiny) runs, in this process: a second `study run` computes nothing, a stopped
// run resumes from its checkpoint and ends bitwise where an uninterrupted run ends, a failed run is isolated.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "study/executor.h"
#include "support/gpu.h"
#include "support/study_files.h"

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;

// Two seeds of the micro case, cut to ~260 steps (0.1 s at dt ~ 3.8e-4 s), a checkpoint every 100 steps.
std::string tiny_study(const std::string& dir) {
  const std::string text = "name = \"tiny\"\nbase = \"" + micro_case() +
                           "\"\nreplicates = 2\n[set]\n\"run.settle\" = \"0.04 s\"\n"
                           "\"run.duration\" = \"0.06 s\"\n\"run.steady_state_start\" = \"0.02 s\"\n"
                           "\"output.checkpoint_interval\" = 100\n";
  const auto s = study::parse_study_file(write_text(dir + "/tiny.toml", text));
  study::write_plan(dir + "/st", s, study::expand(s));
  return dir + "/st";
}

nlohmann::json summary(const std::string& st, size_t i) {
  const auto ix = study::read_index(st);
  std::ifstream in(st + "/" + ix.runs[i].run_dir + "/summary.json");
  return nlohmann::json::parse(in);
}

study::ExecOptions in_process() {
  study::ExecOptions o;
  o.quiet = true;
  return o;
}

// In-process runs on the test's device; run `index` throws "injected failure" at a sample after step 0.
std::function<void(const study::IndexEntry&, app::RunOptions&)> failing_run(size_t index) {
  return [index](const study::IndexEntry& e, app::RunOptions& ro) {
    ro.context = &gpu();
    if (e.index == index)
      ro.on_sample = [](const app::Sample& s) {
        if (s.step > 0) throw std::runtime_error("injected failure");
      };
  };
}

class StudyRun : public GpuTest {};

TEST_F(StudyRun, StoppedRunResumesAndSecondRunComputesNothing) {
  const std::string st = tiny_study(study_temp("resume"));
  study::ExecOptions o = in_process();
  o.configure = [](const study::IndexEntry& e, app::RunOptions& ro) {
    ro.context = &gpu();
    if (e.index == 1) ro.stop_after_steps = 100;  // as if killed after its first checkpoint
  };
  const study::ExecReport a = study::run_study(st, o);
  EXPECT_EQ(a.completed, 1u);
  EXPECT_EQ(a.stopped, 1u);
  EXPECT_EQ(study::run_state(st + "/" + study::read_index(st).runs[1].run_dir), study::RunState::Resumable);
  o.configure = [](const study::IndexEntry&, app::RunOptions& ro) { ro.context = &gpu(); };
  const study::ExecReport b = study::run_study(st, o);
  EXPECT_EQ(b.already_complete, 1u);
  EXPECT_EQ(b.started, 1u);
  EXPECT_EQ(b.completed, 1u);
  EXPECT_EQ(summary(st, 1).value("resumed_from_step", 0u), 100u);
  const study::ExecReport c = study::run_study(st, o);
  EXPECT_EQ(c.already_complete, 2u);
  EXPECT_EQ(c.started, 0u);
  // The resumed run ends where an uninterrupted run of the same case ends: run it again from scratch.
  const std::string resumed_hash = summary(st, 1)["final_state_hash"];
  fs::remove_all(st + "/" + study::read_index(st).runs[1].run_dir);
  EXPECT_EQ(study::run_study(st, o).completed, 1u);
  EXPECT_EQ(summary(st, 1)["final_state_hash"], resumed_hash);
}

TEST_F(StudyRun, FailedRunIsIsolated) {
  const std::string st = tiny_study(study_temp("failed"));
  study::ExecOptions o = in_process();
  o.configure = failing_run(0);
  const study::ExecReport a = study::run_study(st, o);
  EXPECT_EQ(a.failed, 1u);
  EXPECT_EQ(a.completed, 1u);
  const auto ix = study::read_index(st);
  std::string why;
  EXPECT_EQ(study::run_state(st + "/" + ix.runs[0].run_dir, &why), study::RunState::Failed);
  EXPECT_NE(why.find("injected failure"), std::string::npos) << why;
  EXPECT_TRUE(fs::exists(st + "/" + ix.runs[1].run_dir + "/summary.json"));
  // Not retried unless asked.
  const study::ExecReport b = study::run_study(st, o);
  EXPECT_EQ(b.started, 0u);
  EXPECT_EQ(b.skipped_failed, 1u);
}

// A short micro study over three liquid contents of one seed (one dt, so one ensemble can hold them), with
// `extra` lines in its [set], planned twice: BASE/one (run one by one) and BASE/batch (run as a batch).
std::string three_contents_planned(const std::string& name, const std::string& extra) {
  const std::string text = "name = \"grid\"\nbase = \"" + micro_case() +
                           "\"\n[set]\n\"run.settle\" = \"0.04 s\"\n\"run.duration\" = \"0.06 s\"\n"
                           "\"run.steady_state_start\" = \"0.02 s\"\n" +
                           extra + "[axes]\n\"liquid.content\" = [\"0 %\", \"2.5 %\", \"10 %\"]\n";
  const std::string base = study_temp(name);
  const auto s = study::parse_study_file(write_text(base + "/grid.toml", text));
  for (const char* d : {"/one", "/batch"}) study::write_plan(base + d, s, study::expand(s));
  return base;
}

TEST_F(StudyRun, BatchedRunsAreBitwiseTheRunsOneByOne) {
  // Three liquid contents of one seed (one dt): `--batch 3` steps them as one ensemble, and every run's
  // summary is bitwise what the one-by-one executor writes; a study of two seeds (two dt) is split into
  // ensembles of what can share a System and still completes.
  const std::string base = three_contents_planned("batch", "");
  study::ExecOptions o = in_process();
  o.configure = [](const study::IndexEntry&, app::RunOptions& ro) { ro.context = &gpu(); };
  EXPECT_EQ(study::run_study(base + "/one", o).completed, 3u);
  o.batch = 3;
  const study::ExecReport b = study::run_study(base + "/batch", o);
  EXPECT_EQ(b.completed, 3u);
  for (size_t i = 0; i < 3; ++i) {
    const nlohmann::json x = summary(base + "/one", i), y = summary(base + "/batch", i);
    EXPECT_EQ(x["final_state_hash"], y["final_state_hash"]) << "run " << i;
    EXPECT_FALSE(x.contains("ensemble"));
    EXPECT_EQ(y["ensemble"]["runs"], 3) << "run " << i;
  }
  fs::create_directories(base + "/seeds");
  const std::string st = tiny_study(base + "/seeds");
  o.batch = 2;
  EXPECT_EQ(study::run_study(st, o).completed, 2u);
}

TEST_F(StudyRun, AFailingRunFailsAloneItsBatchmatesComplete) {
  // A batch fails whole (app::run_batch), so run_batch_of runs each run of a failed batch again alone: the
  // failing run stays FAILED with its own reason, its batchmates complete bitwise as they do one by one, and
  // none of them is left FAILED for its batchmate's reason (a diagnosis would then find its baseline failed).
  const std::string base = three_contents_planned("batch-fail", "");
  study::ExecOptions o = in_process();
  o.configure = failing_run(1);
  EXPECT_EQ(study::run_study(base + "/one", o).completed, 2u);
  o.batch = 3;
  const study::ExecReport b = study::run_study(base + "/batch", o);
  EXPECT_EQ(b.completed, 2u);
  EXPECT_EQ(b.failed, 1u);
  const auto ix = study::read_index(base + "/batch");
  for (size_t i = 0; i < 3; ++i) {
    std::string why;
    const study::RunState st = study::run_state(base + "/batch/" + ix.runs[i].run_dir, &why);
    if (i == 1) {
      EXPECT_EQ(st, study::RunState::Failed);
      EXPECT_NE(why.find("injected failure"), std::string::npos) << why;
      EXPECT_EQ(why.find("batch"), std::string::npos) << "failed for the batch, not alone: " << why;
    } else {
      EXPECT_EQ(st, study::RunState::Complete) << "run " << i << ": " << why;
      EXPECT_EQ(summary(base + "/one", i)["final_state_hash"],
                summary(base + "/batch", i)["final_state_hash"])
          << "run " << i;
    }
  }
}

TEST_F(StudyRun, StoppedBatchResumesAsABatchAndEndsBitwise) {
  // Issue 19: a `--batch 3` ensemble stopped as if killed leaves each run resumable; the next `study run`
  // (here without --batch) resumes the three as the batch they were, and each ends bitwise where the run done
  // on its own ends.
  const std::string base = three_contents_planned("batch_stop", "\"output.checkpoint_interval\" = 100\n");
  study::ExecOptions o = in_process();
  o.configure = [](const study::IndexEntry&, app::RunOptions& ro) { ro.context = &gpu(); };
  EXPECT_EQ(study::run_study(base + "/one", o).completed, 3u);
  o.batch = 3;
  o.configure = [](const study::IndexEntry&, app::RunOptions& ro) {
    ro.context = &gpu();
    ro.stop_after_steps = 200;  // a checkpoint boundary
  };
  const study::ExecReport a = study::run_study(base + "/batch", o);
  EXPECT_EQ(a.stopped, 3u);
  const auto ix = study::read_index(base + "/batch");
  for (size_t i = 0; i < 3; ++i)
    EXPECT_EQ(study::run_state(base + "/batch/" + ix.runs[i].run_dir), study::RunState::Resumable) << i;
  EXPECT_EQ(study::plan_batches(base + "/batch", {2, 0, 1}, 1).size(), 1u) << "the stopped batch stays whole";
  o.batch = 1;
  o.configure = [](const study::IndexEntry&, app::RunOptions& ro) { ro.context = &gpu(); };
  const study::ExecReport b = study::run_study(base + "/batch", o);
  EXPECT_EQ(b.completed, 3u);
  for (size_t i = 0; i < 3; ++i) {
    const nlohmann::json x = summary(base + "/one", i), y = summary(base + "/batch", i);
    EXPECT_EQ(x["final_state_hash"], y["final_state_hash"]) << "run " << i;
    EXPECT_EQ(y["ensemble"]["runs"], 3) << "run " << i;
    EXPECT_EQ(y.value("resumed_from_step", 0u), 200u) << "run " << i;
  }
}

}  // namespace
}  // namespace wetdem::test
