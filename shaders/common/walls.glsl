// Particle-wall contacts (physics.md §0-4): the drum cylinder (radius R about +z) and the two end plates
// (z = -+L/2). The wall is body j; R* = r_i, m* = m_i, R_h = 2 r_i. Each particle keeps one spring pair,
// bridge and flag word per wall, so wall contacts are evaluated by the particle's own invocation.
#ifndef WETDEM_WALLS_GLSL
#define WETDEM_WALLS_GLSL
#include "geom.glsl"
#include "contact_law.glsl"

// Overlap (m) and normal (from the wall into the particle) of a particle at p (ticks) with radius r_t (ticks)
// against wall w; false when the wall is absent. Overlaps come from exact integers before one float
// division, so they keep float32 relative precision (ARCHITECTURE.md "Precision").
bool wall_geometry(uint w, ivec3 p, vec3 pf, int r_t, float r_f, Params P, out float delta, out vec3 n,
                   out float wall_omega) {
  if (w == 0u) {
    // delta = r - (R - rho) = (rho^2 - A^2) / (rho + A), A = R - r: exact integer parts, float corrections.
    int64_t P2 = int64_t(p.x) * int64_t(p.x) + int64_t(p.y) * int64_t(p.y);
    vec2 pv = vec2(p.xy);
    float corr = 2.0 * dot(pv, pf.xy) + dot(pf.xy, pf.xy);  // rho^2 = P2 + corr
    float rho = sqrt(float(P2) + corr);
    if (rho <= 0.0) return false;
    int64_t Ai = int64_t(P.drum_r_ticks) - int64_t(r_t);
    float Af = P.drum_r_frac - r_f;
    float num = float(P2 - Ai * Ai) + corr - (2.0 * float(Ai) * Af + Af * Af);
    delta = num / (rho + float(Ai) + Af) * P.h;
    n = -vec3(pv + pf.xy, 0.0) / rho;
    wall_omega = P.omega;
    return true;
  }
  uint k = w - 1u;
  if (P.period_ticks > 0 || P.plate_present[k] == 0u) return false;
  // Plates sit at whole ticks (+-plate_z_ticks): integer part exact, fractions added after.
  if (k == 0u) {
    delta = (float(int64_t(r_t) - int64_t(p.z) - int64_t(P.plate_z_ticks)) + (r_f - pf.z)) * P.h;
    n = vec3(0.0, 0.0, 1.0);
  } else {
    delta = (float(int64_t(r_t) - int64_t(P.plate_z_ticks) + int64_t(p.z)) + (r_f + pf.z)) * P.h;
    n = vec3(0.0, 0.0, -1.0);
  }
  wall_omega = P.plate_rotates[k] != 0u ? P.omega : 0.0;
  return true;
}

// Force and torque of wall w on particle i; updates that wall's springs and event flags.
void wall_contact(uint w, uint i, uint s, Params P, inout vec3 F, inout vec3 Tq) {
  ivec3 p = load_i4(paddr(s, PF_POS), i).xyz;
  vec4 pr = load_v4(paddr(s, PF_PROPS), i);
  float delta, wom;
  vec3 n;
  vec4 pf = load_v4(paddr(s, PF_FRAC), i);
  if (!wall_geometry(w, p, pf.xyz, floatBitsToInt(pr.w), pf.w, P, delta, n, wom)) return;
  Int64s wliq = Int64s(paddr(s, PF_WLIQ));
  Uints wfl = Uints(paddr(s, PF_WFLAGS));
  uint k = wall_slot(i, w, P);
  float r = pr.x;
  float S = -delta;
  Liquid L = P.lpw[w];
  vec3 st = load_v4(paddr(s, PF_WST), k).xyz, sr = load_v4(paddr(s, PF_WSR), k).xyz;
  int64_t vb = wliq.v[k];
  uint fl = wfl.v[k] & FLAG_WIC;
  if (S >= L.range) {
    st = vec3(0.0);
    sr = vec3(0.0);
  }
  vec3 ci = -(r - 0.5 * delta) * n;
  vec3 Fw = vec3(0.0), t = vec3(0.0);
  if (delta > 0.0) {
    vec3 xi = (vec3(p) + pf.xyz) * P.h;
    vec3 wom3 = vec3(0.0, 0.0, wom);
    vec3 vw = cross(wom3, xi + ci);  // wall surface velocity at the contact point
    vec3 wi = load_v4(paddr(s, PF_OMG), i).xyz;
    vec3 vrel = load_v4(paddr(s, PF_VEL), i).xyz + cross(wi, ci) - vw;
    contact_force(P.pw[w], P.dt, n, delta, r, pr.y, vrel, wi - wom3, st, sr, Fw, t);
  }
  Effects X = P.fx[1u + w];
  if (vb > 0 && S < L.range) {  // only inside the interaction range (pair_force.comp)
    float Rh = 2.0 * r;
    float f0 = (S > 0.0 ? X.f0r_per_Rh : L.f0_per_Rh) * Rh;  // hysteresis: theta_r once separated
    Fw -= capillary_force(S, Rh, float(vb) * L.unit_m3, f0) * n;
    if (X.visc_eta > 0.0) {  // `viscous`, R* = r; the wall's surface velocity has no normal part
      float vn = dot(Vec4s(paddr(s, PF_VEL)).v[i].xyz, n);
      Fw -= lubrication_coef(X, S, r, float(vb) * L.unit_m3) * vn * n;
    }
  }
  if (delta > 0.0 && X.adhesion > 0.0) Fw -= X.adhesion * r * n;  // `cohesion`, R* = r
  if (L.enabled != 0u) {
    if (vb > 0 && (S >= rupture_gap(L, vb) || S >= L.range)) fl |= FLAG_RUPT;
    if (vb == 0 && (fl & FLAG_WIC) == 0u && delta >= 0.0) fl |= FLAG_FORM;
    if (vb == 0 && S > 0.0) fl &= ~FLAG_WIC;
  }
  store_v4(paddr(s, PF_WST), k, vec4(st, 0.0));
  store_v4(paddr(s, PF_WSR), k, vec4(sr, 0.0));
  wfl.v[k] = fl;
  F += Fw;
  Tq += t + cross(ci, Fw);
}
#endif
