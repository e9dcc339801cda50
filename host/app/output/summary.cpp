#include "app/output/summary.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "app/drum/aor.h"
#include "app/drum/psd.h"
#include "app/observe/interface.h"
#include "app/observe/window.h"
#include "app/output/timeseries_stats.h"
#include "app/output/window_rules.h"
#include "wetdem/observables.h"
#include "wetdem/version.h"

#ifndef WETDEM_VERSION
#define WETDEM_VERSION "unknown"
#endif

namespace wetdem::app {

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(errno));
  size_t done = 0;
  while (done < content.size()) {
    const ssize_t w = ::write(fd, content.data() + done, content.size() - done);
    if (w < 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      ::close(fd);
      throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(e));
    }
    done += size_t(w);
  }
  // fsync before rename: after a crash the new name holds either the old or the complete new content.
  if (::fsync(fd) != 0 || ::close(fd) != 0) throw std::runtime_error("cannot flush " + tmp);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + std::strerror(errno));
}

std::string timeseries_header() {
  std::string h =
      "time,aor_deg,com_x,com_y,contacts,bridges,f_wet,kinetic_energy,"
      "liquid_films_units,liquid_bridges_units,liquid_pores_units,liquid_evaporated_units,"
      "liquid_films_m3,liquid_bridges_m3,liquid_pores_m3,liquid_evaporated_m3";
  for (const observe::CameraField& f : observe::kCameraFields) h += std::string(",") + f.name;
  return h + "\n";
}

std::string timeseries_row(const Sample& s) {
  // aor_deg is |angle|, empty when the bed is flagged (near-centred: no angle reported, drum.md); a camera
  // observable is empty when it has no value (NaN), e.g. the plate angles on a periodic slice.
  const std::string aor = s.flagged ? "" : fmt::format("{:.9g}", std::fabs(s.aor_signed_deg));
  const double u = s.liquid_unit_m3;
  std::string row = fmt::format(
      "{:.9g},{},{:.9g},{:.9g},{},{},{:.9g},{:.9g},{},{},{},{},{:.9g},{:.9g},{:.9g},{:.9g}", s.time, aor,
      s.com_x, s.com_y, s.contacts, s.bridges, s.f_wet, s.kinetic_energy, s.liquid_films, s.liquid_bridges,
      s.liquid_pores, s.liquid_evaporated, double(s.liquid_films) * u, double(s.liquid_bridges) * u,
      double(s.liquid_pores) * u, double(s.liquid_evaporated) * u);
  for (const observe::CameraField& f : observe::kCameraFields) {
    const double v = s.camera.*f.value;
    row += std::isfinite(v) ? fmt::format(",{:.9g}", v) : std::string(",");
  }
  return row + "\n";
}

nlohmann::json samples_to_json(const std::vector<Sample>& v) {
  nlohmann::json j = nlohmann::json::array();
  for (const Sample& s : v) {
    nlohmann::json cam = nlohmann::json::array();  // kCameraFields order, null for NaN
    for (const observe::CameraField& f : observe::kCameraFields) {
      const double x = s.camera.*f.value;
      cam.push_back(std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr));
    }
    nlohmann::json iface = nlohmann::json::array();  // null for NaN
    for (double h : s.interface)
      iface.push_back(std::isfinite(h) ? nlohmann::json(h) : nlohmann::json(nullptr));
    j.push_back({s.step, s.time, s.aor_signed_deg, s.com_x, s.com_y, s.flagged, s.contacts, s.bridges,
                 s.f_wet, s.kinetic_energy, s.liquid_films, s.liquid_bridges, s.liquid_pores,
                 s.liquid_evaporated, s.liquid_unit_m3, cam, iface});
  }
  return j;
}

std::vector<Sample> samples_from_json(const nlohmann::json& j) {
  std::vector<Sample> v;
  for (const auto& e : j) {
    Sample s;
    s.step = e.at(0).get<uint64_t>();
    s.time = e.at(1).get<double>();
    s.aor_signed_deg = e.at(2).get<double>();
    s.com_x = e.at(3).get<double>();
    s.com_y = e.at(4).get<double>();
    s.flagged = e.at(5).get<bool>();
    s.contacts = e.at(6).get<uint64_t>();
    s.bridges = e.at(7).get<uint64_t>();
    s.f_wet = e.at(8).get<double>();
    s.kinetic_energy = e.at(9).get<double>();
    if (e.size() >= 15) {
      s.liquid_films = e.at(10).get<int64_t>();
      s.liquid_bridges = e.at(11).get<int64_t>();
      s.liquid_pores = e.at(12).get<int64_t>();
      s.liquid_evaporated = e.at(13).get<int64_t>();
      s.liquid_unit_m3 = e.at(14).get<double>();
    }
    if (e.size() >= 16) {  // checkpoints written before the camera observables have none
      const nlohmann::json& cam = e.at(15);
      size_t i = 0;
      for (const observe::CameraField& f : observe::kCameraFields) {
        if (i < cam.size() && cam[i].is_number()) s.camera.*f.value = cam[i].get<double>();
        ++i;
      }
    }
    if (e.size() >= 17)  // checkpoints written before the interface profile have none
      for (const auto& h : e.at(16)) s.interface.push_back(h.is_number() ? h.get<double>() : std::nan(""));
    v.push_back(s);
  }
  return v;
}

namespace {

struct Fnv {
  uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
};

// Mean of f over the samples of the steady window.
template <class F>
double window_mean(const std::vector<Sample>& s, double t_from, F f) {
  double sum = 0;
  size_t n = 0;
  for (const Sample& x : s)
    if (x.time >= t_from) sum += f(x), ++n;
  return n ? sum / double(n) : std::nan("");
}

// diagnosis.md §2: each camera observable as <name> (window mean of the samples that have a value) and
// <name>_sem (the correlation-aware error of window_stats, as aor_sem_tau); null when no sample of the window
// has one (the error bar: fewer than two); the plate and centre slab angles are absent on a periodic slice.
// The AoR drift over the window, per revolution. Issue 21: the window rules of window_rules.h decide what may
// be quoted; a mean whose window fails them keeps its value and is listed in `not_quotable` with the reason,
// the drift is not reported at all (null, aor_drift_reason) when the window cannot carry it.
void add_camera_observables(nlohmann::json& j, nlohmann::json& not_quotable, const Case& c,
                            const std::vector<Sample>& samples, double t_from, bool aor_flag,
                            size_t particles, double n_eff) {
  for (const observe::CameraField& f : observe::kCameraFields) {
    if (f.needs_plates && c.drum.periodic_slice) continue;
    std::vector<double> v;
    for (const Sample& s : samples)
      if (s.time >= t_from) v.push_back(s.camera.*f.value);
    const WindowStats w = window_stats_finite(v, c.run.sample_interval);
    j[f.name] = w.n ? number_or_null(w.mean) : nlohmann::json(nullptr);
    j[std::string(f.name) + "_sem"] = w.n >= 2 ? number_or_null(w.sem) : nlohmann::json(nullptr);
    const std::string why = mean_rule_reason(w);
    if (!why.empty() && w.n) not_quotable[f.name] = "window not stationary: " + why;
  }
  // A bridge network that spans the bed is not an agglomerate (window_rules.h).
  const double agg = j.value("agglomerate_size_mean", nlohmann::json(nullptr)).is_number()
                         ? j["agglomerate_size_mean"].get<double>()
                         : std::nan("");
  const bool spans = network_spans_bed(agg, particles);
  j["bridge_network_spans_bed"] = spans;
  j["bridge_network_bed_fraction"] =
      particles ? number_or_null(agg / double(particles)) : nlohmann::json(nullptr);
  if (spans) {
    const std::string why = fmt::format(
        "the bridge network spans the bed (the mass-weighted mean cluster holds {:.0f} % of the particles): "
        "one percolating network, not agglomerates",
        100.0 * agg / double(particles));
    not_quotable["agglomerate_size_mean"] = why;
    if (j.contains("drum_to_agglomerate_ratio")) not_quotable["drum_to_agglomerate_ratio"] = why;
  }
  std::vector<double> t, a;
  for (const Sample& s : samples)
    if (s.time >= t_from && !s.flagged) t.push_back(s.time), a.push_back(std::fabs(s.aor_signed_deg));
  const observe::Drift d = observe::aor_drift(t, a, c.drum.omega);
  const std::string why = aor_flag ? std::string("AoR flagged")
                                   : drift_rule_reason(t, a, c.run.duration - c.run.steady_state_start,
                                                       c.drum.omega, c.run.sample_interval);
  const bool report = why.empty();
  j["aor_drift_deg_per_rev"] = report ? number_or_null(d.slope_deg_per_rev) : nlohmann::json(nullptr);
  j["aor_drift_deg_per_rev_sem"] = report ? number_or_null(d.se_deg_per_rev) : nlohmann::json(nullptr);
  j["aor_drift_reason"] = why;
  j["aor_window_revolutions"] = window_revolutions(c.run.duration - c.run.steady_state_start, c.drum.omega);
  // The cohesive index of rotating-drum testers: the interface's fluctuation over the window
  // (app/observe/interface.h). Its error as that of a standard deviation from n_eff independent samples,
  // σ/√(2 n_eff), with the AoR's n_eff: the interface moves with the same avalanches.
  std::vector<std::vector<double>> profiles;
  for (const Sample& s : samples)
    if (s.time >= t_from && !s.interface.empty()) profiles.push_back(s.interface);
  const double ci = observe::interface_fluctuation(profiles);
  j["cohesive_index_m"] = aor_flag ? nlohmann::json(nullptr) : number_or_null(ci);
  j["cohesive_index_m_sem"] =
      aor_flag || !(n_eff > 0) ? nlohmann::json(nullptr) : number_or_null(ci / std::sqrt(2.0 * n_eff));
}

}  // namespace

std::string state_hash(const SystemState& s) {
  Fnv f;
  const ParticleArrays& p = s.p;
  f.vec(p.x), f.vec(p.v), f.vec(p.w), f.vec(p.f), f.vec(p.t), f.vec(p.radius), f.vec(p.mass),
      f.vec(p.inertia);
  f.vec(p.film);
  f.vec(p.pore), f.vec(p.evaporated);
  for (const WallRecord& w : p.wall)
    f.bytes(&w.spring_t, sizeof(w.spring_t)), f.bytes(&w.spring_r, sizeof(w.spring_r)),
        f.bytes(&w.bridge, sizeof(w.bridge)), f.bytes(&w.flags, sizeof(w.flags));
  for (const PairRecord& r : s.pairs) {
    f.bytes(&r.id_i, sizeof(r.id_i)), f.bytes(&r.id_j, sizeof(r.id_j));
    f.bytes(&r.spring_t, sizeof(r.spring_t)), f.bytes(&r.spring_r, sizeof(r.spring_r));
    f.bytes(&r.bridge, sizeof(r.bridge)), f.bytes(&r.flags, sizeof(r.flags));
  }
  f.bytes(&s.time, sizeof(s.time));
  f.bytes(&s.step, sizeof(s.step));
  return fmt::format("{:016x}", f.h);
}

nlohmann::json make_summary(const Case& c, const Derived& d, const std::vector<Sample>& samples,
                            const RunTotals& t) {
  using nlohmann::json;
  const double t_from = c.run.settle + c.run.steady_state_start;
  std::vector<double> times;
  std::vector<AorSample> aor;
  for (const Sample& s : samples) {
    times.push_back(s.time);
    AorSample a;
    a.signed_deg = s.aor_signed_deg;
    a.abs_deg = std::fabs(s.aor_signed_deg);
    a.com = {s.com_x, s.com_y};
    a.com_radius = std::hypot(s.com_x, s.com_y);
    a.flagged = s.flagged;
    aor.push_back(a);
  }
  const AorSummary as = summarize_aor(times, aor, t_from);
  // drum.md: empty or near-centred beds are flagged, not reported. The run's AoR is flagged when no sample of
  // the window, or fewer than half of them, has a meaningful angle.
  const size_t good = as.samples - as.flagged;
  const bool flag = good == 0 || 2 * as.flagged > as.samples;

  json j;
  j["aor_deg_mean"] = flag ? json(nullptr) : number_or_null(as.abs_deg.mean);
  j["aor_deg_std"] = flag ? json(nullptr) : number_or_null(as.abs_deg.stddev);
  j["aor_sem_block"] = flag ? json(nullptr) : number_or_null(as.abs_deg.sem);
  // Issue 12: the window must span >= 10 integrated autocorrelation times and its halves must agree
  // (timeseries_stats.h); the blocked SEM must also find its plateau (aor.h). Both verdicts carry a reason.
  std::vector<double> abs_window;
  for (size_t i = 0; i < samples.size(); ++i)
    if (times[i] >= t_from && !aor[i].flagged) abs_window.push_back(aor[i].abs_deg);
  const WindowStats ws = window_stats(abs_window, c.run.sample_interval);
  std::string stat_reason = ws.stationary_reason, sem_reason = ws.sem_reliable_reason;
  if (stat_reason.empty() && !as.abs_deg.stationary)
    stat_reason = fmt::format("the halves of the window differ by {:.2f} blocked standard errors (|z| >= 3)",
                              as.abs_deg.drift_z);
  if (sem_reason.empty() && !stat_reason.empty()) sem_reason = "not stationary: " + stat_reason;
  if (sem_reason.empty() && !as.abs_deg.sem_reliable)
    sem_reason = "the blocked standard error found no plateau (window short for its correlation time)";
  j["aor_sem_reliable"] = !flag && sem_reason.empty();
  j["aor_sem_reliable_reason"] = flag ? std::string("AoR flagged") : sem_reason;
  j["aor_stationary"] = !flag && stat_reason.empty();
  j["aor_stationary_reason"] = flag ? std::string("AoR flagged") : stat_reason;
  j["aor_drift_z"] = number_or_null(as.abs_deg.drift_z);
  j["aor_tau_int_s"] = number_or_null(ws.tau_int_s);
  j["aor_n_eff"] = number_or_null(ws.n_eff);
  // The error of the standard deviation (the paper's cohesion indicator): σ/√(2 n_eff) for n_eff
  // independent samples.
  j["aor_deg_std_sem"] =
      flag || !(ws.n_eff > 0) ? json(nullptr) : number_or_null(as.abs_deg.stddev / std::sqrt(2.0 * ws.n_eff));
  j["aor_sem_tau"] = flag ? json(nullptr) : number_or_null(ws.sem);
  j["aor_signed_deg_mean"] = flag ? json(nullptr) : number_or_null(as.signed_deg.mean);
  j["aor_window_s"] = {t_from, c.run.settle + c.run.duration};
  j["aor_window_length_s"] = c.run.duration - c.run.steady_state_start;
  j["aor_samples"] = good;
  j["aor_flagged_samples"] = as.flagged;
  j["aor_flag"] = flag;
  j["aor_definition"] =
      "|atan2(com_x, -com_y)|: angle between the downward vertical and the line from the drum axis to the "
      "bed's centre of mass, in the plane normal to the axis; samples with |COM| < 0.2 R are flagged and "
      "excluded";
  nlohmann::json not_quotable = nlohmann::json::object();  // issue 21: window quantities that fail their rule
  if (!j["aor_stationary"].get<bool>())
    not_quotable["aor_deg_mean"] = "window not stationary: " + j["aor_stationary_reason"].get<std::string>();
  j["f_wet_mean"] = number_or_null(window_mean(samples, t_from, [](const Sample& s) { return s.f_wet; }));
  {  // f_wet's window statistics, as the AoR's: its error bar and whether its window is stationary
    std::vector<double> fw;
    for (const Sample& s : samples)
      if (s.time >= t_from) fw.push_back(s.f_wet);
    const WindowStats w = window_stats(fw, c.run.sample_interval);
    const std::string why = mean_rule_reason(w);
    j["f_wet_sem"] = w.n >= 2 ? number_or_null(w.sem) : json(nullptr);
    j["f_wet_stationary"] = why.empty();
    j["f_wet_stationary_reason"] = why;
    if (!why.empty() && w.n) not_quotable["f_wet_mean"] = "window not stationary: " + why;
  }
  j["f_wet_definition"] = kFwetDefinition;
  j["bridges_mean"] =
      number_or_null(window_mean(samples, t_from, [](const Sample& s) { return double(s.bridges); }));
  j["contacts_mean"] =
      number_or_null(window_mean(samples, t_from, [](const Sample& s) { return double(s.contacts); }));
  j["kinetic_energy_mean_J"] =
      number_or_null(window_mean(samples, t_from, [](const Sample& s) { return s.kinetic_energy; }));
  add_camera_observables(j, not_quotable, c, samples, t_from, flag, t.particles, ws.n_eff);
  j["not_quotable"] = not_quotable;
  j["particles"] = t.particles;
  j["steps"] = t.steps;
  j["dt_s"] = t.dt;
  j["simulated_time_s"] = double(t.steps) * t.dt;
  j["liquid_total_units_start"] = t.liquid_start;
  j["liquid_total_units_end"] = t.liquid_end;
  j["liquid_total_m3_start"] = double(t.liquid_start) * t.liquid_unit_m3;
  j["liquid_total_m3_end"] = double(t.liquid_end) * t.liquid_unit_m3;
  j["liquid_conserved"] = t.liquid_start == t.liquid_end;  // exact: liquid is integer units (physics.md §5)
  {
    const LiquidBudget& b = t.liquid_budget_end;
    const double u = t.liquid_unit_m3;
    j["liquid_end"] = {{"films_units", b.films},          {"bridges_units", b.bridges},
                       {"pores_units", b.pores},          {"evaporated_units", b.evaporated},
                       {"films_m3", double(b.films) * u}, {"bridges_m3", double(b.bridges) * u},
                       {"pores_m3", double(b.pores) * u}, {"evaporated_m3", double(b.evaporated) * u}};
    j["liquid_conserved_definition"] =
        "films + bridges (pair and wall) + pores + evaporated at the end == liquid put in at the start, "
        "exactly (integer units of liquid_unit_m3)";
  }
  j["particle_steps_per_s"] = t.particle_steps_per_s;
  j["wall_time_s"] = t.wall_s;
  j["resumed_from_step"] = t.resumed_from_step;
  j["device"] = t.device;
  j["neighbour_list"] = {{"rebuilds", t.counters.rebuilds},
                         {"regrows", t.counters.regrows},
                         {"entry_capacity", t.counters.entry_capacity},
                         {"lost_bridges", t.counters.lost_bridges},
                         {"escaped", t.counters.escaped}};
  j["seed"] = c.run.seed;
  const PsdQuantiles q = sample_quantiles(t.inserted_diameters, PsdBasis::kVolume);
  j["inserted_psd_volume_basis_m"] = {
      {"d10", q.d10}, {"d25", q.d25}, {"d50", q.d50}, {"d75", q.d75}, {"d90", q.d90}};
  j["final_state_hash"] = t.final_state_hash;
  j["code_version"] = code_version();
  // The run version in the run's store hash (study/study_file.h): `wetdem study prune` tells a run this
  // binary would reuse from one it never will.
  j["run_version"] = run_version();
  j["case"] = case_to_json(c);
  j["case_source"] = c.source;
  j["derived"] = derived_to_json(d);
  j["notes"] = c.notes;
  return j;
}

std::string aor_log_line(const nlohmann::json& s) {
  if (s.at("aor_flag").get<bool>()) return "AoR: flagged (bed near the drum centre: no angle reported)";
  const auto& w = s.at("aor_window_s");
  std::string line = fmt::format(
      "AoR = {:.2f}° ± {:.2f}° (sd {:.2f}°, {} samples over {:.4g}-{:.4g} s, tau_int {:.3g} s, n_eff {:.1f})",
      s.at("aor_deg_mean").get<double>(), s.at("aor_sem_block").get<double>(),
      s.at("aor_deg_std").get<double>(), s.at("aor_samples").get<size_t>(), w.at(0).get<double>(),
      w.at(1).get<double>(), s.value("aor_tau_int_s", 0.0), s.value("aor_n_eff", 0.0));
  if (!s.at("aor_stationary").get<bool>())
    line += "; NOT STATIONARY, do not quote: " + s.at("aor_stationary_reason").get<std::string>();
  else if (!s.at("aor_sem_reliable").get<bool>())
    line += "; error bar NOT RELIABLE: " + s.at("aor_sem_reliable_reason").get<std::string>();
  return line;
}

std::vector<std::string> result_lines(const nlohmann::json& s) {
  std::vector<std::string> out;
  const auto& w = s.at("aor_window_s");
  const double rev = s.value("aor_window_revolutions", std::nan(""));
  out.push_back(fmt::format("result over the window {:.4g}-{:.4g} s ({:.2g} revolutions):",
                            w.at(0).get<double>(), w.at(1).get<double>(), rev));
  if (s.at("aor_flag").get<bool>()) {
    out.push_back("  dynamic AoR: flagged (bed near the drum centre: no angle reported)");
  } else {
    std::string verdict;
    if (!s.at("aor_stationary").get<bool>())
      verdict = "NOT STATIONARY, do not quote: " + s.at("aor_stationary_reason").get<std::string>();
    else if (!s.at("aor_sem_reliable").get<bool>())
      verdict = "stationary; error bar NOT RELIABLE: " + s.at("aor_sem_reliable_reason").get<std::string>();
    else
      verdict = fmt::format("stationary, n_eff {:.0f}", s.value("aor_n_eff", 0.0));
    out.push_back(fmt::format("  dynamic AoR  {:.2f}° ± {:.2f}°  ({}; sd {:.2f}° over {} samples)",
                              s.at("aor_deg_mean").get<double>(), s.at("aor_sem_block").get<double>(),
                              verdict, s.at("aor_deg_std").get<double>(), s.at("aor_samples").get<size_t>()));
  }
  if (s.at("f_wet_mean").is_number()) {
    const bool st = s.value("f_wet_stationary", false);
    const double sem = s.value("f_wet_sem", nlohmann::json(nullptr)).is_number()
                           ? s["f_wet_sem"].get<double>()
                           : std::nan("");
    out.push_back(
        fmt::format("  f_wet        {:.3f} ± {:.3f}  ({})", s["f_wet_mean"].get<double>(), sem,
                    st ? std::string("stationary")
                       : "NOT STATIONARY, do not quote: " + s.value("f_wet_stationary_reason", "")));
  }
  if (s.value("aor_drift_deg_per_rev", nlohmann::json(nullptr)).is_number())
    out.push_back(fmt::format("  AoR drift    {:.2f} ± {:.2f} °/rev",
                              s["aor_drift_deg_per_rev"].get<double>(),
                              s.value("aor_drift_deg_per_rev_sem", 0.0)));
  else if (!s.value("aor_drift_reason", "").empty())
    out.push_back("  AoR drift    not reported: " + s["aor_drift_reason"].get<std::string>());
  if (s.value("bridge_network_spans_bed", false))
    out.push_back(fmt::format(
        "  bridges      the bridge network spans the bed ({:.0f} % of the particles in the mean cluster): "
        "no agglomerate size",
        100.0 * s.value("bridge_network_bed_fraction", 0.0)));
  else if (s.value("agglomerate_size_mean", nlohmann::json(nullptr)).is_number())
    out.push_back(fmt::format("  agglomerates {:.3g} particles (mass-weighted mean bridge cluster)",
                              s["agglomerate_size_mean"].get<double>()));
  std::vector<std::string> other;
  const nlohmann::json not_quotable =
      s.value("not_quotable", nlohmann::json::object());  // kept: items() refers to it
  for (const auto& [k, v] : not_quotable.items())
    if (k != "aor_deg_mean" && k != "f_wet_mean" && k != "agglomerate_size_mean" &&
        k != "drum_to_agglomerate_ratio")
      other.push_back(k);
  if (!other.empty()) {
    std::string l = "  not quotable in this window (summary.json not_quotable):";
    for (const std::string& k : other) l += " " + k;
    out.push_back(l);
  }
  return out;
}

nlohmann::json number_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

}  // namespace wetdem::app
