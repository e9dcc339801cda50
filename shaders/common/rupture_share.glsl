// Liquid pass 4a for one particle (physics.md §5 two-phase rule, phase 1): sum the halves this particle
// receives from its ruptured pairs (the lower id gets floor(V_b/2)) and its ruptured wall bridges, and decide
// the share each of its surviving bridges gets: d_c * received / N (pair ruptures over surviving pair
// bridges, wall ruptures over surviving pair and wall bridges). Remainders and the (1 - d_c) part stay for
// the film (p_gain). Run on its own (liq_rupture_share.comp) or inside gather_kick (the fused step).
// pairs = false: no pair of the system is flagged for rupture this step; then the segment is read only when
// one of the particle's own wall bridges ruptures (its surviving pair bridges share that), which gives the
// same integers.
#ifndef WETDEM_RUPTURE_SHARE_GLSL
#define WETDEM_RUPTURE_SHARE_GLSL
#include "liquid.glsl"

void rupture_share(uint i, uint s, Params P, bool pairs) {
  Int64s wliq = Int64s(paddr(s, PF_WLIQ));
  Uints wfl = Uints(paddr(s, PF_WFLAGS));
  int64_t recv_pp = 0, recv_w[3] = {0, 0, 0};
  uint npp = 0u, nw = 0u;
  bool wall_rupt = false;
  for (uint w = 0u; w < 3u; ++w) {
    if (!wall_present(w, P)) continue;
    uint k = wall_slot(i, w, P);
    wall_rupt = wall_rupt || (wliq.v[k] > 0 && (wfl.v[k] & FLAG_RUPT) != 0u);
  }
  if (pairs || wall_rupt) {
    Uints off = Uints(paddr(s, PF_NOFFSET)), cnt = Uints(paddr(s, PF_NCOUNT));
    Uints mirror = Uints(eaddr(s, EF_MIRROR)), flags = Uints(eaddr(s, EF_FLAGS));
    Int64s liq = Int64s(eaddr(s, EF_LIQ));
    uint b = off.v[i], c = cnt.v[i];
    for (uint e = b; e < b + c; ++e) {
      uint o = mirror.v[e];
      int64_t vb = liq.v[o];
      if (vb <= 0) continue;
      if ((flags.v[o] & FLAG_RUPT) != 0u) recv_pp += (o == e) ? vb / 2 : vb - vb / 2;
      else npp++;
    }
  }
  if (wall_rupt) {
    for (uint w = 0u; w < 3u; ++w) {
      if (!wall_present(w, P)) continue;
      uint k = wall_slot(i, w, P);
      int64_t vb = wliq.v[k];
      if (vb <= 0) continue;
      if ((wfl.v[k] & FLAG_RUPT) != 0u) {
        recv_w[w] = vb;
        wliq.v[k] = 0;
        wfl.v[k] &= ~(FLAG_RUPT | FLAG_WIC);
        atomicAdd(CTL().v[CTL_RUPTURES], 1u);
      } else {
        nw++;
      }
    }
  }
  int64_t gain = 0, share_pp = 0, share_w = 0;
  if (recv_pp > 0) {
    if (npp > 0u) {
      share_pp = mul_q16(recv_pp, P.lpp.dc_q16) / int64_t(npp);
      gain += recv_pp - share_pp * int64_t(npp);
    } else {
      gain += recv_pp;
    }
  }
  // Each ruptured wall bridge is shared on its own (its wall's d_c) over surviving pair and wall bridges.
  uint nt = npp + nw;
  for (uint w = 0u; w < 3u; ++w) {
    if (recv_w[w] == 0) continue;
    if (nt > 0u) {
      int64_t per = mul_q16(recv_w[w], P.lpw[w].dc_q16) / int64_t(nt);
      share_w += per;
      gain += recv_w[w] - per * int64_t(nt);
    } else {
      gain += recv_w[w];
    }
  }
  if (share_w > 0) {
    // Surviving wall bridges belong to this particle alone: apply their share and cap here (never handing
    // back more than the share, as 4b).
    for (uint w = 0u; w < 3u; ++w) {
      if (!wall_present(w, P)) continue;
      uint k = wall_slot(i, w, P);
      int64_t vb = wliq.v[k];
      if (vb <= 0) continue;
      int64_t vn = vb + share_w;
      int64_t over = clamp(vn - P.lpw[w].v_max, int64_t(0), share_w);
      gain += over;
      wliq.v[k] = vn - over;
    }
  }
  Int64s(T().p_share).v[i] = share_pp + share_w;
  Int64s(T().p_gain).v[i] = gain;
}
#endif
