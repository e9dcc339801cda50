// Case-file parsing and validation. Every check runs here, before any particle is made or any file written.
#include "app/case/case.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "app/case/case_reader.h"

namespace wetdem::app {

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------------------
// --set overrides

// The key without its unit suffix (gamma_N_per_m -> gamma), or the key itself. Longest suffix wins.
std::string base_of(const std::string& k) {
  size_t best = 0;
  for (Dim d : {Dim::Fraction, Dim::Length, Dim::Pressure, Dim::SurfaceTension, Dim::Angle, Dim::Time,
                Dim::AngularRate, Dim::Density, Dim::Viscosity, Dim::SurfaceEnergy})
    for (const KeyUnit& u : key_units(d)) {
      const std::string tail = "_" + u.suffix;
      if (k.size() > tail.size() && k.compare(k.size() - tail.size(), tail.size(), tail) == 0)
        best = std::max(best, tail.size());
    }
  return k.substr(0, k.size() - best);
}

// `rpm` is the short spelling of drum.rotation_rpm: compare keys in that form.
std::string canonical_key(const std::string& k) {
  return k == "rpm" ? "rotation_rpm" : k;
}

// True when a and b are two spellings of one quantity (x, x_m, x_mm, ...), so that an override of one
// replaces the other instead of making the case give it twice.
bool same_quantity(const std::string& a0, const std::string& b0) {
  const std::string a = canonical_key(a0), b = canonical_key(b0);
  return a == b || base_of(a) == b || a == base_of(b) || (base_of(a) == base_of(b) && base_of(a) != a);
}

void apply_override(toml::table& root, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw CaseError("", "--set expects key=value, got \"" + assignment + "\"");
  auto trim = [](std::string s) {
    const char* ws = " \t";
    s.erase(0, s.find_first_not_of(ws));
    s.erase(s.find_last_not_of(ws) + 1);
    return s;
  };
  const std::string path = trim(assignment.substr(0, eq));
  const std::string text = trim(assignment.substr(eq + 1));
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');) {
    if (p.empty()) throw CaseError(path, "--set: empty segment in key");
    parts.push_back(p);
  }
  // The value is TOML ("0.3", "\"140 mm\"", "true", "[\"vtk\"]"); anything else is taken as a plain string,
  // so that `--set drum.diameter=140mm` works without shell quoting.
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    parsed = toml::table{};
    parsed.insert("v", text);
  }
  toml::table* t = &root;
  std::string sofar;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    sofar += (sofar.empty() ? "" : ".") + parts[i];
    toml::node* n = t->get(parts[i]);
    if (!n) n = &t->insert(parts[i], toml::table{}).first->second;
    if (!n->is_table()) throw CaseError(sofar, "is not a table, cannot --set " + path);
    t = n->as_table();
  }
  const std::string& leaf = parts.back();
  std::vector<std::string> drop;
  for (auto&& [k, node] : *t)
    if (std::string(k.str()) != leaf && same_quantity(std::string(k.str()), leaf)) drop.emplace_back(k.str());
  for (const std::string& k : drop) t->erase(k);
  t->insert_or_assign(leaf, std::move(*parsed.get("v")));
}

// ---------------------------------------------------------------------------------------------------------
// Sections

void read_material(Section s, Case& c) {
  if (!s.present()) throw CaseError("material", "required table is missing");
  MaterialSpec& m = c.material;
  std::optional<Q> E = s.quantity("E", Dim::Pressure), G = s.quantity("G", Dim::Pressure);
  std::optional<Q> nu = s.quantity("nu", Dim::Dimensionless);
  std::optional<Q> Es = s.quantity("E_star", Dim::Pressure), Gs = s.quantity("G_star", Dim::Pressure);
  for (const auto* q : {&E, &G, &Es, &Gs})
    if (*q) require_positive(**q);
  std::vector<const Q*> present;
  for (const auto* q : {&E, &G, &nu, &Es, &Gs})
    if (*q) present.push_back(&**q);
  const std::string pairs = "give exactly one pair: (E, G), (E, nu), (G, nu) or (E_star, G_star)";
  if (present.size() > 2) throw CaseError(present[2]->key, "one modulus too many; " + pairs);
  if (present.size() < 2)
    throw CaseError(present.empty() ? s.key("E") : present[0]->key, "needs a partner; " + pairs);
  if (bool(Es) != bool(Gs)) throw CaseError((Es ? Es : Gs)->key, "E_star and G_star go together; " + pairs);
  if (Es) {
    m.input = MaterialInput::EStarGStar;
    m.E_star = Es->v;
    m.G_star = Gs->v;
    // E* = G/(1 - nu), G* = G/(2(2 - nu)) (single material, E = 2G(1 + nu)) => nu = (4 - r)/(2 - r), r =
    // E*/G*.
    const double r = m.E_star / m.G_star;
    if (!(r > 3.0)) fail(*Gs, fmt::format("E_star/G_star = {:.4g} must be > 3 (that is nu in (-1, 1))", r));
    m.nu = (4.0 - r) / (2.0 - r);
    m.G = m.E_star * (1.0 - m.nu);
    m.E = 2.0 * m.G * (1.0 + m.nu);
  } else {
    if (E && G)
      m.input = MaterialInput::EG, m.E = E->v, m.G = G->v, m.nu = m.E / (2.0 * m.G) - 1.0;
    else if (E && nu)
      m.input = MaterialInput::ENu, m.E = E->v, m.nu = nu->v, m.G = m.E / (2.0 * (1.0 + m.nu));
    else if (G && nu)
      m.input = MaterialInput::GNu, m.G = G->v, m.nu = nu->v, m.E = 2.0 * m.G * (1.0 + m.nu);
    else
      throw CaseError(s.key("E"), pairs);
    // E* = E/(2(1 - nu^2)) and G* = G/(2(2 - nu)) (physics.md §1) are positive only for nu in (-1, 1).
    const Q& k = nu ? *nu : *G;
    if (!(m.nu > -1.0 && m.nu < 1.0))
      fail(k, fmt::format("gives nu = {:.4g}; E* = E/(2(1 - nu^2)) needs nu in (-1, 1)", m.nu));
    m.E_star = m.E / (2.0 * (1.0 - m.nu * m.nu));
    m.G_star = m.G / (2.0 * (2.0 - m.nu));
  }
  if (m.nu < -1.0 || m.nu > 0.5)
    c.notes.push_back(fmt::format(
        "material: nu = {:.4g} lies outside the isotropic range [-1, 0.5] (E and G of the paper give 0.656); "
        "accepted as physics.md §1 says, E* and G* and the Rayleigh time use it",
        m.nu));
  Q e = s.required("restitution", Dim::Dimensionless);
  require_in(e, 0, true, 1, false, "(0, 1]");
  m.restitution = e.v;
  Q rho = s.required("density", Dim::Density);
  require_positive(rho);
  m.density = rho.v;
  if (auto k = s.quantity("stiffness_reduction", Dim::Dimensionless)) {
    if (!(k->v >= 1.0)) fail(*k, "must be >= 1 (moduli are divided by it)");
    m.stiffness_reduction = k->v;
  }
  s.finish();
}

void read_friction(Section s, Case& c) {
  if (!s.present()) throw CaseError("friction", "required table is missing");
  Q ms = s.required("mu_s", Dim::Dimensionless), mr = s.required("mu_r", Dim::Dimensionless);
  require_nonnegative(ms);
  require_nonnegative(mr);
  c.mu_s = ms.v;
  c.mu_r = mr.v;
  s.finish();
}

void read_wall(Section s, WallSpec& w, const Case& c) {
  w.mu_s = c.mu_s;
  w.mu_r = c.mu_r;
  if (auto q = s.quantity("mu_s", Dim::Dimensionless)) require_nonnegative(*q), w.mu_s = q->v;
  if (auto q = s.quantity("mu_r", Dim::Dimensionless)) require_nonnegative(*q), w.mu_r = q->v;
  if (auto b = s.boolean("liquid_bridges")) w.liquid_bridges = *b;
  s.finish();
}

void read_psd(Section s, Case& c) {
  if (!s.present()) throw CaseError("psd", "required table is missing");
  wetdem::PsdSpec& p = c.psd;
  if (auto b = s.choice("basis", {"volume", "number"})) p.basis = parse_psd_basis(*b);
  if (auto t = s.choice("tails", {"truncate", "lognormal"})) p.tails = parse_psd_tails(*t);
  if (auto m = s.choice("sampling", {"random", "stratified"})) p.sampling = parse_psd_sampling(*m);
  const toml::table* ln = s.table("lognormal");
  static const std::vector<std::pair<std::string, double>> kQuantiles = {
      {"d10", 0.10}, {"d25", 0.25}, {"d50", 0.50}, {"d75", 0.75}, {"d90", 0.90}};
  std::vector<Q> given;
  for (const auto& [name, frac] : kQuantiles)
    if (auto q = s.quantity(name, Dim::Length)) {
      require_positive(*q);
      if (!given.empty() && !(q->v > given.back().v))
        fail(*q, "must be larger than " + given.back().key + " (" + given.back().raw +
                     "): the table must increase");
      given.push_back(*q);
      p.table.push_back({frac, q->v});
    }
  if (ln) {
    if (!given.empty())
      throw CaseError(given.front().key, "give either quantiles d10..d90 or psd.lognormal, not both");
    p.kind = wetdem::PsdSpec::Kind::kLogNormal;
    Section l(ln, s.key("lognormal"));
    Q med = l.required("median", Dim::Length), sig = l.required("sigma", Dim::Dimensionless);
    require_positive(med);
    require_positive(sig);
    p.median = med.v;
    p.sigma = sig.v;
    l.finish();
  } else {
    p.kind = wetdem::PsdSpec::Kind::kTable;
    for (const auto& [name, frac] : kQuantiles)
      if ((frac == 0.10 || frac == 0.50 || frac == 0.90) &&
          std::none_of(p.table.begin(), p.table.end(),
                       [f = frac](const PsdPoint& pt) { return pt.fraction == f; }))
        throw CaseError(s.key(name),
                        "required: a quantile table needs d10, d50 and d90 (or give psd.lognormal)");
  }
  // Where "lognormal" tails are cut: quantiles of the fitted log-normal (app/psd.h), D1 and D99 by default.
  std::optional<Q> lo = s.quantity("tail_lo", Dim::Fraction), hi = s.quantity("tail_hi", Dim::Fraction);
  if (lo)
    require_in(*lo, 0, true, p.kind == wetdem::PsdSpec::Kind::kTable ? p.table.front().fraction : 0.5, true,
               "(0, first table fraction)"),
        p.tail_lo = lo->v;
  if (hi)
    require_in(*hi, p.kind == wetdem::PsdSpec::Kind::kTable ? p.table.back().fraction : 0.5, true, 1, true,
               "(last table fraction, 1)"),
        p.tail_hi = hi->v;
  s.finish();
}

void read_liquid(Section s, Case& c) {
  LiquidSpec& l = c.liquid;
  l.present = s.present();
  if (!l.present) return;
  Q content = s.required("content", Dim::Fraction);
  // Liquid is counted in units of V-bar_S 2^-40 in int64: phi_L <= 1 keeps the total below 2^63 for 4M
  // particles.
  require_in(content, 0, false, 1, false, "[0, 1] (0 to 100 vol %)");
  l.content = content.v;
  Q gamma = s.required("gamma", Dim::SurfaceTension);
  if (l.on()) require_positive(gamma);
  require_nonnegative(gamma);
  l.gamma = gamma.v;
  Q theta = s.required("theta", Dim::Angle);
  require_in(theta, 0, false, kPi / 2, true, "[0, 90) deg");
  l.theta = theta.v;
  if (auto q = s.quantity("v_min", Dim::Fraction)) require_nonnegative(*q), l.v_min = q->v;
  if (auto q = s.quantity("v_max", Dim::Fraction)) {
    if (l.on()) require_positive(*q);
    require_nonnegative(*q);
    // A bridge of V_max = V-bar_S would already be a funicular cluster; 1 (100 %) bounds the integer range
    // too.
    require_in(*q, 0, false, 1, false, "[0, 1] of the mean solid volume");
    l.v_max = q->v;
  } else if (l.on()) {
    throw CaseError(s.key("v_max"), "required when liquid.content > 0");
  }
  if (auto q = s.quantity("d_c", Dim::Dimensionless))
    require_in(*q, 0, false, 1, false, "[0, 1]"), l.d_c = q->v;
  if (auto f = s.choice("films", {"per_particle_volume", "mean_volume"}))
    l.films = *f == "mean_volume" ? FilmMode::MeanVolume : FilmMode::PerParticleVolume;
  // Candidate effects `viscous` and `hysteresis` (docs/model.md "Candidate effects").
  if (auto q = s.quantity("viscosity", Dim::Viscosity))
    require_in(*q, 0, false, 100, false, "[0, 100] Pa s (searched range 1e-4 to 1 Pa s)"), l.viscosity = q->v;
  if (auto q = s.quantity("lubrication_cutoff", Dim::Length)) {
    require_positive(*q);
    l.lubrication_cutoff = q->v;
  }
  if (auto q = s.quantity("theta_receding", Dim::Angle)) {
    require_in(*q, 0, false, kPi / 2, true, "[0, 90) deg (searched range 0 to 80 deg)");
    l.theta_receding = q->v;
  }
  if (auto q = s.quantity("evaporation_time", Dim::Time)) {
    if (q->v != 0) require_in(*q, 1, false, 1000, false, "[1, 1000] s (0 = off)");
    l.evaporation_time = q->v;
  }
  if (auto q = s.quantity("wetted_fraction", Dim::Fraction))
    require_in(*q, 0.1, false, 1, false, "[0.1, 1]"), l.wetted_fraction = q->v;
  s.finish();
}

// [absorption]: pore capacity (fraction of the particle's own volume) and rate k (1/s, or "instantaneous").
void read_absorption(Section s, Case& c) {
  AbsorptionSpec& a = c.absorption;
  if (!s.present()) return;
  if (auto q = s.quantity("capacity", Dim::Fraction))
    require_in(*q, 0, false, 0.3, false, "[0, 0.3] of the particle's own volume"), a.capacity = q->v;
  if ((*s.table_ptr())["rate"].is_string()) {
    const std::string v = *s.string("rate");
    if (v != "instantaneous")
      throw CaseError(s.key("rate"), "must be a number (1/s) or \"instantaneous\", got \"" + v + "\"");
    a.rate = std::numeric_limits<double>::infinity();
  } else if (auto q = s.quantity("rate", Dim::Dimensionless, {{"rate_per_s", 1.0}})) {
    if (q->v != 0) require_in(*q, 0.01, false, 1e9, false, "[0.01, 1e9] 1/s (0 = off), or \"instantaneous\"");
    a.rate = q->v;
  }
  if ((a.capacity > 0) != (a.rate > 0))
    c.notes.push_back("absorption: needs both capacity > 0 and rate > 0; it is off");
  s.finish();
}

void read_cohesion(Section s, Case& c) {
  if (!s.present()) return;
  if (auto q = s.quantity("surface_energy", Dim::SurfaceEnergy))
    require_in(*q, 0, false, 1, false, "[0, 1] J/m^2 (searched range 1e-4 to 0.1 J/m^2)"),
        c.cohesion.surface_energy = q->v;
  s.finish();
}

void read_drum(Section s, Case& c) {
  if (!s.present()) throw CaseError("drum", "required table is missing");
  DrumSpec& d = c.drum;
  Q dia = s.required("diameter", Dim::Length);
  require_positive(dia);
  d.diameter = dia.v;
  Q rot = s.required("rotation", Dim::AngularRate, {{"rpm", 2.0 * kPi / 60.0}});
  require_nonnegative(rot);
  d.omega = rot.v;
  Q fill = s.required("fill", Dim::Fraction);
  require_in(fill, 0, true, 1, false, "(0, 1]");
  d.fill = fill.v;
  if (auto q = s.quantity("bed_solid_fraction", Dim::Fraction)) {
    require_in(*q, 0, true, 0.7405, false, "(0, 0.74] (densest sphere packing)");
    d.bed_solid_fraction = q->v;
  }
  if (auto b = s.boolean("periodic_slice")) d.periodic_slice = *b;
  std::optional<Q> len = s.quantity("length", Dim::Length);
  if (len) require_positive(*len), d.length = len->v;
  std::optional<Q> slice = s.quantity("slice_thickness", Dim::Length);
  std::optional<std::string> plates = s.choice("end_plates", {"rotating", "fixed"});
  if (d.periodic_slice) {
    if (!slice) throw CaseError(s.key("slice_thickness"), "required when drum.periodic_slice = true");
    require_positive(*slice);
    if (len && !(slice->v <= len->v)) fail(*slice, "must not exceed drum.length (" + len->raw + ")");
    d.slice_thickness = slice->v;
    if (plates) throw CaseError(s.key("end_plates"), "a periodic slice has no end plates");
  } else {
    if (slice) throw CaseError(slice->key, "only with drum.periodic_slice = true");
    if (!len) throw CaseError(s.key("length"), "required (or set drum.periodic_slice = true)");
    d.plates_rotate = !plates || *plates == "rotating";
  }
  s.finish();
}

void read_run(Section s, Case& c) {
  if (!s.present()) throw CaseError("run", "required table is missing");
  RunSpec& r = c.run;
  Q settle = s.required("settle", Dim::Time);
  require_nonnegative(settle);
  r.settle = settle.v;
  Q dur = s.required("duration", Dim::Time);
  require_positive(dur);
  r.duration = dur.v;
  Q ss = s.required("steady_state_start", Dim::Time);
  require_nonnegative(ss);
  if (!(ss.v < dur.v)) fail(ss, "must be < run.duration (" + dur.raw + "): the AoR window would be empty");
  r.steady_state_start = ss.v;
  Q si = s.required("sample_interval", Dim::Time);
  require_positive(si);
  if (!(si.v <= dur.v - ss.v))
    fail(si, "must fit in the steady window run.duration - run.steady_state_start");
  r.sample_interval = si.v;
  if (auto seed = s.integer("seed")) {
    if (*seed < 0) throw CaseError(s.key("seed"), fmt::format("must be >= 0, got {}", *seed));
    r.seed = uint64_t(*seed);
  }
  if (auto q = s.quantity("dt", Dim::Time)) require_positive(*q), r.dt = q->v;
  if (auto q = s.quantity("dt_rayleigh_fraction", Dim::Dimensionless)) {
    require_in(*q, 0, true, 1, false, "(0, 1]");
    if (r.dt) throw CaseError(q->key, "give run.dt or run.dt_rayleigh_fraction, not both");
    r.dt_rayleigh_fraction = q->v;
  }
  if (auto q = s.quantity("skin", Dim::Length)) require_positive(*q), r.skin = q->v;
  if (auto q = s.quantity("perturb", Dim::Length)) {
    require_nonnegative(*q);
    // Far below any overlap or gap of the fill: it only moves the start, it never makes a contact.
    if (!(q->v <= 1e-6)) fail(*q, "must be <= 1 um (it moves the starts, not the fill)");
    r.perturb = q->v;
  }
  if (auto seed = s.integer("perturb_seed")) {
    if (*seed < 0) throw CaseError(s.key("perturb_seed"), fmt::format("must be >= 0, got {}", *seed));
    r.perturb_seed = uint64_t(*seed);
  }
  if (auto n = s.integer("steps_per_submit")) {
    if (*n < 1 || *n > 100000)
      throw CaseError(s.key("steps_per_submit"), fmt::format("must be in [1, 100000], got {}", *n));
    r.steps_per_submit = uint32_t(*n);
  }
  s.finish();
}

void read_output(Section s, Case& c) {
  OutputSpec& o = c.output;
  if (auto q = s.quantity("snapshot_interval", Dim::Time))
    require_nonnegative(*q), o.snapshot_interval = q->v;
  if (auto f = s.strings("formats")) {
    for (const std::string& x : *f)
      if (x != "gltf" && x != "vtk")
        throw CaseError(s.key("formats"), "entries must be \"gltf\" or \"vtk\", got \"" + x + "\"");
    o.formats = *f;
  }
  if (auto n = s.integer("checkpoint_interval")) {
    if (*n < 0)
      throw CaseError(s.key("checkpoint_interval"), fmt::format("must be >= 0 (steps), got {}", *n));
    o.checkpoint_interval = uint64_t(*n);
  }
  s.finish();
}

Case read_case(const toml::table& root, const std::string& source) {
  Case c;
  c.source = source;
  Section top(&root, "");
  if (auto s = top.string("name")) c.name = *s;
  if (auto s = top.string("description")) c.description = *s;
  if (auto q = top.quantity("scaling", Dim::Dimensionless)) require_positive(*q), c.scaling = q->v;
  read_material(Section(top.table("material"), "material"), c);
  read_friction(Section(top.table("friction"), "friction"), c);
  Section walls(top.table("walls"), "walls");
  read_wall(Section(walls.table("cylinder"), "walls.cylinder"), c.cylinder, c);
  read_wall(Section(walls.table("plates"), "walls.plates"), c.plates, c);
  walls.finish();
  read_psd(Section(top.table("psd"), "psd"), c);
  read_liquid(Section(top.table("liquid"), "liquid"), c);
  read_cohesion(Section(top.table("cohesion"), "cohesion"), c);
  read_absorption(Section(top.table("absorption"), "absorption"), c);
  read_drum(Section(top.table("drum"), "drum"), c);
  if (c.drum.periodic_slice && walls.has("plates"))
    throw CaseError("walls.plates", "a periodic slice has no end plates");
  read_run(Section(top.table("run"), "run"), c);
  read_output(Section(top.table("output"), "output"), c);
  top.finish();
  // Cross-table checks.
  c.psd.scale = c.scaling;
  double d_largest = 0;
  try {
    d_largest = wetdem::Psd(c.psd).d_max();
  } catch (const std::invalid_argument& e) {
    throw CaseError("psd", e.what());
  }
  if (!(d_largest < 0.5 * c.drum.diameter))
    throw CaseError("scaling",
                    fmt::format("the largest scaled particle ({:.4g} m) does not fit the drum ({:.4g} m)",
                                d_largest, c.drum.diameter));
  if (c.drum.periodic_slice && !(d_largest < 0.5 * c.drum.slice_thickness))
    throw CaseError(
        "drum.slice_thickness",
        fmt::format(
            "must exceed twice the largest scaled particle, 2 x {:.4g} m = {:.4g} m (for the periodic "
            "image), got {:.4g} m",
            d_largest, 2.0 * d_largest, c.drum.slice_thickness));
  if (c.liquid.viscosity > 0 && !c.liquid.on())
    c.notes.push_back(
        "liquid: viscosity acts on bridges only; it has no effect without liquid (content = 0)");
  if (c.liquid.lubrication_cutoff && !(c.liquid.viscosity > 0))
    c.notes.push_back("liquid: lubrication_cutoff has no effect while viscosity = 0");
  if (c.liquid.lubrication_cutoff && !(*c.liquid.lubrication_cutoff < 0.5 * d_largest))
    throw CaseError("liquid.lubrication_cutoff",
                    fmt::format("must be below the largest particle radius ({:.4g} m), got {:.4g} m",
                                0.5 * d_largest, *c.liquid.lubrication_cutoff));
  if ((c.absorption.on() || c.liquid.evaporation_time > 0 || c.liquid.wetted_fraction < 1) && !c.liquid.on())
    c.notes.push_back(
        "absorption, liquid.evaporation_time, liquid.wetted_fraction: no effect without liquid");
  if ((c.cylinder.liquid_bridges || c.plates.liquid_bridges) && !c.liquid.on())
    c.notes.push_back("walls: liquid_bridges = true has no effect without liquid (liquid.content = 0)");
  return c;
}

}  // namespace

Case parse_case_string(const std::string& text, const std::vector<std::string>& overrides,
                       const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw CaseError("", fmt::format("{}:{}:{}: {}", source, b.line, b.column, e.description()));
  }
  for (const std::string& o : overrides) apply_override(root, o);
  return read_case(root, source);
}

Case parse_case_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CaseError("", "cannot read case file " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_case_string(ss.str(), overrides, path);
}

}  // namespace wetdem::app
