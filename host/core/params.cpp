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

int64_t pore_capacity_units(double capacity, double radius, double unit) {
  const double pi = 3.14159265358979323846;
  if (!(capacity > 0.0)) return 0;
  return int64_t(std::floor(capacity * 4.0 / 3.0 * pi * radius * radius * radius / unit));
}

uint64_t loss_fraction_q64(double x) {
  if (!(x > 0.0)) return 0;
  const double a = -std::expm1(-x);    // 1 - e^-x without cancellation for small x
  const double q = std::ldexp(a, 64);  // exact scaling; a < 1 so q < 2^64 unless a rounds to 1
  if (q >= 18446744073709551615.0) return ~uint64_t(0);
  return uint64_t(q);
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
