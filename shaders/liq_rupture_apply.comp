#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4b (per owner entry, over the owner list): ruptured bridges empty; surviving bridges take the
// shares of both ends, capped at V_max, the overflow going back to the two films in proportion to the shares
// (§5 rule 1). A bridge hands back at most what it received this step: one already above the cap (after a
// parameter change) keeps its liquid, so a step without ruptures changes nothing here.
// The overflow goes to 4c through the event slots at both entries, or (pc.arg0 & LQ_ATOMIC, the fused step)
// straight into the two particles' p_gain with integer atomics (exact and order-independent).
#include "liquid.glsl"
#include "modes.glsl"
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
  bool atomic = (pc.arg0 & LQ_ATOMIC) != 0u;
  int64_t vb = liq.v[e];
  uint fl = flags.v[e];
  int64_t oa = 0, ob = 0;
  if ((fl & FLAG_RUPT) != 0u) {
    liq.v[e] = 0;
    flags.v[e] = fl & ~(FLAG_RUPT | FLAG_WIC);
    atomicAdd(CTL().v[CTL_RUPTURES], 1u);
  } else if (vb > 0) {
    int64_t si = Int64s(T().p_share).v[i];
    int64_t sj = Int64s(T().p_share).v[j];
    int64_t vn = vb + si + sj;
    int64_t over = clamp(vn - P.lpp.v_max, int64_t(0), si + sj);
    if (over > 0) {
      oa = split_proportional(over, si, sj);
      ob = over - oa;
      vn -= over;
      liq.v[e] = vn;
    } else if (si + sj > 0) {
      liq.v[e] = vn;
    }
  }
  if (atomic) {
    if (oa > 0) atomicAdd(Int64s(T().p_gain).v[i], oa);
    if (ob > 0) atomicAdd(Int64s(T().p_gain).v[j], ob);
  } else {
    Int64s ev = Int64s(T().ev);
    ev.v[e] = oa;                        // to i's film (4c), at i's entry
    ev.v[Uints(T().partner).v[e]] = ob;  // to j's film, at j's entry
  }
}
