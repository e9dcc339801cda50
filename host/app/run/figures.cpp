#include "app/run/figures.h"

#include <fmt/format.h>

#include <sys/wait.h>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "app/observe/surface.h"
#include "app/output/summary.h"
#include "wetdem/observables.h"

#ifndef WETDEM_SOURCE_DIR
#define WETDEM_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;

namespace wetdem::app {

namespace {

// The figures plot_run.py makes (checked after it ran: only files that exist are listed).
constexpr const char* kFigures[] = {"figures/aor.png", "figures/bed.png"};

std::string last_lines(const fs::path& p, size_t n) {
  std::ifstream f(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(f, l);)
    if (!l.empty()) lines.push_back(l);
  std::string out;
  for (size_t i = lines.size() > n ? lines.size() - n : 0; i < lines.size(); ++i)
    out += (out.empty() ? "" : " | ") + lines[i];
  return out;
}

nlohmann::json finite_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

}  // namespace

std::string default_plot_run_script() {
  if (const char* e = std::getenv("WETDEM_PLOT_RUN_SCRIPT")) return e;
  return std::string(WETDEM_SOURCE_DIR) + "/scripts/plot_run.py";
}

nlohmann::json plot_data(const Prepared& prep, const SystemState& last, const nlohmann::json& s,
                         double color_max_m3) {
  const Case& c = prep.c;
  nlohmann::json j;
  j["name"] = c.name;
  j["description"] = c.description;
  j["device"] = s.value("device", "");
  j["drum"] = {{"radius_m", 0.5 * c.drum.diameter},
               {"omega_rad_s", c.drum.omega},
               {"periodic_slice", c.drum.periodic_slice},
               {"length_m", c.drum.sim_length()}};
  j["rotation_start_s"] = c.run.settle;
  // The window verdicts exactly as summary.json has them (the figure repeats them, it decides nothing).
  for (const char* k : {"aor_window_s", "aor_deg_mean", "aor_sem_block", "aor_deg_std", "aor_stationary",
                        "aor_stationary_reason", "aor_sem_reliable", "aor_sem_reliable_reason", "aor_n_eff",
                        "aor_samples", "aor_flag", "f_wet_mean", "f_wet_sem", "f_wet_stationary",
                        "aor_surface_deg", "aor_window_revolutions"})
    if (s.contains(k)) j["summary"][k] = s[k];

  // The last frame: positions, radii, liquid per particle (film + half of each pair bridge + wall bridges).
  const std::vector<double> liquid = liquid_per_particle(last);
  const double unit = prep.prm.liquid_unit_m3;
  nlohmann::json x = nlohmann::json::array(), y = nlohmann::json::array(), z = nlohmann::json::array(),
                 r = nlohmann::json::array(), q = nlohmann::json::array();
  const ParticleArrays& p = last.p;
  for (size_t i = 0; i < p.size(); ++i) {
    x.push_back(p.x[i].x), y.push_back(p.x[i].y), z.push_back(p.x[i].z), r.push_back(p.radius[i]);
    q.push_back(i < liquid.size() ? liquid[i] * unit : 0.0);
  }
  j["frame"] = {{"time_s", last.time},
                {"x_m", x},
                {"y_m", y},
                {"z_m", z},
                {"radius_m", r},
                {"liquid_m3", q},
                {"liquid_color_max_m3", color_max_m3}};

  // The free surface of this frame as the camera observable fits it (observe/surface.h): the line
  // p . n(α) = height, n(α) = (-sin α, cos α), and the surface-layer particles of the fitted columns.
  const observe::SurfaceResult sf = observe::fit_surface(last, 0.5 * c.drum.diameter, c.drum.sim_length());
  nlohmann::json layer = nlohmann::json::array();
  for (size_t i : sf.layer) layer.push_back(i);
  j["surface"] = {{"valid", sf.valid},
                  {"angle_deg", finite_or_null(sf.angle_deg)},
                  {"height_m", finite_or_null(sf.height_m)},
                  {"com_angle_deg", finite_or_null(sf.com_angle_deg)},
                  {"columns", sf.columns},
                  {"layer", layer}};
  return j;
}

void add_figures(const fs::path& dir, const Prepared& prep, const SystemState& last, double color_max_m3,
                 const std::string& python, const std::string& script, nlohmann::json& summary) {
  std::string error;
  try {
    fs::create_directories(dir / "figures");
    for (const char* f : kFigures) fs::remove(dir / f);  // a resumed run draws them afresh
    write_file_atomic((dir / "figures" / "plot_data.json").string(),
                      plot_data(prep, last, summary, color_max_m3).dump() + "\n");
    const fs::path log = dir / "figures" / "plot.log";
    const std::string cmd =
        fmt::format("'{}' '{}' '{}' > '{}' 2>&1", python, script, dir.string(), log.string());
    const int rc = std::system(cmd.c_str());
    if (rc != 0)
      error = fmt::format("figures: `{} {}` failed (exit {}): {} (figures/plot.log)", python, script,
                          WIFEXITED(rc) ? WEXITSTATUS(rc) : rc, last_lines(log, 1));
  } catch (const std::exception& e) {
    error = std::string("figures: ") + e.what();
  }
  nlohmann::json made = nlohmann::json::array();
  std::string missing;
  for (const char* f : kFigures) {
    if (fs::exists(dir / f))
      made.push_back(f);
    else
      missing += (missing.empty() ? "" : ", ") + std::string(f);
  }
  if (error.empty() && !missing.empty()) error = "figures: not made: " + missing + " (figures/plot.log)";
  summary["figures"] = made;
  summary["figures_error"] = error;
}

}  // namespace wetdem::app
