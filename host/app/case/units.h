// Units of case-file quantities. A quantity is given either under a key that carries its unit
// (`diameter_m = 0.14`, `theta_deg = 30`) or as a string with a unit (`diameter = "140 mm"`,
// `gamma = "21.7 mN/m"`); both resolve to SI (angles to radians, fractions to [0, 1] numbers).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace wetdem::app {

// Physical dimension of a quantity; decides which units are accepted.
enum class Dim {
  Dimensionless,   // plain number, no unit accepted
  Fraction,        // plain number = fraction (0.05), or percent ("5 %", key suffix _pct)
  Length,          // m
  Pressure,        // Pa
  SurfaceTension,  // N/m
  Angle,           // rad (input usually deg)
  Time,            // s
  AngularRate,     // rad/s (input usually rpm)
  Density,         // kg/m^3
  Viscosity,       // Pa s (dynamic viscosity; "2 mPa s", key suffix _Pa_s, _mPa_s)
  SurfaceEnergy,   // J/m^2 (adhesion work; "50 mJ/m2", key suffix _J_per_m2, _mJ_per_m2)
};

const char* dim_name(Dim d);
const char* si_unit(Dim d);  // "m", "Pa", ... ("" for Dimensionless/Fraction)

// Factor to SI of a unit written in a value string ("mm", "mN/m", "deg", "%", "kg/m^3", ...), or nullopt
// when the unit is unknown or of another dimension.
std::optional<double> unit_factor(Dim d, const std::string& unit);

// Unit spellings accepted as key suffixes for a dimension: `_m`, `_mm`, `_um`, `_Pa`, `_MPa`, `_N_per_m`,
// `_deg`, `_rpm`, `_kg_per_m3`, `_pct`, ... Each maps to the same factor as its string form.
struct KeyUnit {
  std::string suffix;  // without the underscore
  double factor;       // to SI
};
std::vector<KeyUnit> key_units(Dim d);

// v in a unit of the given factor, to SI. Decimal sub-units divide (506 um -> 506 / 1e6 = 0.000506 exactly
// rounded) instead of multiplying by an inexact 1e-6, so SI echoes read as written.
double apply_factor(double v, double factor);

// Parses "140 mm", "21.7mN/m", "1.5e3 Pa", "30 deg", "5 %" into SI. A bare number in the string is accepted
// only for Dimensionless and Fraction. Throws std::invalid_argument with a readable reason (no key name:
// the caller adds it).
double parse_quantity(const std::string& text, Dim d);

}  // namespace wetdem::app
