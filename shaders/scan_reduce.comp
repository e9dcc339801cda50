#version 460
#extension GL_GOOGLE_include_directive : require
// First half of one level of the multi-level scan (reduce-then-scan): the sum of each block of
// BLOCK = 2048 uints goes to sums[block]. The level above scans these sums; scan_block then scans each
// block starting from its scanned sum. Each element is read twice and written once in all.
#include "table.glsl"
#define WG 256
#define PER 8
#define BLOCK (WG * PER)
layout(local_size_x = WG) in;
#include "scan_wg.glsl"
layout(push_constant) uniform Push {
  uint64_t data;  // n uints (read only)
  uint64_t sums;  // one uint per block
  uint n;
} pc;
void main() {
  uint t = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * BLOCK;
  Uints data = Uints(pc.data);
  uint sum = 0;
  // Strided by WG so that neighbouring invocations read neighbouring words (coalesced).
  for (uint j = 0; j < PER; ++j) {
    uint g = base + j * WG + t;
    if (g < pc.n) sum += data.v[g];
  }
  wg_exclusive_scan(sum);
  if (t == 0) Uints(pc.sums).v[gl_WorkGroupID.x] = s_scan_total;
}
