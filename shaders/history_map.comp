#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6i (DEM-Engine's history mapping): each owner entry of the new list finds the same pair, by
// stable ids, in the old segment of its particle and takes its springs, bridge and flags. The old entry is
// marked so that 6j can prove no bridge was left behind. New pairs start with zero state.
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint e = gl_GlobalInvocationID.x;
  if (halted()) return;
  if (e >= CTL().v[CTL_ENTRIES_NEEDED]) return;
  uint s = parity(), t = 1u - s;  // s: old list, t: new list
  Vec4s st_new = Vec4s(eaddr(t, EF_ST)), sr_new = Vec4s(eaddr(t, EF_SR));
  Int64s liq_new = Int64s(eaddr(t, EF_LIQ));
  Uints fl_new = Uints(eaddr(t, EF_FLAGS));
  vec4 st = vec4(0.0), sr = vec4(0.0);
  int64_t liq = 0;
  uint fl = 0u;
  if (Uints(eaddr(t, EF_MIRROR)).v[e] == e) {
    uint i = Uints(eaddr(t, EF_SELF)).v[e], j = Uints(eaddr(t, EF_NBR)).v[e];
    uint idj = IVec4s(paddr(t, PF_POS)).v[j].w;
    uint io = Uints(T().sort_val).v[i];  // old index of particle i
    uint b = Uints(paddr(s, PF_NOFFSET)).v[io], c = Uints(paddr(s, PF_NCOUNT)).v[io];
    Uints nbr_old = Uints(eaddr(s, EF_NBR));
    IVec4s pos_old = IVec4s(paddr(s, PF_POS));
    for (uint k = b; k < b + c; ++k) {
      if (uint(pos_old.v[nbr_old.v[k]].w) == idj) {
        st = Vec4s(eaddr(s, EF_ST)).v[k];
        sr = Vec4s(eaddr(s, EF_SR)).v[k];
        liq = Int64s(eaddr(s, EF_LIQ)).v[k];
        fl = Uints(eaddr(s, EF_FLAGS)).v[k] & FLAG_WIC;
        atomicOr(Uints(eaddr(s, EF_FLAGS)).v[k], FLAG_MAPPED);
        break;
      }
    }
  }
  st_new.v[e] = st;
  sr_new.v[e] = sr;
  liq_new.v[e] = liq;
  fl_new.v[e] = fl;
}
