#version 460
#extension GL_GOOGLE_include_directive : require
// Fills n uints at `dst` with `value` (used to clear cell ranges and counters).
#include "table.glsl"
layout(local_size_x = 256) in;
layout(push_constant) uniform Push {
  uint64_t dst;
  uint n;
  uint value;
} pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.n) Uints(pc.dst).v[i] = pc.value;
}
