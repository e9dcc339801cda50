#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4d (per owner entry, over the owner list): a first touch forms a bridge when the full films
// exceed V_min: V_b = min(offer_i + offer_j, V_max), drawn in proportion to the offers (§5 rule 2).
#include "liquid.glsl"
layout(local_size_x = 256) in;
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (halted()) return;
  if (k >= CTL().v[CTL_OWNERS]) return;
  uint e = Uints(T().owners).v[k];
  uint s = parity();
  Params P = PRM_OF(Uints(eaddr(s, EF_SELF)).v[e], s);
  Uints flags = Uints(eaddr(s, EF_FLAGS));
  uint fl = flags.v[e];
  int64_t ta = 0, tb = 0;
  if ((fl & FLAG_FORM) != 0u) {
    flags.v[e] = (fl & ~FLAG_FORM) | FLAG_WIC;  // set even when no bridge forms: no retry until separation
    uint i = Uints(eaddr(s, EF_SELF)).v[e], j = Uints(eaddr(s, EF_NBR)).v[e];
    Int64s full = Int64s(T().p_full), offer = Int64s(T().p_offer);
    if (full.v[i] + full.v[j] > P.lpp.v_min) {
      int64_t oi = offer.v[i], oj = offer.v[j];
      int64_t vb = min(oi + oj, P.lpp.v_max);
      if (vb > 0) {
        ta = split_proportional(vb, oi, oj);
        tb = vb - ta;
        Int64s(eaddr(s, EF_LIQ)).v[e] = vb;
        atomicAdd(CTL().v[CTL_FORMATIONS], 1u);
      }
    }
  }
  Int64s(T().ev).v[e] = ta;  // taken from i's film (4e), at i's entry
  Int64s(T().ev).v[Uints(T().partner).v[e]] = tb;  // from j's film, at j's entry
}
