// What the drivers of drum runs share (run_case: one run; run_batch: an ensemble, ensemble.h): the run
// folder, the set-up lines of run.log, the totals of a finished run and its summary.json.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/output/summary.h"
#include "app/run/log.h"
#include "app/run/run.h"
#include "app/run/schedule.h"
#include "wetdem/system.h"

namespace wetdem::app {

// The run folder: a new one (refusing one that holds a run), or the folder of a run to resume.
std::filesystem::path open_run_folder(const RunOptions& opt, const Case& c);

void log_setup(RunLog& log, const Prepared& prep, const Schedule& sch, bool resume);

RunTotals run_totals(const Prepared& prep, const SystemState& fin, int64_t liquid_start, uint64_t steps,
                     double particle_steps_per_s, double wall_s, const std::string& device,
                     const SystemCounters& counters, uint64_t resumed_from_step);

// summary.json of a finished run (atomically, last), with `extra` keys added and `before_write` (if given)
// called on it just before it is written (the figures add themselves there); drops the checkpoint (a
// complete run cannot be resumed) and logs the result. Returns the summary.
nlohmann::json write_summary(const std::filesystem::path& dir, const Prepared& prep,
                             const std::vector<Sample>& samples, const RunTotals& t,
                             const nlohmann::json& extra, RunLog& log,
                             const std::function<void(nlohmann::json&)>& before_write = {});

}  // namespace wetdem::app
