// What a run writes besides snapshots: the sampled time series (timeseries.csv), and summary.json, the one
// file that says a run completed. Files are written to a temporary name and renamed, so a reader never sees a
// partial file and a killed run never leaves a summary.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/case/case.h"
#include "app/observe/camera.h"
#include "wetdem/state.h"
#include "wetdem/system.h"

namespace wetdem::app {

// One sample of the bed, taken every run.sample_interval (settling included).
struct Sample {
  uint64_t step = 0;
  double time = 0;              // s since the start of the run
  double aor_signed_deg = 0;    // atan2(com_x, -com_y) (app/aor.h convention); |.| is the AoR
  double com_x = 0, com_y = 0;  // m
  bool flagged = true;          // |COM| < 0.2 R: no angle reported
  uint64_t contacts = 0, bridges = 0;
  double f_wet = 0, kinetic_energy = 0;
  observe::CameraSample camera;  // diagnosis.md §2 (app/observe/camera.h); NaN: no value this sample
  // Liquid accounting (units of liquid_unit_m3): films + bridges + pores + evaporated = liquid put in.
  int64_t liquid_films = 0, liquid_bridges = 0, liquid_pores = 0, liquid_evaporated = 0;
  double liquid_unit_m3 = 0;
  // The free surface's height (m) in fixed laboratory-frame columns (app/observe/interface.h), for the
  // window's cohesive index; NaN where a column is not full.
  std::vector<double> interface;
};

// path.tmp, flushed and fsync'ed, then renamed over path. Throws std::runtime_error on failure.
void write_file_atomic(const std::string& path, const std::string& content);

std::string timeseries_header();
std::string timeseries_row(const Sample& s);
// Exact JSON round trip (doubles are written with 17 digits), for checkpoints.
// x as a JSON number, or null when it is NaN or infinite (JSON has neither).
nlohmann::json number_or_null(double x);

nlohmann::json samples_to_json(const std::vector<Sample>& s);
std::vector<Sample> samples_from_json(const nlohmann::json& j);

// 64-bit FNV-1a of the state's bytes (particles, films, wall and pair records, time, step), hex: equal hashes
// mean bitwise-equal states.
std::string state_hash(const SystemState& s);

struct RunTotals {
  size_t particles = 0;
  uint64_t steps = 0;
  double dt = 0;
  int64_t liquid_start = 0, liquid_end = 0;  // liquid units
  LiquidBudget liquid_budget_end;            // where liquid_end is: films, bridges, pores, evaporated
  double liquid_unit_m3 = 0;
  double particle_steps_per_s = 0;  // of the last session (after a resume: since the resume)
  double wall_s = 0;                // wall time of all sessions
  std::string device;
  std::vector<double> inserted_diameters;  // for the inserted D10..D90
  std::string final_state_hash;
  SystemCounters counters;
  uint64_t resumed_from_step = 0;  // 0: ran in one piece
};

// summary.json content: the AoR over the steady window (mean, sd, blocked SEM, flag), window means of f_wet,
// bridges and contacts, the camera observables (<name>, <name>_sem; plate keys absent on a periodic slice)
// and the AoR drift, liquid conservation, performance, the resolved case and derived values, code version.
nlohmann::json make_summary(const Case& c, const Derived& d, const std::vector<Sample>& samples,
                            const RunTotals& t);

// The run's final AoR log line from a summary: mean ± blocked SEM, sd, window, tau_int, n_eff, and, when the
// window is not stationary or its error bar not reliable, that verdict with its reason.
std::string aor_log_line(const nlohmann::json& summary);

// The run's result as a user reads it at the end of the log (issue 21): the dynamic AoR with its error and
// stationarity verdict, f_wet with its error and verdict, the AoR drift when the window can carry it (else
// why not), the bridge network labelled as spanning the bed when it does, and every other window quantity
// that may not be quoted. Figures and paths are added by the driver.
std::vector<std::string> result_lines(const nlohmann::json& summary);

}  // namespace wetdem::app
