#version 460
#extension GL_GOOGLE_include_directive : require
// Radix sort, pass step 1: the 16-bin histogram of one 4-bit digit over each tile of TILE = 2048 keys,
// written digit-major: hist[d * num_tiles + tile]. The exclusive scan of that array (gpu::Scan) is, for
// every (digit, tile), where the tile's keys with that digit start in the output: digit-major and
// tile-minor order is what makes the sort stable. Shared atomics only add integers here, so the counts
// do not depend on their order.
#include "table.glsl"
#define WG 256
#define PER 8
#define TILE (WG * PER)
#define REPL 8  // copies of the histogram, to spread atomic contention when many keys share a digit
layout(local_size_x = WG) in;
layout(push_constant) uniform Push {
  uint64_t keys;
  uint64_t hist;  // 16 * num_tiles uints
  uint n;
  uint shift;  // digit = (key >> shift) & mask
  uint mask;
  uint num_tiles;
} pc;
shared uint s_cnt[REPL * 16];
void main() {
  uint t = gl_LocalInvocationID.x;
  uint tile = gl_WorkGroupID.x;
  if (t < REPL * 16) s_cnt[t] = 0;
  barrier();
  Uints keys = Uints(pc.keys);
  uint base = tile * TILE;
  uint r = (t % REPL) * 16;
  for (uint j = 0; j < PER; ++j) {
    uint g = base + j * WG + t;  // coalesced; the order of counting does not matter
    if (g < pc.n) atomicAdd(s_cnt[r + ((keys.v[g] >> pc.shift) & pc.mask)], 1u);
  }
  barrier();
  if (t < 16) {
    uint c = 0;
    for (uint k = 0; k < REPL; ++k) c += s_cnt[k * 16 + t];
    Uints(pc.hist).v[t * pc.num_tiles + tile] = c;
  }
}
