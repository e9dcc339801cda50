#include "app/case/units.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace wetdem::app {

namespace {

constexpr double kPi = 3.14159265358979323846;

// One unit: the dimension, its spellings in value strings, its key suffix ("" = none) and factor to SI.
struct UnitDef {
  Dim dim;
  std::vector<std::string> spellings;
  std::string key_suffix;
  double factor;
};

const std::vector<UnitDef>& units() {
  static const std::vector<UnitDef> u = {
      {Dim::Fraction, {"%", "pct", "vol%", "percent"}, "pct", 0.01},
      {Dim::Length, {"m"}, "m", 1.0},
      {Dim::Length, {"cm"}, "cm", 1e-2},
      {Dim::Length, {"mm"}, "mm", 1e-3},
      {Dim::Length, {"um", "\xc2\xb5m", "\xce\xbcm", "micron"}, "um", 1e-6},  // µ (micro sign), μ (mu)
      {Dim::Length, {"nm"}, "nm", 1e-9},                                      // run.perturb
      {Dim::Pressure, {"Pa"}, "Pa", 1.0},
      {Dim::Pressure, {"kPa"}, "kPa", 1e3},
      {Dim::Pressure, {"MPa"}, "MPa", 1e6},
      {Dim::Pressure, {"GPa"}, "GPa", 1e9},
      {Dim::SurfaceTension, {"N/m"}, "N_per_m", 1.0},
      {Dim::SurfaceTension, {"mN/m"}, "mN_per_m", 1e-3},
      {Dim::Angle, {"rad"}, "rad", 1.0},
      {Dim::Angle, {"deg", "\xc2\xb0"}, "deg", kPi / 180.0},
      {Dim::Time, {"s"}, "s", 1.0},
      {Dim::Time, {"ms"}, "ms", 1e-3},
      {Dim::Time, {"us", "\xc2\xb5s", "\xce\xbcs"}, "us", 1e-6},
      {Dim::Time, {"min"}, "min", 60.0},
      {Dim::AngularRate, {"rpm"}, "rpm", 2.0 * kPi / 60.0},
      {Dim::AngularRate, {"rad/s"}, "rad_per_s", 1.0},
      {Dim::Density, {"kg/m3", "kg/m^3", "kg/m\xc2\xb3"}, "kg_per_m3", 1.0},
      {Dim::Density, {"g/cm3", "g/cm^3", "g/cm\xc2\xb3"}, "g_per_cm3", 1e3},
      // Spaces are stripped before matching: "2 mPa s" reads as "2 mPas".
      {Dim::Viscosity, {"Pas", "Pa*s", "Pa.s", "Pa\xc2\xb7s"}, "Pa_s", 1.0},
      {Dim::Viscosity, {"mPas", "mPa*s", "mPa.s", "mPa\xc2\xb7s", "cP"}, "mPa_s", 1e-3},
      {Dim::SurfaceEnergy, {"J/m2", "J/m^2", "J/m\xc2\xb2"}, "J_per_m2", 1.0},
      {Dim::SurfaceEnergy, {"mJ/m2", "mJ/m^2", "mJ/m\xc2\xb2"}, "mJ_per_m2", 1e-3},
  };
  return u;
}

std::string strip_spaces(const std::string& s) {
  std::string out;
  for (char c : s)
    if (!std::isspace(static_cast<unsigned char>(c))) out += c;
  return out;
}

}  // namespace

const char* dim_name(Dim d) {
  switch (d) {
    case Dim::Dimensionless:
      return "a number";
    case Dim::Fraction:
      return "a fraction (0.05 or \"5 %\")";
    case Dim::Length:
      return "a length";
    case Dim::Pressure:
      return "a pressure";
    case Dim::SurfaceTension:
      return "a surface tension";
    case Dim::Angle:
      return "an angle";
    case Dim::Time:
      return "a time";
    case Dim::AngularRate:
      return "a rotation rate";
    case Dim::Density:
      return "a density";
    case Dim::Viscosity:
      return "a viscosity";
    case Dim::SurfaceEnergy:
      return "a surface energy";
  }
  return "?";
}

const char* si_unit(Dim d) {
  switch (d) {
    case Dim::Length:
      return "m";
    case Dim::Pressure:
      return "Pa";
    case Dim::SurfaceTension:
      return "N_per_m";
    case Dim::Angle:
      return "rad";
    case Dim::Time:
      return "s";
    case Dim::AngularRate:
      return "rad_per_s";
    case Dim::Density:
      return "kg_per_m3";
    case Dim::Viscosity:
      return "Pa_s";
    case Dim::SurfaceEnergy:
      return "J_per_m2";
    default:
      return "";
  }
}

std::optional<double> unit_factor(Dim d, const std::string& unit) {
  const std::string u = strip_spaces(unit);
  for (const UnitDef& def : units()) {
    if (def.dim != d) continue;
    for (const std::string& s : def.spellings)
      if (s == u) return def.factor;
  }
  return std::nullopt;
}

std::vector<KeyUnit> key_units(Dim d) {
  std::vector<KeyUnit> out;
  for (const UnitDef& def : units())
    if (def.dim == d && !def.key_suffix.empty()) out.push_back({def.key_suffix, def.factor});
  return out;
}

double apply_factor(double v, double factor) {
  if (factor < 1.0) {
    const double inv = std::round(1.0 / factor);
    if (std::fabs(inv * factor - 1.0) < 1e-12) return v / inv;
  }
  return v * factor;
}

double parse_quantity(const std::string& text, Dim d) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin) throw std::invalid_argument("expected a number with a unit, got \"" + text + "\"");
  if (!std::isfinite(v)) throw std::invalid_argument("not a finite number: \"" + text + "\"");
  const std::string unit = strip_spaces(std::string(end));
  if (unit.empty()) {
    if (d == Dim::Dimensionless || d == Dim::Fraction) return v;
    throw std::invalid_argument(std::string("\"") + text + "\" has no unit; " + dim_name(d) +
                                " needs one (e.g. \"140 mm\"), or use a key that names the unit");
  }
  std::optional<double> f = unit_factor(d, unit);
  if (!f) {
    std::string known;
    for (const UnitDef& def : units())
      if (def.dim == d) known += (known.empty() ? "" : ", ") + def.spellings.front();
    if (known.empty()) known = "none";
    throw std::invalid_argument("unknown unit \"" + unit + "\" for " + dim_name(d) + " (accepted: " + known +
                                ")");
  }
  return apply_factor(v, *f);
}

}  // namespace wetdem::app
