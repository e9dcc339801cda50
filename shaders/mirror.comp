#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6h: the owner of a pair is the entry in the segment of the particle with the lower stable id.
// Every other entry finds its owner by searching the partner's segment, and becomes the owner's partner.
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
  uint m = 0xFFFFFFFFu;
  if (pos.v[i].w < pos.v[j].w) {
    m = e;
  } else {
    uint b = Uints(paddr(s, PF_NOFFSET)).v[j], c = Uints(paddr(s, PF_NCOUNT)).v[j];
    for (uint k = b; k < b + c; ++k)
      if (nbr.v[k] == i) m = k;
    if (m == 0xFFFFFFFFu) atomicAdd(C.v[CTL_MIRROR_ERR], 1u);
    else Uints(T().partner).v[m] = e;  // the owner writes this entry's pair results too
  }
  Uints(eaddr(s, EF_MIRROR)).v[e] = m;
}
