#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6k (per particle, the list being built): how many entries of its segment own their pair
// (mirror[e] == e, 6h), into the owner scan array; 6l scans it, 6m writes the owner list.
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint t = 1u - parity();
  Uints mirror = Uints(eaddr(t, EF_MIRROR));
  uint b = Uints(paddr(t, PF_NOFFSET)).v[i], c = Uints(paddr(t, PF_NCOUNT)).v[i];
  uint k = 0u;
  for (uint e = b; e < b + c; ++e) k += mirror.v[e] == e ? 1u : 0u;
  Uints(T().own_scan).v[i] = k;
}
