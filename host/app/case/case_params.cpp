// From a validated case and the inserted particles to SimParams (physics.md §1, §4, §6).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "app/case/case.h"
#include "wetdem/timestep.h"

namespace wetdem::app {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwo40 = 1099511627776.0;  // 2^40: V-bar_S is 2^40 liquid units

double sphere_volume(double r) {
  return 4.0 / 3.0 * kPi * r * r * r;
}

}  // namespace

std::vector<int64_t> initial_films(const Case& c, const std::vector<double>& radii, double unit) {
  std::vector<int64_t> films(radii.size(), 0);
  if (!c.liquid.on()) return films;
  double mean_v = 0;
  for (double r : radii) mean_v += sphere_volume(r);
  mean_v /= double(radii.size());
  for (size_t k = 0; k < radii.size(); ++k) {
    const double v = c.liquid.films == FilmMode::MeanVolume ? mean_v : sphere_volume(radii[k]);
    films[k] = std::llround(c.liquid.content * v / unit);
  }
  if (c.liquid.wetted_fraction < 1.0) {
    std::vector<double> weight(radii.size(), 1.0);
    if (c.liquid.films != FilmMode::MeanVolume)
      for (size_t k = 0; k < radii.size(); ++k) weight[k] = sphere_volume(radii[k]);
    // Its own stream (not the fill's draws): the same seed gives the same wetted particles.
    films = spread_films(films, weight, c.liquid.wetted_fraction, c.run.seed ^ 0x5350524541440000ull);
  }
  return films;
}

std::vector<int64_t> spread_films(const std::vector<int64_t>& films, const std::vector<double>& weight,
                                  double f, uint64_t seed) {
  const size_t n = films.size();
  std::vector<int64_t> out(n, 0);
  if (n == 0) return out;
  int64_t total = 0;
  for (int64_t v : films) total += v;
  const size_t m = std::clamp<size_t>(size_t(std::llround(f * double(n))), 1, n);
  // Fisher-Yates on indices with mt19937_64 (fully specified by the standard; the modulo is our own, so the
  // draw does not depend on the library's distribution implementation).
  std::vector<size_t> idx(n);
  for (size_t k = 0; k < n; ++k) idx[k] = k;
  std::mt19937_64 rng(seed);
  for (size_t k = n - 1; k > 0; --k) std::swap(idx[k], idx[size_t(rng() % (k + 1))]);
  std::vector<size_t> wet(idx.begin(), idx.begin() + long(m));
  std::sort(wet.begin(), wet.end());
  long double wsum = 0;
  for (size_t k : wet) wsum += (long double)weight[k];
  int64_t given = 0;
  for (size_t k : wet) {
    out[k] = int64_t(std::floor((long double)total * (long double)weight[k] / wsum));
    out[k] = std::clamp<int64_t>(out[k], 0, total - given);
    given += out[k];
  }
  // The rounding remainder (0 <= rest < m for exact floors), one unit each in id order, so Σ is exact.
  int64_t rest = total - given;
  for (size_t r = 0; rest > 0; r = (r + 1) % m, --rest) out[wet[r]] += 1;
  return out;
}

double case_viscous_dt_limit(const Case& c, double r_min, double mean_solid_volume) {
  const LiquidSpec& l = c.liquid;
  if (!l.on() || !(l.viscosity > 0)) return 0.0;
  const double r_mean = std::cbrt(mean_solid_volume * 3.0 / (4.0 * kPi));
  const double s_min = l.lubrication_cutoff ? *l.lubrication_cutoff : 0.01 * r_mean;
  const double m_min = c.material.density * sphere_volume(r_min), vmax = l.v_max * mean_solid_volume;
  double lim = viscous_dt_limit(0.5 * m_min, 0.5 * r_min, l.viscosity, s_min, vmax);
  if (c.cylinder.liquid_bridges || (c.plates.liquid_bridges && !c.drum.periodic_slice))
    lim = std::min(lim, viscous_dt_limit(m_min, r_min, l.viscosity, s_min, vmax));
  return lim;
}

SimParams make_sim_params(const Case& c, const std::vector<double>& radii, Derived* out) {
  if (radii.empty()) throw CaseError("drum.fill", "no particle was inserted");
  Derived d;
  const MaterialSpec& m = c.material;
  d.nu = m.nu;
  d.E_star = m.E_star / m.stiffness_reduction;
  d.G_star = m.G_star / m.stiffness_reduction;
  d.r_min = *std::min_element(radii.begin(), radii.end());
  d.r_max = *std::max_element(radii.begin(), radii.end());
  double vs = 0;
  for (double r : radii) vs += sphere_volume(r);
  d.mean_solid_volume = vs / double(radii.size());

  SimParams p;
  // §6: t_R = pi r sqrt(rho/G) / (0.1631 nu + 0.8766), with the reduced G; dt = 0.2 t_R of the smallest
  // particle.
  d.t_rayleigh = rayleigh_time(d.r_min, m.density, m.G / m.stiffness_reduction, m.nu);
  d.dt = c.run.dt ? *c.run.dt : c.run.dt_rayleigh_fraction * d.t_rayleigh;
  d.dt_reason = c.run.dt ? "run.dt" : fmt::format("{} x Rayleigh time of r_min", c.run.dt_rayleigh_fraction);
  if (c.run.dt && *c.run.dt > 0.2 * d.t_rayleigh)
    d.notes.push_back(fmt::format("run.dt = {:.4g} s exceeds 0.2 t_R = {:.4g} s of the smallest particle",
                                  *c.run.dt, 0.2 * d.t_rayleigh));
  // Skin: the list is rebuilt when the two largest displacements in the drum's frame add up to it
  // (ARCHITECTURE.md "The skin test"; measured with the classic rule, largest > skin/2). 0.3 r_min: on the
  // demo (lavapipe) 0.1 r_min rebuilt every ~4 steps and ran 2.5x slower; 0.6 r_min rebuilt half as often as
  // 0.3 r_min but was no faster, the thicker neighbour shell (entries grow with (r + skin)^3) eating the
  // saving.
  d.skin = c.run.skin ? *c.run.skin : 0.3 * d.r_min;
  p.skin = d.skin;

  ContactParams cp;
  cp.E_star = d.E_star;
  cp.G_star = d.G_star;
  cp.restitution = m.restitution;
  cp.mu_s = c.mu_s;
  cp.mu_r = c.mu_r;
  // Candidate effect `cohesion`: w scaled by l like gamma (the same pressure-based Bond number), every
  // contact.
  d.surface_energy_scaled = c.scaling * c.cohesion.surface_energy;
  cp.surface_energy = d.surface_energy_scaled;
  p.pp = cp;
  // Walls: the same material law (the paper's walls are polycarbonate; it gives one set of moduli), their own
  // friction coefficients.
  for (uint32_t w = 0; w < kNumWalls; ++w) {
    const WallSpec& ws = w == kWallCylinder ? c.cylinder : c.plates;
    p.pw[w] = cp;
    p.pw[w].mu_s = ws.mu_s;
    p.pw[w].mu_r = ws.mu_r;
  }

  // Liquid: V-bar_S = 2^40 units, so V_min, V_max (fractions of V-bar_S) are exact multiples of 2^-40
  // V-bar_S.
  d.liquid_unit_m3 = d.mean_solid_volume / kTwo40;
  p.liquid_unit_m3 = d.liquid_unit_m3;
  const LiquidSpec& l = c.liquid;
  d.gamma_scaled = c.scaling * l.gamma;  // §4: gamma_scaled = l gamma
  d.v_min_units = std::llround(l.v_min * kTwo40);
  d.v_max_units = std::llround(l.v_max * kTwo40);
  LiquidParams lp;
  lp.enabled = l.on();
  lp.gamma = d.gamma_scaled;
  lp.theta = l.theta;
  lp.v_min = d.v_min_units;
  lp.v_max = d.v_max_units;
  lp.d_c = l.d_c;
  // Candidate effects `viscous` (S_min default: 1 % of the mean particle radius, the roughness scale DEM
  // lubrication models commonly truncate at) and `hysteresis` (theta_r = theta unless given).
  const double r_mean = std::cbrt(d.mean_solid_volume * 3.0 / (4.0 * kPi));
  d.lubrication_cutoff = l.lubrication_cutoff ? *l.lubrication_cutoff : 0.01 * r_mean;
  lp.viscosity = l.viscosity;
  lp.lubrication_cutoff = d.lubrication_cutoff;
  lp.theta_receding = l.theta_receding ? *l.theta_receding : -1.0;
  p.liq_pp = lp;
  for (uint32_t w = 0; w < kNumWalls; ++w) {
    p.liq_pw[w] = lp;
    p.liq_pw[w].enabled = lp.enabled && (w == kWallCylinder ? c.cylinder : c.plates).liquid_bridges;
  }

  p.drum.radius = 0.5 * c.drum.diameter;
  p.drum.length = c.drum.sim_length();
  p.drum.omega = c.drum.omega;
  p.drum.periodic_z = c.drum.periodic_slice;
  p.drum.plate_lo.present = p.drum.plate_hi.present = !c.drum.periodic_slice;
  p.drum.plate_lo.rotates = p.drum.plate_hi.rotates = c.drum.plates_rotate;

  if (l.on()) {
    // Total liquid must stay far inside int64 (every transfer is an integer move).
    const std::vector<int64_t> films = initial_films(c, radii, d.liquid_unit_m3);
    long double total = 0;
    for (int64_t f : films) total += (long double)f;
    if (total > 4.0e18L)
      throw CaseError("liquid.content",
                      "total liquid exceeds the int64 range of liquid units; reduce content");
    // §6: capillary stiffness k_c = 1.05 f0 sqrt(R_h/V_b) at the smallest bridge the initial films can form
    // (smallest_formable_bridge, between two of the smallest particles); warn when dt > 0.1 pi sqrt(m*/k_c).
    const double vb = double(smallest_formable_bridge(lp, films)) * d.liquid_unit_m3;
    if (vb > 0) {
      const double rh = d.r_min;  // harmonic mean 2 r r / (2 r)
      const double f0 = 2.0 * kPi * rh * d.gamma_scaled * std::cos(lp.theta_r());  // pull just separated
      const double kc = 1.05 * f0 * std::sqrt(rh / vb);
      const double mstar = 0.5 * m.density * sphere_volume(d.r_min);
      d.dt_capillary_limit = 0.1 * kPi * std::sqrt(mstar / kc);
      if (d.dt > d.dt_capillary_limit)
        d.notes.push_back(
            fmt::format("dt = {:.4g} s exceeds the capillary limit 0.1 pi sqrt(m*/k_c) = {:.4g} s at "
                        "the smallest bridge the initial films can form ({:.3g} m^3): divide "
                        "run.dt_rayleigh_fraction by at least {:.3g} (physics.md §6)",
                        d.dt, d.dt_capillary_limit, vb, d.dt / d.dt_capillary_limit));
    }
  }
  if (l.on() && l.viscosity > 0) {
    // Explicit stability of the lubrication damper (docs/model.md "Candidate effects"): dt < 2 m*/(4 c) at
    // S_min for the two smallest particles with a bridge of V_max, or the smallest against a wall with
    // bridges.
    d.dt_viscous_limit = case_viscous_dt_limit(c, d.r_min, d.mean_solid_volume);
    // The damper's limit bounds the time step as the Rayleigh fraction does: a default dt above it is
    // lowered to it (so every strength of the candidate runs, at a cost in steps); an explicit run.dt above
    // it is the user's choice and gets a note.
    if (d.dt >= d.dt_viscous_limit) {
      if (c.run.dt) {
        d.notes.push_back(fmt::format(
            "run.dt = {:.4g} s exceeds the viscous limit 2 m*/(4 c) = {:.4g} s of the lubrication damping "
            "at S_min = {:.4g} m (explicit damping unstable); lower run.dt or raise "
            "liquid.lubrication_cutoff",
            d.dt, d.dt_viscous_limit, d.lubrication_cutoff));
      } else {
        d.notes.push_back(fmt::format(
            "dt lowered from {:.4g} s ({}) to the viscous limit 2 m*/(4 c) = {:.4g} s of the lubrication "
            "damping at S_min = {:.4g} m: {:.3g}x the steps",
            d.dt, d.dt_reason, d.dt_viscous_limit, d.lubrication_cutoff, d.dt / d.dt_viscous_limit));
        d.dt = d.dt_viscous_limit;
        d.dt_reason = "viscous limit 2 m*/(4 c) of the lubrication damping";
      }
    }
  }
  p.dt = d.dt;
  // Liquid sinks (diagnosis.md §3): pore absorption and evaporation act inside the liquid passes.
  if (l.on()) {
    if (c.absorption.on()) {
      p.sinks.pore_capacity = c.absorption.capacity;
      p.sinks.absorption_rate = c.absorption.rate;
      // Time-step check: 1 - e^-(k dt) is always in [0, 1], so no rate is unstable; but with k dt > 0.1 the
      // film empties in fewer than ~10 steps and the decay is resolved only coarsely in time.
      if (std::isfinite(c.absorption.rate) && c.absorption.rate * d.dt > 0.1)
        d.notes.push_back(
            fmt::format("absorption.rate x dt = {:.3g} > 0.1: the film is absorbed within a few "
                        "steps (use \"instantaneous\" if that is intended)",
                        c.absorption.rate * d.dt));
    }
    p.sinks.evaporation_time = l.evaporation_time;
  }
  if (out) *out = d;
  return p;
}

nlohmann::json derived_to_json(const Derived& d) {
  nlohmann::json j;
  j["nu"] = d.nu;
  j["E_star_reduced_Pa"] = d.E_star;
  j["G_star_reduced_Pa"] = d.G_star;
  j["r_min_m"] = d.r_min;
  j["r_max_m"] = d.r_max;
  j["mean_solid_volume_m3"] = d.mean_solid_volume;
  j["rayleigh_time_s"] = d.t_rayleigh;
  j["dt_s"] = d.dt;
  j["dt_reason"] = d.dt_reason;
  j["skin_m"] = d.skin;
  j["gamma_scaled_N_per_m"] = d.gamma_scaled;
  j["liquid_unit_m3"] = d.liquid_unit_m3;
  j["v_min_units"] = d.v_min_units;
  j["v_max_units"] = d.v_max_units;
  j["dt_capillary_limit_s"] = d.dt_capillary_limit;
  j["lubrication_cutoff_m"] = d.lubrication_cutoff;
  j["surface_energy_scaled_J_per_m2"] = d.surface_energy_scaled;
  j["dt_viscous_limit_s"] = d.dt_viscous_limit;
  j["notes"] = d.notes;
  return j;
}

}  // namespace wetdem::app
