#include "diagnose/effects.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wetdem::diagnose {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

std::vector<std::string> EffectSpec::overrides(double s, double shape_value, const ModelFacts& m) const {
  if (!(s > 0))
    throw std::invalid_argument(fmt::format("effect '{}': strength must be > 0, got {}", name, s));
  if (name == "viscous") return {fmt::format("liquid.viscosity=\"{:.9g} Pa s\"", s)};
  if (name == "absorption") {  // capacity (fraction of own volume), filled at the shape's rate k (1/s)
    if (!(shape_value > 0))
      throw std::invalid_argument(fmt::format("effect 'absorption': rate must be > 0, got {}", shape_value));
    return {fmt::format("absorption.capacity={:.9g}", s), fmt::format("absorption.rate={:.9g}", shape_value)};
  }
  if (name == "cohesion") return {fmt::format("cohesion.surface_energy=\"{:.9g} J/m2\"", s)};
  if (name == "hysteresis") {  // s = theta - theta_r in degrees: the receding angle below the static one
    const double th = std::max(0.0, m.theta_rad * 180.0 / kPi - s);
    return {fmt::format("liquid.theta_receding=\"{:.9g} deg\"", th)};
  }
  if (name == "evaporation") return {fmt::format("liquid.evaporation_time=\"{:.9g} s\"", 1.0 / s)};
  if (name == "spread") return {fmt::format("liquid.wetted_fraction={:.9g}", std::max(0.1, 1.0 - s))};
  if (name ==
      "scale")  // s = 1 - l'/l: the real powder is less coarse-grained than the model (l -> (1 - s) l)
    return {fmt::format("scaling={:.9g}", m.scaling * (1.0 - std::min(s, 0.6)))};
  if (name == "plates")  // s = friction added at the end plates, sliding and rolling alike, capped at 1
    return {fmt::format("walls.plates.mu_s={:.9g}", std::min(1.0, m.plates_mu_s + s)),
            fmt::format("walls.plates.mu_r={:.9g}", std::min(1.0, m.plates_mu_r + s))};
  throw std::invalid_argument("effect '" + name + "' has no override rule");
}

std::vector<std::string> EffectSpec::overrides(double s, const ModelFacts& m) const {
  return overrides(s, default_shape(), m);
}

const std::vector<EffectSpec>& effect_catalogue() {
  // Physical ranges from diagnosis.md §3, in strength units: viscous η 1e-4-1 Pa s; absorption capacity
  // 0-0.3 of the own volume and rate 0.01 1/s - instantaneous (1e9 1/s here); cohesion w 1e-4-0.1 J/m²;
  // hysteresis θ_r 0-80°, i.e. θ - θ_r up to θ (checked against the model's θ when the overrides are made:
  // θ_r is floored at 0); evaporation τ 1-1000 s, i.e. 1/τ 1e-3-1 1/s; spread f 0.1-1, i.e. 1 - f up to 0.9;
  // scale l -> 0.6 l, i.e. s up to 0.4; plates μ added up to 1. The lower ends of ranges that start at 0 are
  // the weakest strength worth resolving (a hundredth of the upper end or below).
  static const std::vector<EffectSpec> k = {
      {"viscous",
       "eta (Pa s)",
       {1e-3, 1e-2, 1e-1},
       "grows with drum speed; damps the flowing layer",
       1e-4,
       1.0},
      {"absorption",
       "pore capacity (fraction of own volume)",
       {0.01, 0.05, 0.2},
       "late onset of cohesion (a shift of the liquid content); AoR falls with time at slow rates",
       1e-3,
       0.3,
       "rate k (1/s)",
       {0.3, 3.0, 30.0},
       0.01,
       1e9},
      {"cohesion", "w (J/m2)", {1e-3, 1e-2, 1e-1}, "raises the dry AoR too", 1e-4, 0.1},
      {"hysteresis",
       "theta - theta_r (deg)",
       {3.0, 10.0, 28.0},
       "matters where bridges stretch: high liquid",
       0.3,
       80.0},
      {"evaporation", "1/tau (1/s)", {1e-2, 1e-1, 1.0}, "AoR falls with time, most at low liquid", 1e-3, 1.0},
      {"spread", "1 - wetted fraction", {0.1, 0.3, 0.9}, "onset earlier, f_wet lower", 0.01, 0.9},
      // (1 - s)^-3 times the particles: s = 0.4 (l -> 0.6 l) costs 4.6x the particles and ~1.7x the steps.
      {"scale",
       "1 - l'/l (finer particles)",
       {0.1, 0.25, 0.4},
       "grows with agglomeration (liquid content)",
       0.02,
       0.4},
      {"plates",
       "added plate friction mu",
       {0.05, 0.2, 0.5},
       "AoR at the plate differs from the centre",
       0.01,
       1.0},
  };
  return k;
}

std::string EffectSpec::not_applicable(const ModelFacts& m) const {
  if (name == "plates" && !m.has_plates) return "the model is a periodic slice: it has no end plates";
  return "";
}

double EffectSpec::realisable_hi(const ModelFacts& m) const {
  if (name == "hysteresis" && m.theta_rad > 0) return std::min(phys_hi, m.theta_rad * 180.0 / kPi);
  return phys_hi;
}

std::string EffectSpec::range_text() const {
  return fmt::format("{:g}-{:g}", phys_lo, phys_hi);
}
std::string EffectSpec::shape_range_text() const {
  return fmt::format("{:g}-{:g}", shape_lo, shape_hi);
}

const EffectSpec& effect_spec(const std::string& name) {
  for (const EffectSpec& e : effect_catalogue())
    if (e.name == name) return e;
  std::string known;
  for (const EffectSpec& e : effect_catalogue()) known += (known.empty() ? "" : ", ") + e.name;
  throw std::invalid_argument("unknown effect '" + name + "' (known: " + known + ")");
}

}  // namespace wetdem::diagnose
