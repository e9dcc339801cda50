// A case file: everything that defines one drum run, parsed from TOML and validated before any work.
// Key reference: docs/case-keys.md; the shipped cases are in assets/. Quantities are SI once parsed
// (angles in radians, fractions as numbers in [0, 1]).
#pragma once

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/drum/psd.h"
#include "wetdem/params.h"

namespace wetdem::app {

// Bad input. what() is "KEY: reason" (e.g. "drum.fill: must be in (0, 1], got 1.3"); key() is the dotted key.
class CaseError : public std::runtime_error {
 public:
  CaseError(const std::string& key, const std::string& reason)
      : std::runtime_error(key.empty() ? reason : key + ": " + reason), key_(key) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

enum class MaterialInput { EG, ENu, GNu, EStarGStar };  // which pair the case gave
enum class FilmMode { PerParticleVolume, MeanVolume };  // V_f = phi_L * V_i, or phi_L * mean V_S

struct MaterialSpec {
  MaterialInput input = MaterialInput::EG;
  // Material moduli before stiffness reduction, all resolved from the given pair (physics.md §1):
  // nu = E/(2G) - 1, E* = E/(2(1 - nu^2)), G* = G/(2(2 - nu)); from E*, G*: nu = (4 - r)/(2 - r), r = E*/G*.
  double E = 0, G = 0, nu = 0, E_star = 0, G_star = 0;
  double restitution = 0.5;
  double density = 900.0;             // particle (skeletal) density, kg/m^3
  double stiffness_reduction = 1000;  // E, G, E*, G* are divided by it (paper: 10^3)
};

struct WallSpec {
  double mu_s = 0, mu_r = 0;    // default: the particle-particle values
  bool liquid_bridges = false;  // particle-wall bridges (same gamma, theta, V_min, V_max, d_c as pairs)
};

struct LiquidSpec {
  bool present = false;  // [liquid] given; bridges are on when content > 0
  double gamma = 0;      // N/m, unscaled (scaled by l in SimParams, physics.md §4)
  double theta = 0;      // rad
  double content = 0;    // phi_L = V_L / V_S
  double v_min = 0;      // fraction of mean solid volume V-bar_S
  double v_max = 0;      // fraction of V-bar_S
  double d_c = 1.0;
  FilmMode films = FilmMode::PerParticleVolume;
  // Candidate effects (docs/model.md "Candidate effects"; diagnosis.md §3), off by default:
  double viscosity = 0;                      // eta, Pa s: lubrication of bridged pairs (0 = off)
  std::optional<double> lubrication_cutoff;  // S_min, m; default 1 % of the mean particle radius
  std::optional<double> theta_receding;      // theta_r, rad; absent = theta (no hysteresis)
  double evaporation_time = 0;  // s, tau of evaporation; 0 = off (diagnosis.md §3 `evaporation`)
  double wetted_fraction = 1;   // fraction of the particles that hold all the liquid at the start (`spread`)
  bool on() const { return present && content > 0; }
};

// Pore absorption (diagnosis.md §3 `absorption`), off by default.
struct AbsorptionSpec {
  double capacity = 0;  // pore volume / particle volume, [0, 0.3]
  double rate = 0;      // k (1/s); +infinity = "instantaneous"
  bool on() const { return capacity > 0 && rate > 0; }
};

// Candidate effect `cohesion`: dry JKR adhesion of every contact (particles and walls).
struct CohesionSpec {
  double surface_energy = 0;  // w, J/m^2, unscaled (scaled by l like gamma); 0 = off
};

struct DrumSpec {
  double diameter = 0;              // m
  double length = 0;                // m (the real drum; a periodic slice simulates slice_thickness of it)
  double omega = 0;                 // rad/s about +z
  double fill = 0;                  // bed volume / drum volume
  double bed_solid_fraction = 0.6;  // solid volume inserted = fill * drum volume * bed_solid_fraction
  bool plates_rotate = true;
  bool periodic_slice = false;
  double slice_thickness = 0;  // m, period along z when periodic_slice
  double sim_length() const { return periodic_slice ? slice_thickness : length; }
};

struct RunSpec {
  double settle = 0;              // s, drum at rest before rotation starts
  double duration = 0;            // s of rotation after settling
  double steady_state_start = 0;  // s after rotation starts; AoR averaged over [this, duration]
  double sample_interval = 0;     // s between samples
  uint64_t seed = 1;
  std::optional<double> dt;  // s; default dt_rayleigh_fraction * Rayleigh time of the smallest particle
  double dt_rayleigh_fraction = 0.2;
  std::optional<double> skin;  // m; default 0.3 * smallest radius
  uint32_t steps_per_submit = 200;
  // Starts moved by up to `perturb` (m) along each axis, uniform, drawn with perturb_seed (0 = unmoved):
  // the spread of a run's outcome over starts that differ by far less than anything measurable
  // (docs/closed-slice.md).
  double perturb = 0;
  uint64_t perturb_seed = 1;
};

struct OutputSpec {
  double snapshot_interval = 0;      // s, 0 = no snapshots
  std::vector<std::string> formats;  // "gltf", "vtk"
  uint64_t checkpoint_interval = 0;  // steps, 0 = no checkpoints
};

struct Case {
  std::string name, description, source;  // source: the file it came from
  double scaling = 1.0;                   // particle size factor l (physics.md §4)
  MaterialSpec material;
  double mu_s = 0, mu_r = 0;  // particle-particle
  WallSpec cylinder, plates;
  // The powder (app/psd.h: tails and bases explained there). Table diameters are the unscaled powder sizes;
  // psd.scale = scaling, so Psd(psd) is the distribution actually inserted.
  wetdem::PsdSpec psd;
  LiquidSpec liquid;
  CohesionSpec cohesion;
  AbsorptionSpec absorption;
  DrumSpec drum;
  RunSpec run;
  OutputSpec output;
  std::vector<std::string> notes;  // assumptions and warnings found while resolving (logged)
};

// Parses and validates. `overrides` are "dotted.key=value" strings (value parsed as TOML, else taken as a
// string) applied before validation, replacing any other unit spelling of the same key. Throws CaseError.
Case parse_case_file(const std::string& path, const std::vector<std::string>& overrides = {});
Case parse_case_string(const std::string& toml_text, const std::vector<std::string>& overrides = {},
                       const std::string& source = "<string>");

// The resolved case as a TOML document in SI keys (diameter_m, E_Pa, theta_rad, ...): parses back to the
// same Case. For the log and `wetdem check`.
std::string case_to_toml(const Case& c);
// The same content as JSON (for summary.json).
nlohmann::json case_to_json(const Case& c);

// The case as its physics sees it: parameters that cannot act in it reset to their defaults. Without liquid
// (content 0) the liquid-only candidate effects (diagnosis.md §3: viscous, hysteresis, evaporation, spread,
// absorption) act on nothing, so a dry probe of one of them is the dry baseline run, bit for bit
// (tests/test_dry_inert.cpp runs each and compares the final states). The diagnosis's run book keys runs by
// it so that such a run is computed once (host/diagnose/runbook.h).
Case physics_identity(const Case& c);

// What follows from the case and the inserted particles: SimParams and the derived numbers worth logging.
struct Derived {
  double nu = 0, E_star = 0, G_star = 0;  // reduced moduli that enter the contact laws
  double r_min = 0, r_max = 0, mean_solid_volume = 0;
  double t_rayleigh = 0, dt = 0, skin = 0;
  std::string dt_reason;      // what set dt: "run.dt", "0.2 x Rayleigh time of r_min", the viscous limit
  double gamma_scaled = 0;    // l * gamma
  double liquid_unit_m3 = 0;  // V-bar_S * 2^-40
  int64_t v_min_units = 0, v_max_units = 0;
  double dt_capillary_limit = 0;  // 0.1 pi sqrt(m*/k_c) at the smallest initial bridge (0: dry)
  // Candidate effects, as they enter SimParams.
  double lubrication_cutoff = 0;     // S_min (m): given, or 1 % of the mean radius
  double surface_energy_scaled = 0;  // l w (J/m^2)
  double dt_viscous_limit = 0;       // 2 m*/(4 c) at S_min, smallest particles, V_max bridge (0: viscous off)
  std::vector<std::string> notes;
};
// The explicit stability limit 2 m*/(4 c) of the lubrication damper (candidate effect `viscous`) for the
// smallest particle radius r_min and the mean solid volume (S_min: the case's, else 1 % of the mean radius;
// a bridge of V_max; against a wall too when wall bridges are on). 0 when viscosity is off.
double case_viscous_dt_limit(const Case& c, double r_min, double mean_solid_volume);
// radii: the inserted particles (m). Fills every SimParams field from the case (physics.md §1, §4, §6).
SimParams make_sim_params(const Case& c, const std::vector<double>& radii, Derived* derived = nullptr);
nlohmann::json derived_to_json(const Derived& d);

// Initial film volumes (liquid units) of the particles: phi_L * V_i or phi_L * V-bar_S (FilmMode). With
// liquid.wetted_fraction f < 1, round(f N) particles drawn with run.seed hold the same total, split in
// proportion to the same weights (own or mean volume), exactly in integers (spread_films).
std::vector<int64_t> initial_films(const Case& c, const std::vector<double>& radii, double liquid_unit_m3);
// Puts all of Σ films on round(f N) (at least 1) particles chosen by a seeded Fisher-Yates draw
// (mt19937_64), films in proportion to `weight`; the total is unchanged exactly.
std::vector<int64_t> spread_films(const std::vector<int64_t>& films, const std::vector<double>& weight,
                                  double wetted_fraction, uint64_t seed);

}  // namespace wetdem::app
