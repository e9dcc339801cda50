#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4d (per owner entry, over the owner list): a first touch forms a bridge when the full films
// exceed V_min: V_b = min(offer_i + offer_j, V_max), drawn in proportion to the offers (§5 rule 2).
// What each film gives goes to 4e through the event slots at both entries, or (pc.arg0 & LQ_ATOMIC, the fused
// step) straight out of the two films with integer atomics (exact and order-independent; no 4e). In the
// fused step this is the last pass of a step whose liquid gate was open: its last workgroup takes the
// rebuild decision (LQ_FINISH; it runs with at least one workgroup).
#include "liquid.glsl"
#include "modes.glsl"
#include "step_control.glsl"
layout(local_size_x = 256) in;

void form(uint e, bool atomic) {
  uint s = parity();
  Uints flags = Uints(eaddr(s, EF_FLAGS));
  uint fl = flags.v[e];
  int64_t ta = 0, tb = 0;
  uint i = Uints(eaddr(s, EF_SELF)).v[e], j = Uints(eaddr(s, EF_NBR)).v[e];
  if ((fl & FLAG_FORM) != 0u) {
    Params P = PRM_OF(i, s);
    flags.v[e] = (fl & ~FLAG_FORM) | FLAG_WIC;  // set even when no bridge forms: no retry until separation
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
  if (atomic) {
    Int64s film = Int64s(paddr(s, PF_FILM));
    if (ta > 0) atomicAdd(film.v[i], -ta);
    if (tb > 0) atomicAdd(film.v[j], -tb);
  } else {
    Int64s(T().ev).v[e] = ta;                        // taken from i's film (4e), at i's entry
    Int64s(T().ev).v[Uints(T().partner).v[e]] = tb;  // from j's film, at j's entry
  }
}

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (halted()) return;
  uint mode = pc.arg0;
  if (k < CTL().v[CTL_OWNERS]) form(Uints(T().owners).v[k], (mode & LQ_ATOMIC) != 0u);
  if ((mode & LQ_FINISH) != 0u && last_workgroup() && gl_LocalInvocationIndex == 0u)
    decide_rebuild((mode & LQ_SPLIT) != 0u, true);
}
