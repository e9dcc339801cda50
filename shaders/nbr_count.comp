#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6e: number of neighbours of every particle (new order), into the scan array. The search's first
// pc.arg0 candidates are kept in scratch (the per-entry pair-force buffer, dead between a step's gather and
// the next pair_force), so that 6g copies them instead of searching the 27 cells a second time.
#include "neighbours.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = 1u - parity();
  uint K = pc.arg0;
  Uints keep = Uints(T().pair_f);
  uint count = 0u;
  FOR_EACH_NEIGHBOUR(i, s, P, if (count < K) keep.v[i * K + count] = j; count++)
  Uints(paddr(s, PF_NCOUNT)).v[i] = count;
  Uints(T().cnt_scan).v[i] = count;
}
