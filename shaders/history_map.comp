#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6i (DEM-Engine's history mapping, per particle of the new list): each owner entry of the particle's
// new segment finds the same pair, by stable ids, in the particle's old segment and takes its springs,
// bridge and flags. The old entry is marked so that 6j can prove no bridge was left behind. New pairs start
// with zero state. Both segments are ordered by the partners' stable ids (6g; an uploaded list by id_j), and
// a pair's owner entry sits in the segment of its lower id in both lists, so one merge walk over the two
// segments finds every pair.
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity(), t = 1u - s;  // s: old list, t: new list
  Int64s liq_new = Int64s(eaddr(t, EF_LIQ));
  Uints fl_new = Uints(eaddr(t, EF_FLAGS)), mir_new = Uints(eaddr(t, EF_MIRROR)), nbr_new = Uints(eaddr(t, EF_NBR));
  IVec4s pos_new = IVec4s(paddr(t, PF_POS)), pos_old = IVec4s(paddr(s, PF_POS));
  Uints nbr_old = Uints(eaddr(s, EF_NBR)), fl_old = Uints(eaddr(s, EF_FLAGS));
  uint b = Uints(paddr(t, PF_NOFFSET)).v[i], c = Uints(paddr(t, PF_NCOUNT)).v[i];
  uint io = Uints(T().sort_val).v[i];  // old index of particle i
  uint k = Uints(paddr(s, PF_NOFFSET)).v[io];
  uint ko = k + Uints(paddr(s, PF_NCOUNT)).v[io];
  int idk = k < ko ? pos_old.v[nbr_old.v[k]].w : 0;
  for (uint e = b; e < b + c; ++e) {
    uvec4 st = uvec4(0u);  // the springs as stored (access.glsl): (t, r.x), (r.y, r.z)
    uint64_t sr = 0ul;
    int64_t liq = 0;
    uint fl = 0u;
    if (mir_new.v[e] == e) {
      int idj = pos_new.v[nbr_new.v[e]].w;
      while (k < ko && idk < idj) {
        ++k;
        if (k < ko) idk = pos_old.v[nbr_old.v[k]].w;
      }
      if (k < ko && idk == idj) {
        st = load_u4(eaddr(s, EF_ST), k);
        sr = U64s(eaddr(s, EF_SR)).v[k];
        liq = Int64s(eaddr(s, EF_LIQ)).v[k];
        uint fo = fl_old.v[k];
        fl = fo & FLAG_WIC;
        fl_old.v[k] = fo | FLAG_MAPPED;
      }
    }
    store_u4(eaddr(t, EF_ST), e, st);
    U64s(eaddr(t, EF_SR)).v[e] = sr;
    liq_new.v[e] = liq;
    fl_new.v[e] = fl;
  }
}
