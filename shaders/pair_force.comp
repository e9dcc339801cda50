#version 460
#extension GL_GOOGLE_include_directive : require
// Pass 2: one invocation per owner entry (the owner list) evaluates its pair (physics.md §1-4) and writes the
// force and torque on i at its entry, on j at the mirrored entry; the per-particle gather sums them in list
// order (no atomics).
// Also flags the liquid events the end-of-step passes will apply (§5), from the same positions.
#include "geom.glsl"
#include "contact_law.glsl"
layout(local_size_x = 256) in;
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (halted()) return;
  if (k >= CTL().v[CTL_OWNERS]) return;
  uint e = Uints(T().owners).v[k];
  uint s = parity();
  uint i = Uints(eaddr(s, EF_SELF)).v[e], j = Uints(eaddr(s, EF_NBR)).v[e];
  Params P = PRM_OF(i, s);
  Int64s liq = Int64s(eaddr(s, EF_LIQ));
  Uints flags = Uints(eaddr(s, EF_FLAGS));

  vec4 pi = load_v4(paddr(s, PF_PROPS), i), pj = load_v4(paddr(s, PF_PROPS), j);
  vec4 fi = load_v4(paddr(s, PF_FRAC), i), fj = load_v4(paddr(s, PF_FRAC), j);
  ivec3 D = tick_delta(load_i4(paddr(s, PF_POS), i).xyz, load_i4(paddr(s, PF_POS), j).xyz, P.period_ticks);
  vec3 n;
  float dist;
  float delta = pair_overlap_ticks(D, fi.xyz - fj.xyz, floatBitsToInt(pi.w) + floatBitsToInt(pj.w), fi.w + fj.w, n,
                                   dist) * P.h;
  float S = -delta;
  vec4 sp = load_v4(eaddr(s, EF_ST), e);  // springs (t, r.x), (r.y, r.z): access.glsl
  vec3 st = sp.xyz, sr = vec3(sp.w, load_v2(eaddr(s, EF_SR), e));
  int64_t vb = liq.v[e];
  uint fl = flags.v[e] & FLAG_WIC;

  vec3 F = vec3(0.0), t = vec3(0.0);
  vec3 ci = -(pi.x - 0.5 * delta) * n;  // c - x_i
  vec3 cj = (pj.x - 0.5 * delta) * n;   // c - x_j
  if (S >= P.lpp.range) {  // outside the interaction range: springs dropped (§2)
    st = vec3(0.0);
    sr = vec3(0.0);
  }
  if (delta > 0.0) {
    float Rs = pi.x * pj.x / (pi.x + pj.x);
    float ms = pi.y * pj.y / (pi.y + pj.y);
    vec3 wi = load_v4(paddr(s, PF_OMG), i).xyz, wj = load_v4(paddr(s, PF_OMG), j).xyz;
    vec3 vi = load_v4(paddr(s, PF_VEL), i).xyz, vj = load_v4(paddr(s, PF_VEL), j).xyz;
    vec3 vrel = vi + cross(wi, ci) - vj - cross(wj, cj);
    contact_force(P.pp, P.dt, n, delta, Rs, ms, vrel, wi - wj, st, sr, F, t);
  }
  Effects X = P.fx[0];
  // Capillary force after friction (§0 order, §4); a separated bridge pulls with theta_r. Only inside the
  // interaction range, as MercuryDPM: a V_max bridge does not pull in its rupture step (docs/closed-slice.md).
  if (vb > 0 && S < P.lpp.range) {
    float Rh = 2.0 * pi.x * pj.x / (pi.x + pj.x);
    float f0 = (S > 0.0 ? X.f0r_per_Rh : P.lpp.f0_per_Rh) * Rh;
    float f = capillary_force(S, Rh, float(vb) * P.lpp.unit_m3, f0);
    F -= f * n;
    if (X.visc_eta > 0.0) {  // `viscous`: lubrication opposing the normal relative velocity
      float Rs = pi.x * pj.x / (pi.x + pj.x);
      vec3 dv = load_v4(paddr(s, PF_VEL), i).xyz - load_v4(paddr(s, PF_VEL), j).xyz;
      float vn = dot(dv, n);  // omega x (c - x) has no normal part
      F -= lubrication_coef(X, S, Rs, float(vb) * P.lpp.unit_m3) * vn * n;
    }
  }
  if (delta > 0.0 && X.adhesion > 0.0) {  // `cohesion`: JKR pull-off 1.5 pi w R*, outside the Coulomb limit
    F -= X.adhesion * (pi.x * pj.x / (pi.x + pj.x)) * n;
  }
  if (P.lpp.enabled != 0u) {  // §5 event flags at the end-of-step positions
    // S_c(V) <= S_c,max = range; the second test only guards float rounding of the two (a bridge never
    // survives outside the range without pulling).
    if (vb > 0 && (S >= rupture_gap(P.lpp, vb) || S >= P.lpp.range)) fl |= FLAG_RUPT;
    if (vb == 0 && (fl & FLAG_WIC) == 0u && delta >= 0.0) fl |= FLAG_FORM;
    if (vb == 0 && S > 0.0) fl &= ~FLAG_WIC;
    // Candidates for the liquid gate of the fused step (gather_kick's last workgroup).
    uint cand = ((fl & FLAG_RUPT) != 0u ? CAND_RUPT : 0u) | ((fl & FLAG_FORM) != 0u ? CAND_FORM : 0u);
    if (cand != 0u) atomicOr(CTL().v[CTL_CAND_PAIR], cand);
  }
  store_v4(eaddr(s, EF_ST), e, vec4(st, sr.x));
  store_v2(eaddr(s, EF_SR), e, sr.yz);
  flags.v[e] = fl;
  uint m = Uints(T().partner).v[e];  // the mirrored entry, in j's segment
  // Force and torque of each entry as (F, T.x) in pair_f and (T.y, T.z) in pair_t (buffer_set.h).
  vec3 ti = t + cross(ci, F), tj = -t - cross(cj, F);
  store_v4(T().pair_f, e, vec4(F, ti.x));
  store_v2(T().pair_t, e, ti.yz);
  store_v4(T().pair_f, m, vec4(-F, tj.x));
  store_v2(T().pair_t, m, tj.yz);
}
