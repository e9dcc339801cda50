#include "wetdem/timestep.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace wetdem {

namespace {
constexpr double kPi = 3.14159265358979323846;

// The pull of a bridge just separated (S -> 0+), whose slope is k_c: cos(theta_r) with hysteresis.
double f0_of(const LiquidParams& l, double R_h) {
  return 2.0 * kPi * R_h * l.gamma * std::cos(l.theta_r());
}
}  // namespace

double capillary_dt_limit(double m_star, double R_h, double f0, double volume_m3) {
  const double k_c = 1.05 * f0 * std::sqrt(R_h / volume_m3);  // §6
  return 0.1 * kPi * std::sqrt(m_star / k_c);
}

int64_t smallest_formable_bridge(const LiquidParams& l, const std::vector<int64_t>& films) {
  int64_t f_min = 0, top1 = 0, top2 = 0;  // smallest positive film, two largest films
  for (int64_t f : films) {
    if (f > 0 && (f_min == 0 || f < f_min)) f_min = f;
    if (f > top1) {
      top2 = top1;
      top1 = f;
    } else if (f > top2) {
      top2 = f;
    }
  }
  if (l.v_max <= 0 || top1 + top2 <= l.v_min) return 0;
  return std::min(std::max(f_min, l.v_min + 1), l.v_max);
}

namespace {

struct Stiffest {
  double limit = 1e300;
  std::string where;
};

void check_present(const SimParams& prm, const SystemState& s, Stiffest& w) {
  const LiquidParams& l = prm.liq_pp;
  for (const PairRecord& r : s.pairs) {
    if (r.bridge <= 0) continue;
    const double ri = s.p.radius[r.id_i], rj = s.p.radius[r.id_j];
    const double mi = s.p.mass[r.id_i], mj = s.p.mass[r.id_j];
    const double R_h = 2.0 * ri * rj / (ri + rj);
    const double lim =
        capillary_dt_limit(mi * mj / (mi + mj), R_h, f0_of(l, R_h), double(r.bridge) * prm.liquid_unit_m3);
    if (lim < w.limit) {
      w.limit = lim;
      w.where = fmt::format("bridge {}-{} of {:.3g} m^3 ({} units)", r.id_i, r.id_j,
                            double(r.bridge) * prm.liquid_unit_m3, r.bridge);
    }
  }
}

std::optional<std::string> verdict(const SimParams& prm, const Stiffest& w) {
  if (prm.dt <= w.limit) return std::nullopt;
  return fmt::format(
      "time step {:.3g} s exceeds the capillary limit 0.1 pi sqrt(m*/k_c) = {:.3g} s of the stiffest bridge "
      "({}), by a factor {:.3g}: divide run.dt_rayleigh_fraction (or run.dt) by at least that factor "
      "(physics.md §6)",
      prm.dt, w.limit, w.where, prm.dt / w.limit);
}

}  // namespace

std::optional<std::string> capillary_timestep_warning_present(const SimParams& prm, const SystemState& s) {
  if (!prm.liq_pp.enabled || s.p.size() == 0) return std::nullopt;
  Stiffest w;
  check_present(prm, s, w);
  return verdict(prm, w);
}

std::optional<std::string> capillary_timestep_warning(const SimParams& prm, const SystemState& s) {
  if (!prm.liq_pp.enabled || s.p.size() == 0) return std::nullopt;
  const LiquidParams& l = prm.liq_pp;
  Stiffest w;
  check_present(prm, s, w);
  // The smallest bridge the films can form, between the two smallest particles: for a given volume the limit
  // grows as m*^1/2 R_h^-3/4, i.e. as r^3/4 for equal spheres, so the smallest particles have the lowest.
  const int64_t v = smallest_formable_bridge(l, s.p.film);
  if (v > 0) {
    size_t a = 0;
    for (size_t k = 1; k < s.p.size(); ++k)
      if (s.p.radius[k] < s.p.radius[a]) a = k;
    const double r = s.p.radius[a], m = s.p.mass[a];
    const double lim = capillary_dt_limit(0.5 * m, r, f0_of(l, r), double(v) * prm.liquid_unit_m3);
    if (lim < w.limit) {
      w.limit = lim;
      w.where = fmt::format(
          "smallest bridge the films can form, {:.3g} m^3 ({} units), between the smallest particles",
          double(v) * prm.liquid_unit_m3, v);
    }
  }
  return verdict(prm, w);
}

double viscous_damping_coefficient(double eta, double s_min, double R_star, double volume_m3) {
  const double b = 1.0 - 1.0 / std::sqrt(1.0 + volume_m3 / (kPi * R_star * s_min * s_min));
  return 6.0 * kPi * eta * R_star * R_star / s_min * b * b;  // dF_v/dv_n at S = S_min (Pitois 2000)
}

double viscous_dt_limit(double m_star, double R_star, double eta, double s_min, double volume_m3) {
  // One damper on m*: v <- v (1 - c dt/m*) is stable for c dt/m* < 2. A particle damped by Z bridged
  // neighbours moving against it sees Z such dampers, which divides the limit by Z; Z = 12 (the kissing
  // number) is the rigorous bound, but only neighbours squeezed to S_min damp that hard at once. Measured on
  // the micro drum (10 % liquid, 30 rpm, 0.5 s of rotation, lavapipe, 24 Nov 2026): at eta = 0.1 Pa s the bed
  // runs stably at 2x, 4x and 8x the Z = 12 step; it blew up at 11x (50 mPa s at dt = 3.8e-4 s). Z = 4 (3x
  // the Z = 12 step) keeps a factor 2.7 below the largest stable step measured.
  constexpr double kZ = 4.0;
  return 2.0 * m_star / (kZ * viscous_damping_coefficient(eta, s_min, R_star, volume_m3));
}

std::optional<std::string> viscous_timestep_warning(const SimParams& prm, const SystemState& s) {
  if (s.p.size() == 0) return std::nullopt;
  size_t a = 0;
  for (size_t k = 1; k < s.p.size(); ++k)
    if (s.p.radius[k] < s.p.radius[a]) a = k;
  const double r = s.p.radius[a], m = s.p.mass[a];
  // m*/c grows with the radius (m* ~ r^3, c ~ R*^2) and with smaller bridges: the two smallest particles with
  // a bridge of V_max are the worst pair; a wall (R* = r, m* = m) is worse still by a factor 2.
  double worst = 1e300;
  std::string where;
  auto consider = [&](const LiquidParams& l, double m_star, double R_star, const char* what) {
    if (!l.enabled || !(l.viscosity > 0) || l.v_max <= 0) return;
    const double lim = viscous_dt_limit(m_star, R_star, l.viscosity, l.lubrication_cutoff,
                                        double(l.v_max) * prm.liquid_unit_m3);
    if (lim < worst) worst = lim, where = what;
  };
  consider(prm.liq_pp, 0.5 * m, 0.5 * r, "two smallest particles with a bridge of V_max");
  for (uint32_t w = 0; w < kNumWalls; ++w)
    consider(prm.liq_pw[w], m, r, "smallest particle bridged to a wall");
  // A default dt is lowered to exactly this limit (case_params.cpp, the same formula): at the limit is fine.
  // The tolerance absorbs the rounding between the case's r_min and the smallest radius drawn.
  if (prm.dt <= worst * (1.0 + 1e-9)) return std::nullopt;
  return fmt::format(
      "time step {:.3g} s exceeds the viscous limit 2 m*/(4 c) = {:.3g} s (c = dF_v/dv_n at S_min; {}): the "
      "explicit lubrication damping is unstable; lower dt or raise liquid.lubrication_cutoff",
      prm.dt, worst, where);
}

}  // namespace wetdem
