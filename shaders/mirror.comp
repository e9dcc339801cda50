#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6h: the owner of a pair is the entry in the segment of the particle with the lower stable id.
// Every other entry finds its owner in the partner's segment, and becomes the owner's partner. Segments are
// ordered by the partners' stable ids (6g), so the search is a bisection.
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint e = gl_GlobalInvocationID.x;
  if (halted()) return;
  Uints C = CTL();
  if (e >= C.v[CTL_ENTRIES_NEEDED]) return;
  uint s = 1u - parity();
  Uints nbr = Uints(eaddr(s, EF_NBR)), self = Uints(eaddr(s, EF_SELF));
  IVec4s pos = IVec4s(paddr(s, PF_POS));
  uint i = self.v[e], j = nbr.v[e];
  int id_i = pos.v[i].w;
  uint m = 0xFFFFFFFFu;
  if (id_i < pos.v[j].w) {
    m = e;
  } else {
    uint lo = Uints(paddr(s, PF_NOFFSET)).v[j], hi = lo + Uints(paddr(s, PF_NCOUNT)).v[j];
    while (lo < hi) {  // first entry whose partner id is >= id_i
      uint mid = (lo + hi) >> 1;
      if (pos.v[nbr.v[mid]].w < id_i) lo = mid + 1u;
      else hi = mid;
    }
    uint end = Uints(paddr(s, PF_NOFFSET)).v[j] + Uints(paddr(s, PF_NCOUNT)).v[j];
    if (lo < end && nbr.v[lo] == i) m = lo;
    if (m == 0xFFFFFFFFu) atomicAdd(C.v[CTL_MIRROR_ERR], 1u);
    else Uints(T().partner).v[m] = e;  // the owner writes this entry's pair results too
  }
  Uints(eaddr(s, EF_MIRROR)).v[e] = m;
}
