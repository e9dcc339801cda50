#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6e: number of neighbours of every particle (new order), into the scan array.
#include "neighbours.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = 1u - parity();
  uint count = 0u;
  FOR_EACH_NEIGHBOUR(i, s, P, count++)
  Uints(paddr(s, PF_NCOUNT)).v[i] = count;
  Uints(T().cnt_scan).v[i] = count;
}
