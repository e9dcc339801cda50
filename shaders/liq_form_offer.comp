#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4c (per particle), §5 two-phase rule, phase 2 set-up: the film after ruptures (received
// remainders + overflow returned by its bridges) is the "full film" of the threshold; a particle with k
// forming contacts (pairs and walls) offers floor(V_f / k) to each. Wall bridges form here (film only).
// The liquid sinks act first, on that film (params.h LiquidSinkParams): pore absorption, then evaporation of
// the film, of the pair bridges this particle owns and of its wall bridges, credited to its own counter.
// pc.arg0 & LQ_ATOMIC (the fused step): 4b added the overflow to p_gain already, no event slots to read;
// LQ_GATED: the segment is read for forming contacts only on steps with formation candidates.
#include "liquid.glsl"
#include "modes.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity();
  P = PRM_OF(i, s);
  Uints off = Uints(paddr(s, PF_NOFFSET)), cnt = Uints(paddr(s, PF_NCOUNT));
  Uints mirror = Uints(eaddr(s, EF_MIRROR)), flags = Uints(eaddr(s, EF_FLAGS));
  Int64s ev = Int64s(T().ev);
  Int64s film = Int64s(paddr(s, PF_FILM));
  int64_t f = film.v[i] + Int64s(T().p_gain).v[i];
  uint k = 0u;
  uint b = off.v[i], c = cnt.v[i];
  if ((pc.arg0 & LQ_ATOMIC) == 0u) {
    for (uint e = b; e < b + c; ++e) {
      f += ev.v[e];  // this particle's part of the overflow of its bridge (4b)
      if ((flags.v[mirror.v[e]] & FLAG_FORM) != 0u) k++;
    }
  } else if ((pc.arg0 & LQ_GATED) == 0u || (CTL().v[CTL_CAND_STEP] & CAND_FORM) != 0u) {
    for (uint e = b; e < b + c; ++e)
      if ((flags.v[mirror.v[e]] & FLAG_FORM) != 0u) k++;
  }
  Int64s wliq = Int64s(paddr(s, PF_WLIQ));
  Uints wfl = Uints(paddr(s, PF_WFLAGS));
  for (uint w = 0u; w < 3u; ++w)
    if (wall_present(w, P) && (wfl.v[wall_slot(i, w, P)] & FLAG_FORM) != 0u) k++;
  if (P.absorb_mode != 0u) {
    Int64s pore = Int64s(paddr(s, PF_PORE));
    int64_t room = Int64s(paddr(s, PF_PORECAP)).v[i] - pore.v[i];
    int64_t m = min(P.absorb_mode == 2u ? f : mul_q64(f, P.absorb_q64), room);
    if (m > 0) {
      f -= m;
      pore.v[i] += m;
    }
  }
  if (P.evap_on != 0u) {
    int64_t lost = mul_q64(f, P.evap_q64);
    f -= lost;
    Int64s liq = Int64s(eaddr(s, EF_LIQ));
    for (uint e = b; e < b + c; ++e) {  // owner entries only: no other thread writes them in this pass
      if (mirror.v[e] != e) continue;
      int64_t d = mul_q64(liq.v[e], P.evap_q64);
      if (d > 0) {
        liq.v[e] -= d;
        lost += d;
      }
    }
    for (uint w = 0u; w < 3u; ++w) {
      if (!wall_present(w, P)) continue;
      int64_t d = mul_q64(wliq.v[wall_slot(i, w, P)], P.evap_q64);
      wliq.v[wall_slot(i, w, P)] -= d;
      lost += d;
    }
    Int64s(paddr(s, PF_EVAP)).v[i] += lost;
  }
  int64_t offer = k > 0u ? f / int64_t(k) : 0;
  const int64_t full = f;
  Int64s(T().p_full).v[i] = full;
  Int64s(T().p_offer).v[i] = offer;
  for (uint w = 0u; w < 3u; ++w) {
    if (!wall_present(w, P)) continue;
    uint kk = wall_slot(i, w, P);
    if ((wfl.v[kk] & FLAG_FORM) == 0u) continue;
    wfl.v[kk] = (wfl.v[kk] & ~FLAG_FORM) | FLAG_WIC;
    if (full >= P.lpw[w].v_min) {  // §5: a wall bridge needs V_f,i >= V_min
      int64_t take = min(offer, P.lpw[w].v_max);
      if (take > 0) {
        wliq.v[kk] = take;
        f -= take;
        atomicAdd(CTL().v[CTL_FORMATIONS], 1u);
      }
    }
  }
  film.v[i] = f;
}
