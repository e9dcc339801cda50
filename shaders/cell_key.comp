#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6a: cell index of every particle (key) and its current index (value) for the radix sort.
#include "geom.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  bool esc;
  ivec4 p = IVec4s(paddr(parity(), PF_POS)).v[i];
  ivec3 c = cell_of(p.xyz, P, esc);
  if (esc) atomicAdd(CTL().v[CTL_ESCAPED], 1u);
  Uints(T().cell_key).v[i] = cell_index(c, P) + run_of_id(p.w) * P.cells_per_run;
  Uints(T().sort_val).v[i] = i;
}
