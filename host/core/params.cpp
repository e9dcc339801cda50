#include "wetdem/params.h"

#include <algorithm>
#include <cmath>

namespace wetdem {

double rupture_distance(double theta, double volume_m3) {
  return (1.0 + 0.5 * theta) * std::cbrt(volume_m3);  // §4
}

double SimParams::bridge_range_pp() const {
  if (!liq_pp.enabled || liq_pp.v_max <= 0) return 0.0;
  return rupture_distance(std::max(liq_pp.theta, liq_pp.theta_r()), double(liq_pp.v_max) * liquid_unit_m3);
}

double SimParams::bridge_range_pw(uint32_t wall) const {
  const LiquidParams& l = liq_pw[wall];
  if (!l.enabled || l.v_max <= 0) return 0.0;
  return rupture_distance(std::max(l.theta, l.theta_r()), double(l.v_max) * liquid_unit_m3);
}

double damping_factor(double e) {
  if (e <= 0.0) return std::sqrt(5.0);  // §1: phi_n = sqrt(5) for e = 0
  const double pi = 3.14159265358979323846;
  double l = std::log(e);
  return std::sqrt(5.0 * l * l / (l * l + pi * pi));
}

EffectiveModuli effective_moduli(double E, double G) {
  EffectiveModuli m;
  m.nu = E / (2.0 * G) - 1.0;
  m.E_star = E / (2.0 * (1.0 - m.nu * m.nu));
  m.G_star = G / (2.0 * (2.0 - m.nu));
  return m;
}

double rayleigh_time(double r, double rho, double G, double nu) {
  const double pi = 3.14159265358979323846;
  return pi * r * std::sqrt(rho / G) / (0.1631 * nu + 0.8766);  // §6
}

}  // namespace wetdem
