#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4b (per owner entry, over the owner list): ruptured bridges empty; surviving bridges take the
// shares of both ends, capped at V_max, the overflow going back to the two films in proportion to the shares (§5 rule 1).
#include "liquid.glsl"
layout(local_size_x = 256) in;
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (halted()) return;
  if (k >= CTL().v[CTL_OWNERS]) return;
  uint e = Uints(T().owners).v[k];
  uint s = parity();
  Params P = PRM_OF(Uints(eaddr(s, EF_SELF)).v[e], s);
  Int64s liq = Int64s(eaddr(s, EF_LIQ));
  Uints flags = Uints(eaddr(s, EF_FLAGS));
  Int64s ev = Int64s(T().ev);
  int64_t vb = liq.v[e];
  uint fl = flags.v[e];
  int64_t oa = 0, ob = 0;
  if ((fl & FLAG_RUPT) != 0u) {
    liq.v[e] = 0;
    flags.v[e] = fl & ~(FLAG_RUPT | FLAG_WIC);
    atomicAdd(CTL().v[CTL_RUPTURES], 1u);
  } else if (vb > 0) {
    int64_t si = Int64s(T().p_share).v[Uints(eaddr(s, EF_SELF)).v[e]];
    int64_t sj = Int64s(T().p_share).v[Uints(eaddr(s, EF_NBR)).v[e]];
    int64_t vn = vb + si + sj;
    if (vn > P.lpp.v_max) {
      int64_t over = vn - P.lpp.v_max;
      oa = split_proportional(over, si, sj);
      ob = over - oa;
      vn = P.lpp.v_max;
    }
    liq.v[e] = vn;
  }
  ev.v[e] = oa;  // to i's film (4c), at i's entry
  ev.v[Uints(T().partner).v[e]] = ob;  // to j's film, at j's entry
}
