// End-to-end drum runs on the GPU system (lavapipe in CI): outputs, AoR, failure handling, bitwise resume.
// Small on purpose: ~360 particles in a 60 mm periodic slice, stiffness reduced 10^5 (dt ~ 3.8e-4 s) and a
// fast drum, so a run is a few thousand steps.
#ifdef WETDEM_HAVE_APP

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/run/ensemble.h"
#include "app/run/run.h"
#include "app/run/session.h"
#include "support/gpu.h"
#include "support/small_case.h"
#include "support/state_diff.h"

namespace wetdem::test {
namespace {

namespace fs = std::filesystem;

// A file's whole text (timeseries compared row for row).
std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string temp_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("wetdem_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p.string();
}

std::string write_case(const std::string& dir) {
  fs::create_directories(dir);
  const std::string path = dir + "/small.toml";
  std::ofstream(path) << kSmall;
  return path;
}

app::RunOptions options(const std::string& case_path, const std::string& out) {
  app::RunOptions o;
  o.case_path = case_path;
  o.out_dir = out;
  o.quiet = true;
  o.context = &gpu();
  return o;
}

class DrumRun : public GpuTest {};

TEST_F(DrumRun, WritesSummaryTimeseriesAndFrames) {
  const std::string base = temp_dir("outputs");
  app::RunOptions o = options(write_case(base), base + "/run");
  o.overrides = {"output.formats=[\"gltf\", \"vtk\"]", "output.snapshot_interval=\"0.25 s\""};
  const app::RunResult r = app::run_case(o);
  ASSERT_TRUE(r.completed);
  ASSERT_TRUE(fs::exists(base + "/run/summary.json"));
  std::ifstream in(base + "/run/summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  for (const char* k : {"aor_deg_mean",
                        "aor_deg_std",
                        "aor_sem_block",
                        "aor_window_s",
                        "aor_samples",
                        "aor_flag",
                        "f_wet_mean",
                        "f_wet_definition",
                        "bridges_mean",
                        "contacts_mean",
                        "particles",
                        "steps",
                        "dt_s",
                        "liquid_total_m3_start",
                        "liquid_total_m3_end",
                        "liquid_conserved",
                        "particle_steps_per_s",
                        "device",
                        "case",
                        "code_version",
                        "seed",
                        "inserted_psd_volume_basis_m"})
    EXPECT_TRUE(s.contains(k)) << k;
  EXPECT_TRUE(s["liquid_conserved"].get<bool>());  // exact integer equality (physics.md §5)
  EXPECT_GT(s["particles"].get<int>(), 200);
  EXPECT_LT(s["particles"].get<int>(), 600);
  EXPECT_FALSE(s["aor_flag"].get<bool>());
  // The drum turns about +z (omega > 0): its bottom moves to +x and drags the bed up on the +x side
  // (app/aor.h).
  EXPECT_GT(s["aor_signed_deg_mean"].get<double>(), 5.0);
  EXPECT_LT(s["aor_deg_mean"].get<double>(), 80.0);
  EXPECT_GT(s["contacts_mean"].get<double>(), 0.0);
  EXPECT_GT(s["bridges_mean"].get<double>(), 0.0);  // V_min = 0: every touch forms a bridge
  EXPECT_GT(s["f_wet_mean"].get<double>(), 0.0);
  EXPECT_LE(s["f_wet_mean"].get<double>(), 1.0);
  EXPECT_EQ(s["neighbour_list"]["lost_bridges"].get<uint64_t>(), 0u);

  // timeseries.csv: header + one row per sample, at steps 0, k, 2k, ... <= steps.
  std::ifstream ts(base + "/run/timeseries.csv");
  std::string line;
  std::getline(ts, line);
  EXPECT_EQ(line.rfind("time,aor_deg,com_x,com_y,contacts,bridges,f_wet,kinetic_energy,liquid_films_units,"
                       "liquid_bridges_units,liquid_pores_units,liquid_evaporated_units,liquid_films_m3,"
                       "liquid_bridges_m3,liquid_pores_m3,liquid_evaporated_m3,",
                       0),
            0u)
      << line;
  // A periodic slice has no plates: the slab angles are absent (not zero); the other camera observables
  // are there (tests/test_observe_drum_run.cpp checks a closed drum).
  EXPECT_FALSE(s.contains("aor_plate_deg"));
  EXPECT_FALSE(s.contains("aor_centre_deg"));
  EXPECT_TRUE(s.contains("aor_surface_deg"));
  size_t rows = 0;
  while (std::getline(ts, line)) ++rows;
  const double dt = s["dt_s"].get<double>();
  const uint64_t every = uint64_t(std::llround(0.025 / dt)), steps = s["steps"].get<uint64_t>();
  EXPECT_EQ(rows, steps / every + 1);
  EXPECT_EQ(steps, uint64_t(std::llround(0.25 / dt)) + uint64_t(std::llround(0.7 / dt)));
  EXPECT_TRUE(fs::exists(base + "/run/frames/frames.json"));
  EXPECT_TRUE(fs::exists(base + "/run/frames/frames.pvd"));
  EXPECT_TRUE(fs::exists(base + "/run/case.toml"));
  EXPECT_FALSE(fs::exists(base + "/run/checkpoint"));  // dropped once the run is complete
  EXPECT_FALSE(fs::exists(base + "/run/FAILED.txt"));
  fs::remove_all(base);
}

TEST_F(DrumRun, FailingRunLeavesNoSummaryButFailedTxt) {
  const std::string base = temp_dir("failing");
  app::RunOptions o = options(write_case(base), base + "/run");
  int n = 0;
  o.on_sample = [&](const app::Sample&) {
    if (++n == 3) throw std::runtime_error("injected failure at the third sample");
  };
  EXPECT_THROW(app::run_case(o), std::runtime_error);
  EXPECT_FALSE(fs::exists(base + "/run/summary.json"));
  ASSERT_TRUE(fs::exists(base + "/run/FAILED.txt"));
  std::ifstream in(base + "/run/FAILED.txt");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("injected failure"), std::string::npos);
  fs::remove_all(base);
}

TEST_F(DrumRun, ResumedSessionStepsInLockstepWithTheUninterruptedOne) {
  // The run phases without files: a session resumed from a checkpoint taken while settling and the session
  // that went on are advanced stop by stop (across the settle -> rotate switch) and must be bitwise equal at
  // every stop. When they are not, the first stop and field that differ say where (sample, switch, restore).
  const app::Prepared prep = app::prepare_run(app::parse_case_string(kSmall));
  auto quiet = [](const std::string&) {};
  app::DrumSession a(gpu(), prep, quiet);
  const app::Schedule& sch = a.schedule();
  ASSERT_GT(sch.n_settle, 500u);
  while (a.step() < 500) a.advance(sch.next_stop(a.step()));
  // As --resume does it: the case re-read from its resolved echo, the checkpoint through its files.
  const std::string dir = temp_dir("lockstep");
  app::save_checkpoint(dir, a.checkpoint({}));
  const app::Prepared again = app::prepare_run(app::parse_case_string(app::case_to_toml(prep.c)));
  EXPECT_EQ(app::case_to_json(again.c), app::case_to_json(prep.c));
  app::DrumSession b(gpu(), again, app::load_checkpoint(dir), quiet);
  ASSERT_EQ(b.step(), a.step());
  EXPECT_EQ(first_difference(a.state(), b.state()), "") << "right after the restore at step " << a.step();
  // A second resume while rotating (the restored System is then the turning drum's).
  std::unique_ptr<app::DrumSession> c;
  std::string hist;
  while (!a.done()) {
    const uint64_t to = sch.next_stop(a.step());
    a.advance(to);
    b.advance(to);
    if (c) c->advance(to);
    ASSERT_EQ(first_difference(a.state(), b.state()), "")
        << "first difference by step " << to << " (settled at " << sch.n_settle << ")";
    if (c) {
      auto k = [](app::DrumSession& x) {
        const SystemCounters q = x.system().counters();
        return fmt::format("rebuilds {} split {} regrows {} capacity {} entries {}", q.rebuilds,
                           q.split_rebuilds, q.regrows, q.entry_capacity, q.entries);
      };
      ASSERT_EQ(first_difference(a.state(), c->state()), "")
          << "second resume: first difference by step " << to << " (settled at " << sch.n_settle
          << "); uninterrupted: " << k(a) << "; resumed: " << k(*c) << "; history: " << hist;
      hist += fmt::format(" {}:[{}|{}]", to, k(a), k(*c));
    }
    if (!c && to >= sch.n_settle + 300) {
      app::save_checkpoint(dir, b.checkpoint({}));
      c = std::make_unique<app::DrumSession>(gpu(), again, app::load_checkpoint(dir), quiet);
    }
  }
  ASSERT_TRUE(c);
  fs::remove_all(dir);
}

TEST_F(DrumRun, BatchRunsAreBitwiseTheirRunsAlone) {
  // Three runs of one fill (wet as given; fewer bridges and less friction; dry) in one ensemble write what
  // each writes alone: the same final state hash, AoR and timeseries rows; one that cannot share the
  // ensemble's clock is refused by key before any folder is made.
  const std::string base = temp_dir("batch");
  const std::string case_path = write_case(base);
  const std::vector<std::vector<std::string>> sets = {
      {}, {"liquid.v_max=\"0.5 %\"", "friction.mu_s=0.6"}, {"liquid.content=0"}};
  const std::string shorter = "run.duration=\"0.3 s\"";  // still past the settle -> rotate switch
  std::vector<app::RunOptions> batch;
  std::vector<app::RunResult> alone;
  for (size_t r = 0; r < sets.size(); ++r) {
    app::RunOptions o = options(case_path, base + "/alone" + std::to_string(r));
    o.overrides = sets[r];
    o.overrides.push_back(shorter);
    o.overrides.push_back("run.steady_state_start=\"0.15 s\"");
    alone.push_back(app::run_case(o));
    o.out_dir = base + "/batch" + std::to_string(r);
    batch.push_back(o);
  }
  const std::vector<app::RunResult> together = app::run_batch(batch, gpu());
  ASSERT_EQ(together.size(), sets.size());
  for (size_t r = 0; r < sets.size(); ++r) {
    ASSERT_TRUE(together[r].completed);
    EXPECT_EQ(alone[r].summary["final_state_hash"], together[r].summary["final_state_hash"]) << "run " << r;
    EXPECT_EQ(alone[r].summary["aor_deg_mean"], together[r].summary["aor_deg_mean"]) << "run " << r;
    EXPECT_EQ(together[r].summary["ensemble"]["runs"], 3);
    EXPECT_TRUE(together[r].summary["liquid_conserved"].get<bool>());
    EXPECT_EQ(read_text(alone[r].dir + "/timeseries.csv"), read_text(together[r].dir + "/timeseries.csv"))
        << "run " << r;
  }
  EXPECT_NE(alone[0].summary["final_state_hash"], alone[2].summary["final_state_hash"]);
  EXPECT_GT(alone[0].summary["bridges_mean"].get<double>(), 0.0);
  // Where the wall time went (docs/outputs.md "wall_split_s"): the loop's parts, each measured, add up to the
  // wall time; stepping and sampling happened in every run, alone or batched.
  for (const app::RunResult* res : std::vector<const app::RunResult*>{&alone[0], &together[0]}) {
    const auto& w = res->summary["wall_split_s"];
    double parts = 0;
    for (const char* k : {"stepping", "sampling", "frames", "checkpoints"}) {
      EXPECT_GE(w[k].get<double>(), 0.0) << k;
      parts += w[k].get<double>();
    }
    EXPECT_GT(w["stepping"].get<double>(), 0.0);
    EXPECT_GT(w["sampling"].get<double>(), 0.0);
    EXPECT_LE(parts, w["wall"].get<double>());
    EXPECT_DOUBLE_EQ(parts + w["other"].get<double>(), w["wall"].get<double>());
  }

  std::vector<app::RunOptions> bad = {batch[0], batch[1]};
  bad[0].out_dir = base + "/bad0";
  bad[1].out_dir = base + "/bad1";
  bad[1].overrides.push_back("run.dt=\"0.1 ms\"");
  try {
    app::run_batch(bad, gpu());
    ADD_FAILURE() << "a batch of two time steps ran";
  } catch (const app::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("run.dt"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(base + "/bad0"));
  fs::remove_all(base);
}

TEST_F(DrumRun, StoppedAndInterruptedBatchResumesBitwise) {
  // Issue 19: a batch stopped as if killed (stop_after_steps: its checkpoint at the stop), resumed, then
  // interrupted (SIGTERM's path: a checkpoint at the next step boundary, FAILED.txt "interrupted"), resumed
  // again to the end, writes bitwise what the uninterrupted batch writes: final state hash, timeseries rows.
  const std::string base = temp_dir("batch_resume");
  const std::string case_path = write_case(base);
  const std::vector<std::vector<std::string>> sets = {{}, {"liquid.content=0"}};
  auto batch_in = [&](const std::string& tag) {
    std::vector<app::RunOptions> b;
    for (size_t r = 0; r < sets.size(); ++r) {
      app::RunOptions o = options(case_path, base + "/" + tag + std::to_string(r));
      o.overrides = sets[r];
      o.overrides.push_back("run.duration=\"0.3 s\"");
      o.overrides.push_back("run.steady_state_start=\"0.15 s\"");
      b.push_back(o);
    }
    return b;
  };
  const std::vector<app::RunResult> whole = app::run_batch(batch_in("whole"), gpu());

  std::vector<app::RunOptions> first = batch_in("split");
  first[0].stop_after_steps = 700;  // past the checkpoint at 500, still settling (the switch is at ~650)
  const std::vector<app::RunResult> stopped = app::run_batch(first, gpu());
  for (size_t r = 0; r < sets.size(); ++r) {
    EXPECT_FALSE(stopped[r].completed);
    EXPECT_FALSE(fs::exists(stopped[r].dir + "/summary.json"));
    EXPECT_TRUE(fs::exists(stopped[r].dir + "/" + app::kEnsembleMember));
    EXPECT_EQ(app::ensemble_members(stopped[r].dir).size(), sets.size());
  }
  ASSERT_TRUE(fs::exists(base + "/split0/ensemble/checkpoint/system.bin"));

  std::vector<app::RunOptions> again(sets.size());
  for (size_t r = 0; r < sets.size(); ++r) {
    again[r].resume_dir = base + "/split" + std::to_string(r);
    again[r].quiet = true;
    again[r].context = &gpu();
  }
  // Interrupted at the fourth sample after the resume (rotating by then).
  int seen = 0;
  again[0].on_sample = [&](const app::Sample&) {
    if (++seen == 4) app::request_interrupt();
  };
  EXPECT_THROW(app::run_batch(again, gpu()), std::runtime_error);
  app::clear_interrupt();
  for (size_t r = 0; r < sets.size(); ++r) {
    std::ifstream f(base + "/split" + std::to_string(r) + "/FAILED.txt");
    std::string why;
    std::getline(f, why);
    EXPECT_EQ(why.rfind("interrupted at step", 0), 0u) << why;
  }
  again[0].on_sample = nullptr;
  const std::vector<app::RunResult> resumed = app::run_batch(again, gpu());
  for (size_t r = 0; r < sets.size(); ++r) {
    ASSERT_TRUE(resumed[r].completed);
    EXPECT_EQ(whole[r].summary["final_state_hash"], resumed[r].summary["final_state_hash"]) << "run " << r;
    EXPECT_EQ(whole[r].summary["aor_deg_mean"], resumed[r].summary["aor_deg_mean"]) << "run " << r;
    EXPECT_GT(resumed[r].summary["resumed_from_step"].get<uint64_t>(), 700u) << "run " << r;
    EXPECT_EQ(read_text(whole[r].dir + "/timeseries.csv"), read_text(resumed[r].dir + "/timeseries.csv"))
        << "run " << r;
    EXPECT_FALSE(fs::exists(resumed[r].dir + "/FAILED.txt"));
    EXPECT_FALSE(fs::exists(resumed[r].dir + "/" + app::kEnsembleMember));
  }
  EXPECT_FALSE(fs::exists(base + "/split0/ensemble"));
  EXPECT_NE(whole[0].summary["final_state_hash"], whole[1].summary["final_state_hash"]);
  // A resumed batch must name the checkpoint's runs in its order.
  fs::remove_all(base);
}

TEST_F(DrumRun, ResumeReachesTheBitwiseSameFinalState) {
  const std::string base = temp_dir("resume");
  const std::string case_path = write_case(base);
  const app::RunResult whole = app::run_case(options(case_path, base + "/whole"));
  ASSERT_TRUE(whole.completed);

  // Stop at the first checkpoint (step 500, still settling), resume and stop again at step 1500 (rotating:
  // the resumed part crossed the settle -> rotate switch at step ~650), then resume to the end.
  app::RunOptions first = options(case_path, base + "/split");
  first.stop_after_steps = 500;
  const app::RunResult stopped = app::run_case(first);
  EXPECT_FALSE(stopped.completed);
  EXPECT_FALSE(fs::exists(base + "/split/summary.json"));
  ASSERT_TRUE(fs::exists(base + "/split/checkpoint/system.bin"));

  app::RunOptions again;
  again.resume_dir = base + "/split";
  again.quiet = true;
  again.context = &gpu();
  again.stop_after_steps = 1500;
  EXPECT_FALSE(app::run_case(again).completed);
  again.stop_after_steps = 0;
  const app::RunResult resumed = app::run_case(again);
  ASSERT_TRUE(resumed.completed);

  EXPECT_EQ(whole.summary["final_state_hash"], resumed.summary["final_state_hash"]);
  const SystemState &a = whole.final_state, &b = resumed.final_state;
  ASSERT_EQ(a.p.size(), b.p.size());
  EXPECT_EQ(a.step, b.step);
  for (size_t k = 0; k < a.p.size(); ++k) {
    ASSERT_EQ(a.p.x[k], b.p.x[k]) << k;
    ASSERT_EQ(a.p.v[k], b.p.v[k]) << k;
    ASSERT_EQ(a.p.w[k], b.p.w[k]) << k;
    ASSERT_EQ(a.p.film[k], b.p.film[k]) << k;
  }
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  // The statistics are computed from the same samples, so they agree exactly too.
  for (const char* k : {"aor_deg_mean", "aor_sem_block", "f_wet_mean", "bridges_mean", "contacts_mean"})
    EXPECT_EQ(whole.summary[k], resumed.summary[k]) << k;
  // Both timeseries files hold the same rows.
  EXPECT_EQ(read_text(base + "/whole/timeseries.csv"), read_text(base + "/split/timeseries.csv"));
  // A complete run cannot be resumed.
  EXPECT_THROW(app::run_case(again), app::CaseError);
  fs::remove_all(base);
}

}  // namespace
}  // namespace wetdem::test

#endif  // WETDEM_HAVE_APP
