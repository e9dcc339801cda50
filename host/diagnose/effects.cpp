#include "diagnose/effects.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace wetdem::diagnose {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

std::vector<std::string> EffectSpec::overrides(double s, double theta_rad) const {
  if (!(s > 0))
    throw std::invalid_argument(fmt::format("effect '{}': strength must be > 0, got {}", name, s));
  if (name == "viscous") return {fmt::format("liquid.viscosity=\"{:.9g} Pa s\"", s)};
  if (name == "absorption")  // capacity (fraction of own volume) filled at 10 1/s: onset delayed within a run
    return {fmt::format("absorption.capacity={:.9g}", s), "absorption.rate=10.0"};
  if (name == "cohesion") return {fmt::format("cohesion.surface_energy=\"{:.9g} J/m2\"", s)};
  if (name == "hysteresis") {  // s = theta - theta_r in degrees: the receding angle below the static one
    const double th = std::max(0.0, theta_rad * 180.0 / kPi - s);
    return {fmt::format("liquid.theta_receding=\"{:.9g} deg\"", th)};
  }
  if (name == "evaporation") return {fmt::format("liquid.evaporation_time=\"{:.9g} s\"", 1.0 / s)};
  if (name == "spread") return {fmt::format("liquid.wetted_fraction={:.9g}", std::max(0.1, 1.0 - s))};
  throw std::invalid_argument("effect '" + name + "' has no override rule");
}

const std::vector<EffectSpec>& effect_catalogue() {
  static const std::vector<EffectSpec> k = {
      {"viscous", "eta (Pa s)", {1e-3, 1e-2, 1e-1}, "grows with drum speed; damps the flowing layer"},
      {"absorption",
       "pore capacity (fraction of own volume)",
       {0.01, 0.05, 0.2},
       "late onset of cohesion; AoR falls with time"},
      {"cohesion", "w (J/m2)", {1e-3, 1e-2, 1e-1}, "raises the dry AoR too"},
      {"hysteresis",
       "theta - theta_r (deg)",
       {3.0, 10.0, 28.0},
       "matters where bridges stretch: high liquid"},
      {"evaporation", "1/tau (1/s)", {1e-3, 1e-2, 1e-1}, "AoR falls with time, most at low liquid"},
      {"spread", "1 - wetted fraction", {0.1, 0.3, 0.9}, "onset earlier, f_wet lower"},
  };
  return k;
}

const EffectSpec& effect_spec(const std::string& name) {
  for (const EffectSpec& e : effect_catalogue())
    if (e.name == name) return e;
  std::string known;
  for (const EffectSpec& e : effect_catalogue()) known += (known.empty() ? "" : ", ") + e.name;
  throw std::invalid_argument("unknown effect '" + name + "' (known: " + known + ")");
}

}  // namespace wetdem::diagnose
