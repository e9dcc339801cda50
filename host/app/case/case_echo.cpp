// The resolved case written back in SI keys: the run log, `wetdem check` and summary.json show exactly what
// ran, and the TOML form parses back to the same Case.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/case/case.h"

namespace wetdem::app {

namespace {

toml::table wall_table(const WallSpec& w) {
  return toml::table{{"mu_s", w.mu_s}, {"mu_r", w.mu_r}, {"liquid_bridges", w.liquid_bridges}};
}

toml::table to_table(const Case& c) {
  toml::table root;
  if (!c.name.empty()) root.insert("name", c.name);
  if (!c.description.empty()) root.insert("description", c.description);
  root.insert("scaling", c.scaling);

  const MaterialSpec& m = c.material;
  toml::table mat;
  switch (m.input) {
    case MaterialInput::EG:
      mat.insert("E_Pa", m.E), mat.insert("G_Pa", m.G);
      break;
    case MaterialInput::ENu:
      mat.insert("E_Pa", m.E), mat.insert("nu", m.nu);
      break;
    case MaterialInput::GNu:
      mat.insert("G_Pa", m.G), mat.insert("nu", m.nu);
      break;
    case MaterialInput::EStarGStar:
      mat.insert("E_star_Pa", m.E_star), mat.insert("G_star_Pa", m.G_star);
      break;
  }
  mat.insert("restitution", m.restitution);
  mat.insert("density_kg_per_m3", m.density);
  mat.insert("stiffness_reduction", m.stiffness_reduction);
  root.insert("material", std::move(mat));
  root.insert("friction", toml::table{{"mu_s", c.mu_s}, {"mu_r", c.mu_r}});
  toml::table walls{{"cylinder", wall_table(c.cylinder)}};
  if (!c.drum.periodic_slice) walls.insert("plates", wall_table(c.plates));
  root.insert("walls", std::move(walls));

  const wetdem::PsdSpec& p = c.psd;
  toml::table psd{{"basis", to_string(p.basis)},
                  {"tails", to_string(p.tails)},
                  {"tail_lo", p.tail_lo},
                  {"tail_hi", p.tail_hi}};
  // Only when not the default, so that the resolved case (and run hash) of every random-sampled case is what
  // it was before the key existed.
  if (p.sampling != wetdem::PsdSampling::kRandom) psd.insert("sampling", to_string(p.sampling));
  if (p.kind == wetdem::PsdSpec::Kind::kLogNormal) {
    psd.insert("lognormal", toml::table{{"median_m", p.median}, {"sigma", p.sigma}});
  } else {
    for (const PsdPoint& pt : p.table) {
      const int pct = int(pt.fraction * 100.0 + 0.5);
      psd.insert("d" + std::to_string(pct) + "_m", pt.diameter);
    }
  }
  root.insert("psd", std::move(psd));

  const LiquidSpec& l = c.liquid;
  if (l.present) {
    toml::table liq{{"content", l.content},
                    {"gamma_N_per_m", l.gamma},
                    {"theta_rad", l.theta},
                    {"v_min", l.v_min},
                    {"v_max", l.v_max},
                    {"d_c", l.d_c},
                    {"films", l.films == FilmMode::MeanVolume ? "mean_volume" : "per_particle_volume"}};
    // Candidate effects: viscous (cut-off only when given: its default follows the particles, see the
    // derived lubrication_cutoff_m) and hysteresis (theta_r resolved: theta when not given).
    liq.insert("viscosity_Pa_s", l.viscosity);
    if (l.lubrication_cutoff) liq.insert("lubrication_cutoff_m", *l.lubrication_cutoff);
    liq.insert("theta_receding_rad", l.theta_receding.value_or(l.theta));
    liq.insert("evaporation_time_s", l.evaporation_time);
    liq.insert("wetted_fraction", l.wetted_fraction);
    root.insert("liquid", std::move(liq));
  }
  root.insert("cohesion", toml::table{{"surface_energy_J_per_m2", c.cohesion.surface_energy}});
  {
    const AbsorptionSpec& a = c.absorption;
    toml::table ab{{"capacity", a.capacity}};
    if (std::isinf(a.rate))
      ab.insert("rate", "instantaneous");
    else
      ab.insert("rate_per_s", a.rate);
    root.insert("absorption", std::move(ab));
  }

  const DrumSpec& d = c.drum;
  toml::table drum{{"diameter_m", d.diameter},
                   {"rotation_rad_per_s", d.omega},
                   {"fill", d.fill},
                   {"bed_solid_fraction", d.bed_solid_fraction},
                   {"periodic_slice", d.periodic_slice}};
  if (d.length > 0) drum.insert("length_m", d.length);
  if (d.periodic_slice)
    drum.insert("slice_thickness_m", d.slice_thickness);
  else
    drum.insert("end_plates", d.plates_rotate ? "rotating" : "fixed");
  root.insert("drum", std::move(drum));

  const RunSpec& r = c.run;
  toml::table run{{"settle_s", r.settle},
                  {"duration_s", r.duration},
                  {"steady_state_start_s", r.steady_state_start},
                  {"sample_interval_s", r.sample_interval},
                  {"seed", int64_t(r.seed)},
                  {"steps_per_submit", int64_t(r.steps_per_submit)}};
  if (r.dt)
    run.insert("dt_s", *r.dt);
  else
    run.insert("dt_rayleigh_fraction", r.dt_rayleigh_fraction);
  if (r.skin) run.insert("skin_m", *r.skin);
  if (r.perturb > 0) {
    run.insert("perturb_m", r.perturb);
    run.insert("perturb_seed", int64_t(r.perturb_seed));
  }
  root.insert("run", std::move(run));

  toml::array formats;
  for (const std::string& f : c.output.formats) formats.push_back(f);
  root.insert("output", toml::table{{"snapshot_interval_s", c.output.snapshot_interval},
                                    {"formats", std::move(formats)},
                                    {"checkpoint_interval", int64_t(c.output.checkpoint_interval)}});
  return root;
}

nlohmann::json to_json(const toml::node& n) {
  if (const auto* t = n.as_table()) {
    nlohmann::json j = nlohmann::json::object();
    for (auto&& [k, v] : *t) j[std::string(k.str())] = to_json(v);
    return j;
  }
  if (const auto* a = n.as_array()) {
    nlohmann::json j = nlohmann::json::array();
    for (const toml::node& e : *a) j.push_back(to_json(e));
    return j;
  }
  if (const auto* s = n.as_string()) return s->get();
  if (const auto* i = n.as_integer()) return i->get();
  if (const auto* f = n.as_floating_point()) return f->get();
  if (const auto* b = n.as_boolean()) return b->get();
  return nullptr;
}

// A value as TOML: numbers in their shortest exact form ("0.14", not "0.14000000000000001").
std::string value_text(const toml::node& n) {
  if (const auto* f = n.as_floating_point()) {
    std::string t = fmt::format("{}", f->get());
    if (t.find_first_of(".eEn") == std::string::npos) t += ".0";  // stay a float (inf/nan contain 'n')
    return t;
  }
  if (const auto* a = n.as_array()) {
    std::string t = "[";
    for (const toml::node& e : *a) t += (t.size() > 1 ? ", " : "") + value_text(e);
    return t + "]";
  }
  std::ostringstream os;
  n.visit([&](const auto& v) { os << v; });
  return os.str();
}

// Scalars of a table first, then its sub-tables as [a.b] sections.
void emit(std::ostringstream& os, const toml::table& t, const std::string& path) {
  bool any = false;
  for (auto&& [k, v] : t)
    if (!v.is_table()) {
      if (!any && !path.empty()) os << "\n[" << path << "]\n";
      any = true;
      os << k.str() << " = " << value_text(v) << '\n';
    }
  for (auto&& [k, v] : t)
    if (const auto* sub = v.as_table())
      emit(os, *sub, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str()));
}

}  // namespace

std::string case_to_toml(const Case& c) {
  std::ostringstream os;
  emit(os, to_table(c), "");
  return os.str();
}

nlohmann::json case_to_json(const Case& c) {
  return to_json(to_table(c));
}

}  // namespace wetdem::app
