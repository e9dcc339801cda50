#version 460
#extension GL_GOOGLE_include_directive : require
// Copies n (key, value) pairs: brings an odd number of radix passes back from the scratch buffers.
// A kernel rather than vkCmdCopyBuffer so that it goes through the (possibly gated) Dispatcher.
#include "table.glsl"
#define WG 256
#define PER 8
layout(local_size_x = WG) in;
layout(push_constant) uniform Push {
  uint64_t src_keys;
  uint64_t src_vals;
  uint64_t dst_keys;
  uint64_t dst_vals;
  uint n;
} pc;
void main() {
  // PER elements per invocation keep the group count below 65535 up to n = 2^27.
  uint base = gl_WorkGroupID.x * (WG * PER) + gl_LocalInvocationID.x;
  for (uint j = 0; j < PER; ++j) {
    uint g = base + j * WG;
    if (g < pc.n) {
      Uints(pc.dst_keys).v[g] = Uints(pc.src_keys).v[g];
      Uints(pc.dst_vals).v[g] = Uints(pc.src_vals).v[g];
    }
  }
}
