// Figures of a finished run (issue 21), drawn by scripts/plot_run.py with Debian's matplotlib
// (/usr/bin/python3), as the study figures are:
//   figures/aor.png  the dynamic AoR against time, the averaging window shaded, its mean ± error marked;
//   figures/bed.png  the last frame seen along the drum axis, particles as circles of their radius coloured
//   by
//                    liquid per particle (the snapshots' colour scale), the fitted free surface drawn.
// The script reads timeseries.csv and figures/plot_data.json, which add_figures writes: the window verdict
// of the summary, and the last frame with the surface fit of app/observe/surface.h. A figure that fails never
// fails the run: summary.json gets figures_error with the reason (and the log a warning), and lists in
// `figures` only the PNGs that exist.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "app/run/run.h"
#include "wetdem/state.h"

namespace wetdem::app {

// The plotting script: $WETDEM_PLOT_RUN_SCRIPT, else scripts/plot_run.py of the source tree.
std::string default_plot_run_script();

// figures/plot_data.json: what plot_run.py draws besides the time series. color_max_m3: the top of the
// liquid colour scale (the largest initial film, as the glTF/VTK frames).
nlohmann::json plot_data(const Prepared& prep, const SystemState& last, const nlohmann::json& summary,
                         double color_max_m3);

// Writes figures/plot_data.json, runs `python script DIR` (output in figures/plot.log), and sets
// summary["figures"] (the PNGs made, relative to dir) and summary["figures_error"] ("" when all were made).
void add_figures(const std::filesystem::path& dir, const Prepared& prep, const SystemState& last,
                 double color_max_m3, const std::string& python, const std::string& script,
                 nlohmann::json& summary);

}  // namespace wetdem::app
