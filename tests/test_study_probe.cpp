// `study plan --probe` (issue 19): the estimate of a study from a probe's rates, by hand; and plan_batches,
// the batches `study run --batch` and `study slurm --batch` hand out.
#include <gtest/gtest.h>

#include <cmath>

#include "app/run/resources.h"
#include "study/executor.h"
#include "study/probe.h"
#include "support/study_files.h"

namespace wetdem::test {
namespace {

std::vector<study::PlannedRun> five_runs(const std::string& dir) {
  const std::string text =
      "name = \"p\"\nbase = \"" + micro_case() +
      "\"\n[axes]\n\"liquid.content\" = [\"0 %\", \"2.5 %\", \"5 %\", \"7.5 %\", \"10 %\"]\n";
  return study::expand(study::parse_study_file(write_text(dir + "/p.toml", text)));
}

TEST(StudyProbe, EstimateIsTheProbedRatesTimesEachBatchsWork) {
  const auto runs = five_runs(study_temp("probe"));
  study::ProbeResult p;
  p.particles = 1000;
  p.step_s = 0.02;   // 2e-5 s per particle-step
  p.sample_s = 0.1;  // 1e-4 s per particle and sample
  p.setup_s_per_run = 0.5;
  const study::Estimate e = study::estimate(runs, 2, p);
  EXPECT_EQ(e.batches, 3u);  // 2 + 2 + 1
  EXPECT_EQ(e.runs, 5u);
  // By hand: every run has the micro case's particles, steps and samples; a batch's time is its particles x
  // steps x 2e-5 s + particles x samples x 1e-4 s + 0.5 s per run.
  const app::ResourceEstimate r = app::estimate_resources(runs[0].resolved);
  const app::Case& c = runs[0].resolved;
  const double samples = std::floor((c.run.settle + c.run.duration) / c.run.sample_interval) + 1.0;
  const double per_run = r.particles * r.steps * 2e-5 + r.particles * samples * 1e-4;
  EXPECT_NEAR(e.total_s(), 5 * per_run + 5 * 0.5, 1e-9 * e.total_s());
  ASSERT_EQ(e.batch_s.size(), 3u);
  EXPECT_NEAR(e.batch_s[0], 2 * per_run + 1.0, 1e-9 * e.batch_s[0]);
  EXPECT_NEAR(e.batch_s[2], per_run + 0.5, 1e-9 * e.batch_s[2]);
  EXPECT_NEAR(e.particle_steps, 5 * r.particles * r.steps, 1e-9 * e.particle_steps);
}

TEST(StudyProbe, MeasuredRateIsTheCompleteRunsSteppingOnThisDevice) {
  // By hand: a batch of 2 runs of 1,000 particles that stepped 10,000 steps in 4 s of stepping is 5e6
  // particle-steps/s (2e-7 s each); a run resumed at step 4,000 of 8,000 that stepped its 4,000 steps alone
  // in 1 s is 4e6 (2.5e-7 s). The mean time per particle-step is 2.25e-7 s: 4.444e6 particle-steps/s. Runs on
  // another device, or without a stepping time, are left out.
  const nlohmann::json batch = {{"device", "GPU A"},
                                {"particles", 1000},
                                {"steps", 10000},
                                {"ensemble", {{"runs", 2}}},
                                {"wall_split_s", {{"stepping", 4.0}, {"sampling", 3.0}}}};
  const nlohmann::json resumed = {{"device", "GPU A"},
                                  {"particles", 1000},
                                  {"steps", 8000},
                                  {"resumed_from_step", 4000},
                                  {"wall_split_s", {{"stepping", 1.0}}}};
  nlohmann::json other = batch;
  other["device"] = "GPU B";
  nlohmann::json old = batch;
  old.erase("wall_split_s");
  const study::MeasuredRate m = study::measured_rate({batch, batch, resumed, other, old}, "GPU A");
  EXPECT_EQ(m.runs, 3u);
  EXPECT_NEAR(m.particle_steps_per_s, 3.0 / (2e-7 + 2e-7 + 2.5e-7), 1.0);
  EXPECT_EQ(m.batch_min, 1u);
  EXPECT_EQ(m.batch_max, 2u);
  EXPECT_EQ(study::measured_rate({other, old}, "GPU A").runs, 0u);
  EXPECT_EQ(study::measured_rate({batch, other, old}, "").runs, 2u) << "an empty device takes every device";

  // The estimate at that rate: the probe's stepping time replaced, its samples and set-up kept.
  study::ProbeResult p;
  p.particles = 2000;
  p.step_s = 1e-4;  // 2e7 particle-steps/s on a fresh bed
  p.particle_steps_per_s = 2e7;
  p.sample_s = 0.01;
  const study::ProbeResult q = study::at_rate(p, 5e6);
  EXPECT_DOUBLE_EQ(q.step_s, 4e-4);
  EXPECT_DOUBLE_EQ(q.particle_steps_per_s, 5e6);
  EXPECT_DOUBLE_EQ(q.sample_s, p.sample_s);
  const auto runs = five_runs(study_temp("probe_rate"));
  const study::Estimate a = study::estimate(runs, 2, p), b = study::estimate(runs, 2, q);
  EXPECT_NEAR(b.step_s, 4 * a.step_s, 1e-9 * b.step_s);
  EXPECT_NEAR(b.sample_s, a.sample_s, 1e-12);
}

TEST(StudyProbe, PlanBatchesSpreadsTheQueueEvenlyOverTheProcesses) {
  const std::string dir = study_temp("batches");
  const auto runs = five_runs(dir);
  const auto s = study::parse_study_file(dir + "/p.toml");
  study::write_plan(dir + "/st", s, runs);
  using B = std::vector<std::vector<size_t>>;
  // At most `batch` a run, in queue order, as few batches as that allows, of even sizes.
  EXPECT_EQ(study::plan_batches(dir + "/st", {4, 0, 1, 3}, 3), (B{{4, 0}, {1, 3}}));
  EXPECT_EQ(study::plan_batches(dir + "/st", {4, 0, 1, 3, 2}, 3), (B{{4, 0, 1}, {3, 2}}));
  EXPECT_EQ(study::plan_batches(dir + "/st", {0, 1}, 1), (B{{0}, {1}}));
  // Two processes: a multiple of two batches where there are runs enough (no process idles in a last round).
  EXPECT_EQ(study::plan_batches(dir + "/st", {0, 1, 2, 3, 4}, 4, 2), (B{{0, 1, 2}, {3, 4}}));
  EXPECT_EQ(study::plan_batches(dir + "/st", {0, 1, 2}, 4, 2), (B{{0, 1}, {2}}));
  EXPECT_EQ(study::plan_batches(dir + "/st", {0, 1, 2, 3, 4}, 2, 2), (B{{0, 1}, {2}, {3}, {4}}));
  EXPECT_EQ(study::plan_batches(dir + "/st", {0, 1}, 4, 3), (B{{0}, {1}}));
}

}  // namespace
}  // namespace wetdem::test
