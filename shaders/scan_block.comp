#version 460
#extension GL_GOOGLE_include_directive : require
// Exclusive scan of each block of BLOCK = 2048 uints in place, each block starting from offsets[block]
// (the scanned block sums of the level above, or 0 when there is a single block). With one block, the
// total (offset + block sum) goes to `total` when that address is not 0.
#include "table.glsl"
#define WG 256
#define PER 8
#define BLOCK (WG * PER)
layout(local_size_x = WG) in;
#include "scan_wg.glsl"
layout(push_constant) uniform Push {
  uint64_t data;     // n uints, scanned in place
  uint64_t offsets;  // 0, or one uint per block added to the whole block
  uint64_t total;    // 0, or where a single block's total goes
  uint n;
} pc;
shared uint s_val[SCAN_PAD(BLOCK)];
void main() {
  uint t = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * BLOCK;
  Uints data = Uints(pc.data);
  // Coalesced load into shared memory; each invocation then scans a contiguous run of PER words.
  for (uint j = 0; j < PER; ++j) {
    uint i = j * WG + t;
    s_val[SCAN_PAD(i)] = base + i < pc.n ? data.v[base + i] : 0u;
  }
  barrier();
  uint loc[PER];
  uint sum = 0;
  for (uint j = 0; j < PER; ++j) {
    loc[j] = sum;
    sum += s_val[SCAN_PAD(t * PER + j)];
  }
  uint off = pc.offsets != 0ul ? Uints(pc.offsets).v[gl_WorkGroupID.x] : 0u;
  uint pre = wg_exclusive_scan(sum) + off;  // ends with a barrier: every run has been read
  for (uint j = 0; j < PER; ++j) s_val[SCAN_PAD(t * PER + j)] = loc[j] + pre;
  barrier();
  for (uint j = 0; j < PER; ++j) {
    uint i = j * WG + t;
    if (base + i < pc.n) data.v[base + i] = s_val[SCAN_PAD(i)];
  }
  if (pc.total != 0ul && t == 0) Uints(pc.total).v[0] = off + s_scan_total;
}
