#include "reference/contact_law.h"

#include <algorithm>
#include <cmath>

namespace wetdem::ref {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double hertz_stiffness(double E_star, double R_star, double delta) {
  return 4.0 / 3.0 * E_star * std::sqrt(R_star * delta);  // §1
}

double hertz_normal_force(const ContactParams& cp, double R_star, double m_star, double delta, double v_n) {
  const double k_n = hertz_stiffness(cp.E_star, R_star, delta);
  const double eta_n = damping_factor(cp.restitution) * std::sqrt(m_star * k_n);  // §1
  return k_n * delta - eta_n * v_n;                                               // §1: not clipped at zero
}

double hertz_energy(double E_star, double R_star, double delta) {
  // integral of (4/3) E* sqrt(R*) d^(3/2) from 0 to delta
  return 8.0 / 15.0 * E_star * std::sqrt(R_star) * std::pow(delta, 2.5);
}

double tangential_stiffness(double G_star, double R_star, double delta) {
  return 8.0 * G_star * std::sqrt(R_star * delta);  // §2
}

glm::dvec3 rotate_into_plane(const glm::dvec3& xi, const glm::dvec3& n) {
  const double len = glm::length(xi);
  if (len == 0.0) return xi;
  const glm::dvec3 p = xi - glm::dot(xi, n) * n;  // §2 step 1
  const double lp = glm::length(p);
  if (lp <= 1e-12 * len) return glm::dvec3(0.0);
  return p * (len / lp);
}

glm::dvec3 sliding_friction(const ContactParams& cp, double k_t, double m_star, double f_n,
                            const glm::dvec3& n, const glm::dvec3& v_t, double dt, glm::dvec3& xi) {
  xi = rotate_into_plane(xi, n);                   // §2.1
  xi += v_t * dt;                                  // §2.2
  const glm::dvec3 f_e = -(2.0 / 3.0) * k_t * xi;  // §2.3
  const double limit = cp.mu_s * std::fabs(f_n);
  const double le = glm::length(f_e);
  if (le < limit) {  // §2.4 sticking
    const double eta_t = cp.phi_t * std::sqrt(m_star * k_t);
    return f_e - eta_t * v_t;
  }
  // §2.4 sliding. [ours] F_e = 0 here only when xi = 0 and F_n = 0: no direction, no force.
  if (le == 0.0) return glm::dvec3(0.0);
  const glm::dvec3 f_t = limit * f_e / le;
  xi = -f_t / ((2.0 / 3.0) * k_t);
  return f_t;
}

glm::dvec3 rolling_torque(const ContactParams& cp, double k_t, double R_star, double f_n, const glm::dvec3& n,
                          const glm::dvec3& w_rel, double dt, glm::dvec3& xi_r) {
  const glm::dvec3 v_r = -R_star * glm::cross(n, w_rel);  // §3.1
  xi_r = rotate_into_plane(xi_r, n);                      // §3.2
  xi_r += v_r * dt;
  glm::dvec3 f_r = -k_t * xi_r - cp.eta_r * v_r;  // §3.3
  const double limit = cp.mu_r * std::fabs(f_n);
  const double lr = glm::length(f_r);
  if (lr > limit) {  // §3.4 (lr > limit >= 0, so lr > 0)
    f_r = limit * f_r / lr;
    xi_r = -(f_r + cp.eta_r * v_r) / k_t;
  }
  return R_star * glm::cross(n, f_r);  // §3.5
}

double pull_off_force(double R_h, double gamma, double theta) {
  return 2.0 * kPi * R_h * gamma * std::cos(theta);  // §4
}

double capillary_force(double f0, double R_h, double volume_m3, double gap) {
  if (volume_m3 <= 0.0) return 0.0;
  if (gap <= 0.0) return f0;  // §4: constant f0 at any overlap (delta >= 0)
  const double s = gap * std::sqrt(R_h / volume_m3);
  return f0 / (1.0 + 1.05 * s + 2.5 * s * s);
}

double lubrication_force(double eta, double s_min, double R_star, double volume_m3, double gap, double v_n) {
  if (eta <= 0.0 || volume_m3 <= 0.0) return 0.0;
  const double S = std::max(gap, s_min);  // [ours] the cut-off also stands for the film of an overlap
  const double b = 1.0 - 1.0 / std::sqrt(1.0 + volume_m3 / (kPi * R_star * S * S));
  return -6.0 * kPi * eta * R_star * R_star * v_n / S * b * b;  // Pitois 2000, truncated at the wetted radius
}

double adhesion_force(double surface_energy, double R_star) {
  return 1.5 * kPi * surface_energy * R_star;  // JKR pull-off
}

double harmonic_radius(double r_i, double r_j) {
  return 2.0 * r_i * r_j / (r_i + r_j);
}

ContactKinematics pair_kinematics(const glm::dvec3& d, double r_i, double r_j, double m_i, double m_j,
                                  const glm::dvec3& v_i, const glm::dvec3& v_j, const glm::dvec3& w_i,
                                  const glm::dvec3& w_j) {
  ContactKinematics k;
  const double dist = glm::length(d);
  k.n = d / dist;  // §0: from j to i
  k.delta = r_i + r_j - dist;
  k.r_ci = -(r_i - 0.5 * k.delta) * k.n;  // c - x_i
  k.r_cj = k.r_ci + d;                    // c - x_j
  k.v_rel = v_i + glm::cross(w_i, k.r_ci) - v_j - glm::cross(w_j, k.r_cj);
  k.w_rel = w_i - w_j;
  k.R_star = r_i * r_j / (r_i + r_j);
  k.m_star = m_i * m_j / (m_i + m_j);
  k.R_h = harmonic_radius(r_i, r_j);
  return k;
}

PairForce evaluate_contact(const ContactParams& cp, const LiquidParams& lp, double liquid_unit_m3,
                           double range, double dt, const ContactKinematics& k, ContactHistory& h) {
  PairForce out;
  out.overlap = k.delta;
  glm::dvec3 f(0.0), t(0.0);
  const double gap = -k.delta;
  if (k.delta > 0.0) {
    // §1 normal force
    const double v_n = glm::dot(k.v_rel, k.n);
    const double f_n = hertz_normal_force(cp, k.R_star, k.m_star, k.delta, v_n);
    out.normal_force = f_n;
    f += f_n * k.n;
    const double k_t = tangential_stiffness(cp.G_star, k.R_star, k.delta);
    // §2 sliding friction
    if (cp.mu_s > 0.0) {
      const glm::dvec3 v_t = k.v_rel - v_n * k.n;
      f += sliding_friction(cp, k_t, k.m_star, f_n, k.n, v_t, dt, h.spring_t);
    }
    // §3 rolling resistance
    if (cp.mu_r > 0.0) t = rolling_torque(cp, k_t, k.R_star, f_n, k.n, k.w_rel, dt, h.spring_r);
  }
  // §2/§3: springs survive only inside the interaction range (range = 0 when dry: dropped once S >= 0;
  // [ours] at exactly S = range the pair counts as out of range). A spring not updated above is left as is.
  if (gap >= range) {
    h.spring_t = glm::dvec3(0.0);
    h.spring_r = glm::dvec3(0.0);
  }
  // §4 capillary force, after friction; never enters the Coulomb limits above. Only inside the interaction
  // range, as MercuryDPM (its neighbour search no longer sees a pair with S >= S_c,max): a V_max bridge
  // (S_c = S_c,max) does not pull in the step in which it ruptures; a smaller bridge (S_c < S_c,max) does
  // (docs/closed-slice.md).
  if (h.bridge > 0 && gap < range) {
    // Hysteresis: a separated bridge (gap > 0) is receding and pulls with cos(theta_r).
    const double f0 = pull_off_force(k.R_h, lp.gamma, gap > 0.0 ? lp.theta_r() : lp.theta);
    const double volume = double(h.bridge) * liquid_unit_m3;
    const double fc = capillary_force(f0, k.R_h, volume, gap);
    f -= fc * k.n;
    const double v_n = glm::dot(k.v_rel, k.n);
    f += lubrication_force(lp.viscosity, lp.lubrication_cutoff, k.R_star, volume, gap, v_n) * k.n;
  }
  if (k.delta > 0.0 && cp.surface_energy > 0.0) f -= adhesion_force(cp.surface_energy, k.R_star) * k.n;
  out.force = f;
  out.torque_i = t + glm::cross(k.r_ci, f);
  out.torque_j = -t - glm::cross(k.r_cj, f);
  return out;
}

}  // namespace wetdem::ref
