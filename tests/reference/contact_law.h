// Contact laws of the CPU reference, double precision, one small function per formula of
// ../shared/spec/physics.md (§1 Hertz, §2 Mindlin, §3 rolling, §4 Willett capillary).
// Nothing here knows about particles or walls: callers build a ContactKinematics (pairs in
// reference_system.cpp, walls in walls.cpp) and call evaluate_contact.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "reference/reference.h"
#include "wetdem/params.h"

namespace wetdem::ref {

// §1: Hertz stiffness k_n = (4/3) E* sqrt(R* delta).
double hertz_stiffness(double E_star, double R_star, double delta);
// §1: F_n = k_n delta - eta_n v_n with eta_n = phi_n sqrt(m* k_n); unclipped (may be negative).
double hertz_normal_force(const ContactParams& cp, double R_star, double m_star, double delta, double v_n);
// §1 integrated: elastic energy of a Hertz contact, (8/15) E* sqrt(R*) delta^(5/2) (tests only).
double hertz_energy(double E_star, double R_star, double delta);
// §2: k_t = 8 G* sqrt(R* delta).
double tangential_stiffness(double G_star, double R_star, double delta);

// §2 step 1 / §3 step 2: xi <- xi - (xi.n) n, rescaled to the old |xi|. A spring that has (almost) no
// component in the plane (|xi_perp| <= 1e-12 |xi|) cannot be rotated and is set to zero [ours].
glm::dvec3 rotate_into_plane(const glm::dvec3& xi, const glm::dvec3& n);

// §2: Mindlin sliding friction with history. Updates the spring xi and returns F_t. f_n is F_n of §1
// (only |F_n| enters the Coulomb limit). Caller guarantees delta > 0 and mu_s > 0.
glm::dvec3 sliding_friction(const ContactParams& cp, double k_t, double m_star, double f_n,
                            const glm::dvec3& n, const glm::dvec3& v_t, double dt, glm::dvec3& xi);

// §3: rolling resistance, rolling stiffness = k_t. w_rel = omega_i - omega_j (a wall contributes its own
// omega). Updates xi_r and returns the pure torque t on i (-t on j). Caller guarantees delta > 0, mu_r > 0.
glm::dvec3 rolling_torque(const ContactParams& cp, double k_t, double R_star, double f_n, const glm::dvec3& n,
                          const glm::dvec3& w_rel, double dt, glm::dvec3& xi_r);

// §4: pull-off force f0 = 2 pi R_h gamma cos(theta).
double pull_off_force(double R_h, double gamma, double theta);
// §4: capillary force magnitude at surface gap S for bridge volume V (m^3): f0 for S <= 0 (delta >= 0),
// else f0 / (1 + 1.05 Sbar + 2.5 Sbar^2) with Sbar = S sqrt(R_h / V). 0 when V = 0.
double capillary_force(double f0, double R_h, double volume_m3, double gap);
// §4: harmonic-mean radius R_h = 2 r_i r_j / (r_i + r_j) of a pair (a wall bridge uses R_h = 2 r_i).
double harmonic_radius(double r_i, double r_j);

// Candidate effect `viscous` (Pitois et al. 2000; diagnosis.md §3): normal lubrication force on i along n,
// F = -6 pi eta R*^2 v_n / S (1 - 1/sqrt(1 + V/(pi R* S^2)))^2 with S = max(gap, S_min) (S = S_min while
// overlapping): opposes the normal relative velocity v_n. 0 when V = 0 or eta = 0.
double lubrication_force(double eta, double s_min, double R_star, double volume_m3, double gap, double v_n);
// Candidate effect `cohesion` (JKR pull-off, diagnosis.md §3): F_a = 1.5 pi w R*, attraction while delta > 0.
double adhesion_force(double surface_energy, double R_star);

// Geometry and kinematics of one contact (pair or particle-wall), §0.
struct ContactKinematics {
  glm::dvec3 n{0.0};      // unit normal from j to i
  double delta = 0.0;     // overlap (negative: gap)
  glm::dvec3 r_ci{0.0};   // c - x_i
  glm::dvec3 r_cj{0.0};   // c - x_j (a wall: unused, torque_j left 0)
  glm::dvec3 v_rel{0.0};  // v_i(c) - v_j(c)
  glm::dvec3 w_rel{0.0};  // omega_i - omega_j
  double R_star = 0.0, m_star = 0.0, R_h = 0.0;
};

// Kinematics of the pair (i, j), §0: d = x_i - x_j (x_j as its minimum image), n = d/|d|,
// c = x_i - (r_i - delta/2) n, R* = r_i r_j/(r_i + r_j), m* = m_i m_j/(m_i + m_j), R_h harmonic. |d| > 0.
ContactKinematics pair_kinematics(const glm::dvec3& d, double r_i, double r_j, double m_i, double m_j,
                                  const glm::dvec3& v_i, const glm::dvec3& v_j, const glm::dvec3& w_i,
                                  const glm::dvec3& w_j);

// Persistent state the contact laws read and write.
struct ContactHistory {
  glm::dvec3 spring_t{0.0}, spring_r{0.0};
  int64_t bridge = 0;  // liquid units
};

// Everything of §1-§4 for one contact, in the order of §0 (normal, sliding, rolling, capillary):
// - while delta > 0: Hertz; springs updated only where mu > 0;
// - springs kept while the gap S = -delta < range (interaction range of §4, 0 when dry), zeroed otherwise;
// - capillary force while the bridge holds liquid and the gap is below range (rupture itself is the event
//   pass' job), with cos(theta_r) instead of cos(theta) once separated (hysteresis);
// - candidate effects after it: lubrication on a bridged contact (viscous), JKR adhesion while delta > 0.
// Returns the force on i and the torques T_i = t + r_ci x F, T_j = -t - r_cj x F.
PairForce evaluate_contact(const ContactParams& cp, const LiquidParams& lp, double liquid_unit_m3,
                           double range, double dt, const ContactKinematics& k, ContactHistory& h);

}  // namespace wetdem::ref
