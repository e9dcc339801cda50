#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6d: [start, end) of every non-empty cell in the sorted order (cells were cleared to empty).
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  uint n = P.num_particles;
  if (i >= n || halted()) return;
  Uints key = Uints(T().cell_key);
  uint k = key.v[i];
  if (i == 0u || key.v[i - 1u] != k) Uints(T().cell_start).v[k] = i;
  if (i == n - 1u || key.v[i + 1u] != k) Uints(T().cell_end).v[k] = i + 1u;
}
