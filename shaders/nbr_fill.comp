#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6g: write every particle's neighbours into its CSR segment of the new list, same order as 6e.
#include "neighbours.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = 1u - parity();
  uint off = Uints(T().cnt_scan).v[i];
  Uints(paddr(s, PF_NOFFSET)).v[i] = off;
  Uints nbr = Uints(eaddr(s, EF_NBR)), self = Uints(eaddr(s, EF_SELF));
  uint e = off;
  FOR_EACH_NEIGHBOUR(i, s, P, nbr.v[e] = j; self.v[e] = i; e++)
}
