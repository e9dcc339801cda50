#version 460
#extension GL_GOOGLE_include_directive : require
// At upload only (issue 12; MercuryDPM's initialiseSolve runs its formation check once): flag the §5 events of
// the uploaded positions exactly as pair_force (pairs) and wall_contact (walls) flag them at the end of a
// step, without forces or springs; the liquid passes 4a-4e then apply them, so pairs touching in the uploaded
// state bridge at t = 0 instead of waiting for a separation and a new touch. Per particle: its owner entries
// (the owner is the lower id, whose segment holds the entry) and its three walls.
#include "walls.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity();
  P = PRM_OF(i, s);
  Uints off = Uints(paddr(s, PF_NOFFSET)), cnt = Uints(paddr(s, PF_NCOUNT));
  Uints mirror = Uints(eaddr(s, EF_MIRROR)), flags = Uints(eaddr(s, EF_FLAGS));
  Uints nbr = Uints(eaddr(s, EF_NBR));
  Int64s liq = Int64s(eaddr(s, EF_LIQ));
  IVec4s pos = IVec4s(paddr(s, PF_POS));
  Vec4s props = Vec4s(paddr(s, PF_PROPS)), frac = Vec4s(paddr(s, PF_FRAC));
  vec4 pi = props.v[i], fi = frac.v[i];
  uint b = off.v[i], c = cnt.v[i];
  if (P.lpp.enabled != 0u) {
    for (uint e = b; e < b + c; ++e) {
      if (mirror.v[e] != e) continue;
      uint j = nbr.v[e];
      vec4 pj = props.v[j], fj = frac.v[j];
      ivec3 D = tick_delta(pos.v[i].xyz, pos.v[j].xyz, P.period_ticks);
      vec3 n;
      float dist;
      float delta = pair_overlap_ticks(D, fi.xyz - fj.xyz, floatBitsToInt(pi.w) + floatBitsToInt(pj.w),
                                       fi.w + fj.w, n, dist) *
                    P.h;
      float S = -delta;
      int64_t vb = liq.v[e];
      uint fl = flags.v[e] & FLAG_WIC;
      if (vb > 0 && S >= rupture_gap(P.lpp, vb)) fl |= FLAG_RUPT;
      if (vb == 0 && (fl & FLAG_WIC) == 0u && delta >= 0.0) fl |= FLAG_FORM;
      if (vb == 0 && S > 0.0) fl &= ~FLAG_WIC;
      flags.v[e] = fl;
    }
  }
  Int64s wliq = Int64s(paddr(s, PF_WLIQ));
  Uints wfl = Uints(paddr(s, PF_WFLAGS));
  for (uint w = 0u; w < 3u; ++w) {
    Liquid L = P.lpw[w];
    float delta, wom;
    vec3 n;
    if (L.enabled == 0u ||
        !wall_geometry(w, pos.v[i].xyz, fi.xyz, floatBitsToInt(pi.w), fi.w, P, delta, n, wom))
      continue;
    uint k = wall_slot(i, w, P);
    float S = -delta;
    int64_t vb = wliq.v[k];
    uint fl = wfl.v[k] & FLAG_WIC;
    if (vb > 0 && S >= rupture_gap(L, vb)) fl |= FLAG_RUPT;
    if (vb == 0 && (fl & FLAG_WIC) == 0u && delta >= 0.0) fl |= FLAG_FORM;
    if (vb == 0 && S > 0.0) fl &= ~FLAG_WIC;
    wfl.v[k] = fl;
  }
}
