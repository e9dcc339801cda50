// The run driver: case -> particles in the drum -> GPU system -> settle -> rotate -> samples, snapshots,
// checkpoints -> summary.json. The phases are parts of their own (prepare_run below; DrumSession in
// session.h: settle, rotate, sample, checkpoint; RunOutputs in outputs.h) so studies and ensembles can call
// them. Everything that can be wrong with the input is found before the run folder is created; a run that
// fails later leaves FAILED.txt and no summary.json.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/case/case.h"
#include "app/output/summary.h"
#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {
namespace vk {
class Context;
}

namespace app {

struct RunOptions {
  std::string case_path;               // may be empty with resume_dir (the run's own case.toml is used)
  std::vector<std::string> overrides;  // --set key=value
  std::string out_dir;                 // empty: runs/<case name>-<local time>
  std::string device;                  // vk::ContextOptions::device
  std::string resume_dir;              // continue the run in this folder from its checkpoint
  bool quiet = false;                  // no progress or log on stdout (run.log is still written)
  int progress_tty = -1;               // -1: detect; 0: plain lines; 1: bar
  // Stop, as if killed, once this many steps are done (0: never). The run folder keeps its checkpoints and
  // gets no summary.json. Used by tests of --resume; pick a multiple of output.checkpoint_interval.
  uint64_t stop_after_steps = 0;
  // Called after every sample; an exception thrown here fails the run (tests use it to make a run fail).
  std::function<void(const Sample&)> on_sample;
  vk::Context* context = nullptr;  // use this Vulkan context (tests); otherwise one is created
  // Figures of the finished run (app/run/figures.h): `wetdem run` draws them unless --no-figures; runs inside
  // studies and diagnoses do not (their figures are the study's). A failing figure never fails the run.
  bool figures = false;
  std::string python = "/usr/bin/python3";
  std::string plot_script;  // empty: default_plot_run_script()
};

struct RunResult {
  std::string dir;
  bool completed = false;   // false: stopped by stop_after_steps
  nlohmann::json summary;   // what summary.json holds (empty when not completed)
  SystemState final_state;  // downloaded at the end or at the stop
};

// Runs a case. Throws CaseError on bad input (nothing written), std::runtime_error when the run fails
// (FAILED.txt written in the run folder, no summary.json).
RunResult run_case(const RunOptions& opt);

// The set-up, no file written and no device needed: particles drawn from the PSD and placed without overlaps,
// SimParams (drum at rest: omega = 0 until rotation starts), the initial state with films. Throws CaseError.
struct Prepared {
  Case c;
  Derived derived;
  SimParams prm;      // rotating drum (the run uses omega = 0 while settling)
  SystemState state;  // at rest, films as the case says
  std::vector<double> diameters;
  std::string radii_hash;  // identifies the fill, checked on resume
  std::string psd_description;
};
Prepared prepare_run(const Case& c);

// Asks a running run_case to stop at its next step boundary (async-signal-safe: for SIGINT/SIGTERM handlers).
// The run fails with "interrupted" (FAILED.txt, no summary.json); its last checkpoint stays for --resume.
void request_interrupt();
bool interrupt_requested();  // ... and whether one was asked for (run_batch polls it too)
void clear_interrupt();      // forgets it (tests, and a driver that has handled it)

// Resolves a case like `wetdem run` does (file + overrides, or a run folder's case.toml for --resume).
Case resolve_case(const RunOptions& opt);

}  // namespace app
}  // namespace wetdem
