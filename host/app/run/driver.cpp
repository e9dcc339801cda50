#include "app/run/driver.h"

#include <fmt/format.h>

#include <ctime>

#include "app/drum/psd.h"
#include "app/output/checkpoint.h"
#include "wetdem/version.h"

namespace fs = std::filesystem;

namespace wetdem::app {

namespace {

std::string local_time(const char* fmt_str) {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, fmt_str, &tm);
  return buf;
}

void log_result(RunLog& log, const nlohmann::json& s, const fs::path& dir) {
  auto num = [](const nlohmann::json& v) {
    return v.is_number() ? fmt::format("{:.4g}", v.get<double>()) : "-";
  };
  log(fmt::format("bridges {}, contacts {} (window means); {:.3g} particle-steps/s, {:.1f} s wall",
                  num(s["bridges_mean"]), num(s["contacts_mean"]), s["particle_steps_per_s"].get<double>(),
                  s.value("wall_time_s", 0.0)));
  for (const std::string& l : result_lines(s)) log(l);  // issue 21: what may be quoted, and what not
  if (s.contains("figures")) {
    std::string l = "figures:";
    for (const auto& f : s["figures"]) l += " " + (dir / f.get<std::string>()).string();
    if (s["figures"].empty()) l += " none";
    log(l);
  }
  if (!s.value("figures_error", "").empty()) log("WARNING: " + s["figures_error"].get<std::string>());
  log("summary: " + (dir / "summary.json").string());
}

}  // namespace

// The run folder: a new one (refusing one that holds a run), or the folder of a run to resume.
fs::path open_run_folder(const RunOptions& opt, const Case& c) {
  if (!opt.resume_dir.empty()) {
    const fs::path dir = opt.resume_dir;
    if (fs::exists(dir / "summary.json"))
      throw CaseError("", "--resume " + dir.string() + ": the run is complete");
    return dir;
  }
  const fs::path dir =
      opt.out_dir.empty()
          ? fs::path("runs") / ((c.name.empty() ? fs::path(c.source).stem().string() : c.name) + "-" +
                                local_time("%Y%m%d-%H%M%S"))
          : fs::path(opt.out_dir);
  for (const char* f : {"summary.json", "case.toml", "checkpoint"})
    if (fs::exists(dir / f))
      throw CaseError("", "--out " + dir.string() + " already holds a run (use --resume or another --out)");
  fs::create_directories(dir);
  write_file_atomic((dir / "case.toml").string(),
                    "# resolved case (SI), written by wetdem run\n" + case_to_toml(c));
  return dir;
}

void log_setup(RunLog& log, const Prepared& prep, const Schedule& sch, bool resume) {
  const Case& c = prep.c;
  const Derived& d = prep.derived;
  log(fmt::format("wetdem {} | {} | {} | case {}", code_version(), local_time("%Y-%m-%d %H:%M:%S"),
                  resume ? "resume" : "run", c.source));
  for (const std::string& note : c.notes) log("note: " + note);
  for (const std::string& note : d.notes) log("note: " + note);
  log("psd: " + prep.psd_description);
  const PsdQuantiles q = sample_quantiles(prep.diameters, PsdBasis::kVolume);
  log(fmt::format(
      "inserted: {} particles, volume-basis D10/D25/D50/D75/D90 = {:.1f}/{:.1f}/{:.1f}/{:.1f}/{:.1f} µm "
      "(scaled, l = {})",
      prep.state.p.size(), q.d10 * 1e6, q.d25 * 1e6, q.d50 * 1e6, q.d75 * 1e6, q.d90 * 1e6, c.scaling));
  log(fmt::format(
      "material: density {} kg/m³ (particle density: an assumption, the paper gives bulk densities), "
      "nu = {:.4g}, reduced E* = {:.4g} Pa, G* = {:.4g} Pa",
      c.material.density, d.nu, d.E_star, d.G_star));
  log(fmt::format(
      "time step: dt = {:.4g} s (set by: {}; {:.3g} x Rayleigh time {:.4g} s of r_min = {:.4g} m); skin "
      "{:.4g} m{}",
      d.dt, d.dt_reason, d.dt / d.t_rayleigh, d.t_rayleigh, d.r_min, d.skin,
      c.run.skin ? "" : " (0.3 r_min)"));
  if (c.liquid.on())
    log(fmt::format(
        "liquid: gamma x l = {:.4g} N/m, unit = V-bar_S 2^-40 = {:.4g} m³, V_min = {} units, V_max = {} "
        "units, films {}",
        d.gamma_scaled, d.liquid_unit_m3, d.v_min_units, d.v_max_units,
        c.liquid.films == FilmMode::MeanVolume ? "phi_L x V-bar_S" : "phi_L x own volume"));
  log(fmt::format(
      "schedule: {} settle + {} rotating steps, sample every {}, snapshot every {}, checkpoint every {}",
      sch.n_settle, sch.total - sch.n_settle, sch.sample, sch.snapshot, sch.checkpoint));
}

RunTotals run_totals(const Prepared& prep, const SystemState& fin, int64_t liquid_start, uint64_t steps,
                     double particle_steps_per_s, double wall_s, const std::string& device,
                     const SystemCounters& counters, uint64_t resumed_from_step) {
  RunTotals t;
  t.particles = prep.state.p.size();
  t.steps = steps;
  t.dt = prep.derived.dt;
  t.liquid_start = liquid_start;
  t.liquid_end = fin.total_liquid();
  t.liquid_budget_end = fin.liquid_budget();
  t.liquid_unit_m3 = prep.prm.liquid_unit_m3;
  t.particle_steps_per_s = particle_steps_per_s;
  t.wall_s = wall_s;
  t.device = device;
  t.inserted_diameters = prep.diameters;
  t.final_state_hash = state_hash(fin);
  t.counters = counters;
  t.resumed_from_step = resumed_from_step;
  return t;
}

nlohmann::json write_summary(const fs::path& dir, const Prepared& prep, const std::vector<Sample>& samples,
                             const RunTotals& t, const nlohmann::json& extra, RunLog& log,
                             const std::function<void(nlohmann::json&)>& before_write) {
  nlohmann::json s = make_summary(prep.c, prep.derived, samples, t);
  for (const auto& [k, v] : extra.items()) s[k] = v;
  if (before_write) before_write(s);
  if (t.liquid_start != t.liquid_end)
    log(fmt::format("WARNING: liquid not conserved: {} units at the start, {} at the end", t.liquid_start,
                    t.liquid_end));
  write_file_atomic((dir / "summary.json").string(), s.dump(2) + "\n");
  fs::remove_all(dir / "checkpoint");
  fs::remove_all(dir / "checkpoint.old");
  log_result(log, s, dir);
  return s;
}

}  // namespace wetdem::app
