#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4e (per particle): films give what the new bridges took (gather over the list segment).
#include "liquid.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity();
  P = PRM_OF(i, s);
  Uints off = Uints(paddr(s, PF_NOFFSET)), cnt = Uints(paddr(s, PF_NCOUNT));
  Int64s ev = Int64s(T().ev);
  int64_t taken = 0;
  uint b = off.v[i], c = cnt.v[i];
  for (uint e = b; e < b + c; ++e) taken += ev.v[e];  // this particle's part of each new bridge (4d)
  Int64s(paddr(s, PF_FILM)).v[i] -= taken;
}
