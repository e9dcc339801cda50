#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6m (per particle, the list being built): the owner list, every owner entry in list order, so that
// the passes over pairs (2, 4b, 4d) run one invocation per pair instead of one per entry.
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint t = 1u - parity();
  Uints mirror = Uints(eaddr(t, EF_MIRROR)), owners = Uints(T().owners);
  uint b = Uints(paddr(t, PF_NOFFSET)).v[i], c = Uints(paddr(t, PF_NCOUNT)).v[i];
  uint k = Uints(T().own_scan).v[i];
  for (uint e = b; e < b + c; ++e)
    if (mirror.v[e] == e) owners.v[k++] = e;
}
