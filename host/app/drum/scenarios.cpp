#include "app/drum/scenarios.h"

#include <cmath>

#include "app/drum/fill.h"

namespace wetdem {

void set_polypropylene_contacts(SimParams& prm, double mu_s, double mu_r, double r_min, double rho) {
  const double G = 400e6 / 1000.0;
  EffectiveModuli m = effective_moduli(1325e6 / 1000.0, G);
  prm.pp.E_star = m.E_star;
  prm.pp.G_star = m.G_star;
  prm.pp.restitution = 0.5;
  prm.pp.mu_s = mu_s;
  prm.pp.mu_r = mu_r;
  for (auto& w : prm.pw) w = prm.pp;
  prm.dt = 0.2 * rayleigh_time(r_min, rho, G, m.nu);
}

Scenario tumbling_wet_slice(size_t n, uint64_t seed, double speed) {
  constexpr double kPi = 3.14159265358979323846;
  Scenario sc;
  SimParams& prm = sc.prm;
  const double r_lo = 0.9e-3, r_hi = 1.1e-3, rho = 900.0;
  // Drum radius for a ~30 % bed (solid fraction 0.6) of n particles in a slice 12 particle diameters thick.
  const double L = 12 * 2 * r_hi;
  const double v_mean = 4.0 / 3.0 * kPi * std::pow(1e-3, 3);
  const double R = std::sqrt(double(n) * v_mean / (0.6 * 0.30 * kPi * L));
  set_polypropylene_contacts(prm, 0.5, 0.1, r_lo, rho);
  prm.drum.radius = R;
  prm.drum.length = L;
  prm.drum.periodic_z = true;
  prm.drum.omega = 6.0;  // ~57 rpm: a cascading bed, contacts open and close everywhere
  prm.liquid_unit_m3 = v_mean * std::ldexp(1.0, -40);
  LiquidParams l;
  l.enabled = true;
  l.gamma = 0.0217 * 5;
  l.theta = 30.0 * kPi / 180.0;
  l.v_min = 0;
  l.v_max = int64_t(0.0005 * std::ldexp(1.0, 40));
  l.d_c = 0.9;
  prm.liq_pp = l;
  prm.liq_pw[kWallCylinder] = l;

  uint64_t z = seed * 0x9E3779B97F4A7C15ull + 1;
  auto uni = [&z] {  // splitmix64: portable, deterministic
    z += 0x9E3779B97F4A7C15ull;
    uint64_t x = z;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    x ^= x >> 31;
    return double(x >> 11) * 0x1.0p-53;
  };
  std::vector<double> radii(n);
  for (auto& r : radii) r = r_lo + (r_hi - r_lo) * uni();
  FillSpec fs;
  fs.drum_radius = R;
  fs.drum_length = L;
  fs.periodic_z = true;
  fs.count = n;
  fs.seed = seed;
  FillResult fr = fill_drum(fs, radii);
  sc.state.p.resize(fr.x.size());
  for (size_t k = 0; k < fr.x.size(); ++k) {
    set_sphere(sc.state.p, k, fr.x[k], fr.radius[k], rho);
    const double v = 4.0 / 3.0 * kPi * std::pow(fr.radius[k], 3);
    sc.state.p.film[k] = int64_t(0.02 * v / prm.liquid_unit_m3);
    sc.state.p.v[k] = speed * glm::dvec3(2 * uni() - 1, 2 * uni() - 1, 2 * uni() - 1);
  }
  return sc;
}

}  // namespace wetdem
