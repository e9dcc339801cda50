// Simulation parameters shared by the GPU system and the CPU reference.
// Plain structs, SI units, zero/default value = documented default (VkFFT style).
// The formulas these feed are in ../shared/spec/physics.md (cited as §N below).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <string>

namespace wetdem {

// Contact-law coefficients of one interaction type (particle-particle, or particle-wall).
struct ContactParams {
  double E_star = 0.0;       // effective Young's modulus E* (Pa), §1
  double G_star = 0.0;       // effective shear modulus G* (Pa), §2
  double restitution = 0.5;  // e, gives phi_n = sqrt(5 ln^2 e / (ln^2 e + pi^2)), §1
  double mu_s = 0.0;         // sliding friction coefficient, §2 (0 = frictionless, no spring kept)
  double mu_r = 0.0;         // rolling friction coefficient, §3 (0 = off)
  double phi_t = 0.0;        // tangential damping factor, eta_t = phi_t sqrt(m* k_t), §2
  double eta_r = 0.0;        // rolling viscous coefficient (kg/s), §3
  // Candidate effect `cohesion` (diagnosis.md §3, docs/model.md "Candidate effects"): dry JKR adhesion,
  // pull-off F_a = 1.5 pi w R*, attractive along n while touching (delta > 0), outside the Coulomb limits. 0
  // = off.
  double surface_energy = 0.0;  // w (J/m^2), already scaled by l like gamma (w_scaled = l w)
};

// Liquid-bridge coefficients of one interaction type, §4-5. Volumes are fixed-point integers
// in units of SimParams::liquid_unit_m3 so that total liquid is conserved exactly.
struct LiquidParams {
  bool enabled = false;  // particle-particle: bridges on; a wall: particle-wall bridges on
  double gamma = 0.0;    // surface tension (N/m), already scaled by l (gamma_scaled = l gamma)
  double theta = 0.0;    // contact angle (rad)
  int64_t v_min = 0;     // formation threshold: V_f,i + V_f,j > v_min (units)
  int64_t v_max = 0;     // bridge volume cap (units)
  double d_c = 1.0;      // distribution coefficient on rupture, [0, 1]
  // Candidate effects (diagnosis.md §3, docs/model.md "Candidate effects"), off by default:
  // `viscous`: Pitois lubrication of bridged pairs, F_v = 6 pi eta R*^2 v_n / S (1 - 1/sqrt(1 + V_b/(pi R*
  // S^2)))^2 with S = max(gap, S_min) (S = S_min while overlapping), opposing v_n. 0 = off.
  double viscosity = 0.0;           // eta (Pa s)
  double lubrication_cutoff = 0.0;  // S_min (m), > 0 when viscosity > 0
  // `hysteresis`: receding angle theta_r: rupture at (1 + theta_r/2) V_b^(1/3), separated bridges (gap > 0)
  // pull with cos(theta_r). < 0 = equal to theta (off).
  double theta_receding = -1.0;  // rad
  double theta_r() const { return theta_receding < 0.0 ? theta : theta_receding; }
};

// Liquid sinks (diagnosis.md §3 `absorption`, `evaporation`), off by default. Each step, before the formation
// phase of §5, a particle moves floor(V_f a_k) of its film into its pores (up to its capacity), then its film
// and each bridge it owns (and its wall bridges) lose floor(V e_t) to its evaporated counter, with a_k = 1 -
// exp(-k dt), e_t = 1 - exp(-dt/tau) as 64-bit fractions (loss_fraction_q64). Integers throughout.
struct LiquidSinkParams {
  double pore_capacity = 0.0;    // absorption.capacity: pore volume / particle volume, [0, 0.3]; 0 = off
  double absorption_rate = 0.0;  // absorption.rate k (1/s); 0 = off; +infinity = instantaneous (all the film)
  double evaporation_time = 0.0;  // liquid.evaporation_time tau (s); 0 = off
  bool absorbs() const { return pore_capacity > 0.0 && absorption_rate > 0.0; }
  bool evaporates() const { return evaporation_time > 0.0; }
};

// One flat end plate of the drum (normal along the drum axis z).
struct PlateParams {
  bool present = true;
  bool rotates = true;  // turns with the drum (angular velocity omega about z) or stays fixed
};

// The drum: a cylinder of radius R about the z axis, centred at the origin, gravity in -y.
struct DrumParams {
  double radius = 0.07;     // inner radius (m)
  double length = 0.18;     // axial length (m); end plates at z = +-length/2
  double omega = 0.0;       // angular velocity about +z (rad/s)
  bool periodic_z = false;  // thin periodic slice: no end plates, z wraps with period `length`
  PlateParams plate_lo, plate_hi;
};

// Index of a wall in per-particle wall state: each particle keeps one record per wall.
enum WallIndex : uint32_t { kWallCylinder = 0, kWallPlateLo = 1, kWallPlateHi = 2, kNumWalls = 3 };

struct SimParams {
  double dt = 1e-5;                     // time step (s), §6
  glm::dvec3 gravity{0.0, -9.81, 0.0};  // m/s^2
  double skin = 0.0;                    // neighbour-list skin (m); rebuild when the two largest displacements
                                        // in the drum's frame add up to it (ARCHITECTURE.md "The skin test");
                                        // 0 = automatic, 0.1 x the smallest radius
  ContactParams pp;                     // particle-particle
  ContactParams pw[kNumWalls];          // particle-wall, per wall
  LiquidParams liq_pp;                  // particle-particle bridges
  LiquidParams liq_pw[kNumWalls];       // particle-wall bridges (off by default)
  double liquid_unit_m3 = 1e-21;        // volume of one liquid unit (m^3); V-bar_S * 2^-40 in drum runs
  DrumParams drum;
  LiquidSinkParams sinks;  // pore absorption and evaporation (off by default)

  // Interaction range of a particle pair beyond contact: S_c,max = (1 + theta/2) V_max^(1/3), §4, with
  // max(theta, theta_r) when the receding angle differs (hysteresis).
  // Zero when particle-particle bridges are off. Springs are dropped beyond it (§2).
  double bridge_range_pp() const;
  double bridge_range_pw(uint32_t wall) const;
};

// Rupture distance of a bridge of volume v (m^3): S_c = (1 + theta/2) V^(1/3), §4.
double rupture_distance(double theta, double volume_m3);
// Pore capacity of a particle of radius r (liquid units): floor(capacity * 4/3 pi r^3 / unit).
int64_t pore_capacity_units(double capacity, double radius, double liquid_unit_m3);
// The fraction 1 - exp(-x) (x >= 0) as a 64-bit fixed-point number floor(2^64 (1 - e^-x)), saturated at
// 2^64 - 1; the per-step loss of a volume V is then floor(V F / 2^64), exact in integers on every device.
uint64_t loss_fraction_q64(double x);
// Normal damping factor phi_n(e), §1.
double damping_factor(double restitution);
// Single-material effective moduli from E and G, §1: nu = E/(2G) - 1, E* = E/(2(1-nu^2)), G* = G/(2(2-nu)).
struct EffectiveModuli {
  double nu, E_star, G_star;
};
EffectiveModuli effective_moduli(double E, double G);
// Rayleigh time of a sphere, §6: t_R = pi r sqrt(rho/G) / (0.1631 nu + 0.8766).
double rayleigh_time(double radius, double density, double G, double nu);

}  // namespace wetdem
