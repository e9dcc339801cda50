// Contact laws of physics.md §1-4 in float32. The CPU reference (tests/reference/contact_law.cpp) is an
// independent double-precision implementation of the same formulas.
#ifndef WETDEM_CONTACT_LAW_GLSL
#define WETDEM_CONTACT_LAW_GLSL
#include "params.glsl"

// Rotates a spring into the tangent plane of n keeping its length (§2 step 1, §3 step 2).
vec3 project_keep_length(vec3 xi, vec3 n) {
  float len = length(xi);
  vec3 p = xi - dot(xi, n) * n;
  float plen = length(p);
  return plen > 0.0 ? p * (len / plen) : vec3(0.0);
}

// Hertz normal (§1), Mindlin sliding (§2), rolling resistance (§3) for a touching contact (delta > 0).
// n: unit normal from j to i; vrel: velocity of i relative to j at the contact point; wrel = w_i - w_j.
// Updates the springs st, sr; returns the force on i and the pure rolling torque t on i.
void contact_force(Contact C, float dt, vec3 n, float delta, float Rs, float ms, vec3 vrel, vec3 wrel,
                   inout vec3 st, inout vec3 sr, out vec3 F, out vec3 t) {
  float vn = dot(vrel, n);
  vec3 vt = vrel - vn * n;
  float sRd = sqrt(Rs * delta);
  float kn = (4.0 / 3.0) * C.E_star * sRd;               // §1 k_n = 4/3 E* sqrt(R* delta)
  float Fn = kn * delta - C.phi_n * sqrt(ms * kn) * vn;  // §1 unclipped, eta_n = phi_n sqrt(m* k_n)
  float absFn = abs(Fn);
  F = Fn * n;
  t = vec3(0.0);
  float kt = 8.0 * C.G_star * sRd;  // §2 k_t = 8 G* sqrt(R* delta)
  if (C.mu_s > 0.0) {
    st = project_keep_length(st, n) + vt * dt;
    vec3 Fe = -(2.0 / 3.0) * kt * st;
    float lim = C.mu_s * absFn;
    float fe = length(Fe);
    vec3 Ft;
    if (fe < lim) {
      Ft = Fe - C.phi_t * sqrt(ms * kt) * vt;
    } else {
      Ft = fe > 0.0 ? Fe * (lim / fe) : vec3(0.0);
      st = -Ft / ((2.0 / 3.0) * kt);  // §2: spring truncated to the Coulomb limit
    }
    F += Ft;
  }
  if (C.mu_r > 0.0) {
    vec3 vr = -Rs * cross(n, wrel);  // §3 rolling velocity
    sr = project_keep_length(sr, n) + vr * dt;
    vec3 Fr = -kt * sr - C.eta_r * vr;
    float lim = C.mu_r * absFn;
    float fr = length(Fr);
    if (fr > lim) {
      Fr = Fr * (lim / fr);
      sr = -(Fr + C.eta_r * vr) / kt;
    }
    t = Rs * cross(n, Fr);  // torque capped at mu_r R* |F_n|
  }
}

// Willett capillary force magnitude (§4), attraction: apply as -f n on i. S = gap (m), V = bridge volume
// (m^3), f0 = 2 pi R_h gamma cos(theta).
float capillary_force(float S, float Rh, float V, float f0) {
  if (S <= 0.0) return f0;
  float Sb = S * sqrt(Rh / V);
  return f0 / (1.0 + 1.05 * Sb + 2.5 * Sb * Sb);
}

// Candidate effect `viscous` (Pitois et al. 2000): damping coefficient c = dF_v/dv_n of a bridge of volume V
// (m^3) at surface gap `gap`: c = 6 pi eta R*^2 / S (1 - 1/sqrt(1 + x))^2, x = V / (pi R* S^2),
// S = max(gap, S_min). The force on i is -c v_n n. 1 - 1/sqrt(1 + x) is written x / (sqrt(1 + x)(sqrt(1 + x)
// + 1)) so that float32 keeps its relative precision when x is small (a wide gap).
float lubrication_coef(Effects X, float gap, float Rs, float V) {
  float S = max(gap, X.visc_smin);
  float x = V / (3.14159265 * Rs * S * S);
  float q = sqrt(1.0 + x);
  float a = x / (q * (q + 1.0));
  return 6.0 * 3.14159265 * X.visc_eta * Rs * Rs / S * (a * a);
}

// Rupture distance S_c = (1 + theta/2) V^(1/3) (§4).
float rupture_gap(Liquid L, int64_t v_units) { return L.rupture_coef * pow(float(v_units) * L.unit_m3, 1.0 / 3.0); }
#endif
