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
#include "wetdem/observables.h"

#ifndef WETDEM_VERSION
#define WETDEM_VERSION "unknown"
#endif
#ifndef WETDEM_GIT
#define WETDEM_GIT "unknown"
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
  return "time,aor_deg,com_x,com_y,contacts,bridges,f_wet,kinetic_energy,"
         "liquid_films_units,liquid_bridges_units,liquid_pores_units,liquid_evaporated_units,"
         "liquid_films_m3,liquid_bridges_m3,liquid_pores_m3,liquid_evaporated_m3\n";
}

std::string timeseries_row(const Sample& s) {
  // aor_deg is |angle|, empty when the bed is flagged (near-centred: no angle reported, drum.md).
  const std::string aor = s.flagged ? "" : fmt::format("{:.9g}", std::fabs(s.aor_signed_deg));
  const double u = s.liquid_unit_m3;
  return fmt::format("{:.9g},{},{:.9g},{:.9g},{},{},{:.9g},{:.9g},{},{},{},{},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                     s.time, aor, s.com_x, s.com_y, s.contacts, s.bridges, s.f_wet, s.kinetic_energy,
                     s.liquid_films, s.liquid_bridges, s.liquid_pores, s.liquid_evaporated,
                     double(s.liquid_films) * u, double(s.liquid_bridges) * u, double(s.liquid_pores) * u,
                     double(s.liquid_evaporated) * u);
}

nlohmann::json samples_to_json(const std::vector<Sample>& v) {
  nlohmann::json j = nlohmann::json::array();
  for (const Sample& s : v)
    j.push_back({s.step, s.time, s.aor_signed_deg, s.com_x, s.com_y, s.flagged, s.contacts, s.bridges,
                 s.f_wet, s.kinetic_energy, s.liquid_films, s.liquid_bridges, s.liquid_pores,
                 s.liquid_evaporated, s.liquid_unit_m3});
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

nlohmann::json number_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
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
  j["aor_sem_reliable"] = as.abs_deg.sem_reliable;
  j["aor_stationary"] = as.abs_deg.stationary;
  j["aor_drift_z"] = number_or_null(as.abs_deg.drift_z);
  j["aor_signed_deg_mean"] = flag ? json(nullptr) : number_or_null(as.signed_deg.mean);
  j["aor_window_s"] = {t_from, c.run.settle + c.run.duration};
  j["aor_window_length_s"] = c.run.duration - c.run.steady_state_start;
  j["aor_samples"] = good;
  j["aor_flagged_samples"] = as.flagged;
  j["aor_flag"] = flag;
  j["aor_definition"] =
      "|atan2(com_x, -com_y)|: angle between the downward vertical and the line from the drum axis to the "
      "bed's "
      "centre of mass, in the plane normal to the axis; samples with |COM| < 0.2 R are flagged and excluded";
  j["f_wet_mean"] = number_or_null(window_mean(samples, t_from, [](const Sample& s) { return s.f_wet; }));
  j["f_wet_definition"] = kFwetDefinition;
  j["bridges_mean"] =
      number_or_null(window_mean(samples, t_from, [](const Sample& s) { return double(s.bridges); }));
  j["contacts_mean"] =
      number_or_null(window_mean(samples, t_from, [](const Sample& s) { return double(s.contacts); }));
  j["kinetic_energy_mean_J"] =
      number_or_null(window_mean(samples, t_from, [](const Sample& s) { return s.kinetic_energy; }));
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
        "exactly "
        "(integer units of liquid_unit_m3)";
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
  j["code_version"] = std::string(WETDEM_VERSION) + "+" + WETDEM_GIT;
  j["case"] = case_to_json(c);
  j["case_source"] = c.source;
  j["derived"] = derived_to_json(d);
  j["notes"] = c.notes;
  return j;
}

}  // namespace wetdem::app
