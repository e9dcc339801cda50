#version 460
#extension GL_GOOGLE_include_directive : require
// Radix sort, pass step 2: stable scatter of one tile of TILE = 2048 (key, value) pairs by one 4-bit digit.
// Every invocation owns a contiguous run of PER elements of the tile and counts its digits; an exclusive
// scan over the (digit-major, invocation-minor) counts ranks every element among the tile's elements
// with the same digit, in input order. The tile is then sorted by digit in shared memory and written out
// in index order, so neighbouring invocations write neighbouring words of each digit's output run.
// Nothing depends on atomics or on scheduling: the result is stable and bitwise deterministic.
#include "table.glsl"
#define WG 256
#define PER 8
#define TILE (WG * PER)
layout(local_size_x = WG) in;
#include "scan_wg.glsl"
layout(push_constant) uniform Push {
  uint64_t src_keys;
  uint64_t src_vals;
  uint64_t dst_keys;
  uint64_t dst_vals;
  uint64_t offsets;  // scanned histogram: offsets[d * num_tiles + tile] = first output index
  uint n;
  uint shift;  // digit = (key >> shift) & mask
  uint mask;
  uint num_tiles;
} pc;
shared uint s_key[SCAN_PAD(TILE)];
shared uint s_val[SCAN_PAD(TILE)];
// Per-invocation digit counts, two 16-bit counters per word: digit d lives in row (d & 7), half (d >> 3),
// column t. Counts and in-tile ranks are below TILE = 2048, so a half never carries into the other.
shared uint s_cnt[SCAN_PAD(8 * WG)];
shared uint s_goff[16];    // first output index of this tile's keys with digit d
shared uint s_lstart[16];  // first in-tile (sorted) position of digit d
void main() {
  uint t = gl_LocalInvocationID.x;
  uint tile = gl_WorkGroupID.x;
  uint base = tile * TILE;
  uint count = min(uint(TILE), pc.n - base);

  // 1. Coalesced load of the tile; clear this invocation's counters (its column).
  Uints src_keys = Uints(pc.src_keys);
  Uints src_vals = Uints(pc.src_vals);
  for (uint j = 0; j < PER; ++j) {
    uint i = j * WG + t;
    if (i < count) {
      s_key[SCAN_PAD(i)] = src_keys.v[base + i];
      s_val[SCAN_PAD(i)] = src_vals.v[base + i];
    }
  }
  for (uint r = 0; r < 8; ++r) s_cnt[SCAN_PAD(r * WG + t)] = 0;
  if (t < 16) s_goff[t] = Uints(pc.offsets).v[t * pc.num_tiles + tile];
  barrier();

  // 2. Take this invocation's contiguous run into registers and count its digits.
  uint k[PER], v[PER];
  for (uint j = 0; j < PER; ++j) {
    uint i = t * PER + j;
    k[j] = i < count ? s_key[SCAN_PAD(i)] : 0u;
    v[j] = i < count ? s_val[SCAN_PAD(i)] : 0u;
    if (i < count) {
      uint d = (k[j] >> pc.shift) & pc.mask;
      s_cnt[SCAN_PAD((d & 7) * WG + t)] += 1u << ((d >> 3) * 16);
    }
  }
  barrier();

  // 3. Exclusive scan of the 8*WG packed counters in row-major order: the low halves become the
  // digit-major ranks of digits 0-7; the high halves those of digits 8-15, less the count of digits 0-7.
  uint loc[PER];
  uint sum = 0;
  for (uint j = 0; j < PER; ++j) {
    loc[j] = sum;
    sum += s_cnt[SCAN_PAD(t * PER + j)];
  }
  uint pre = wg_exclusive_scan(sum);
  uint low_total = s_scan_total & 0xffffu;
  for (uint j = 0; j < PER; ++j) s_cnt[SCAN_PAD(t * PER + j)] = loc[j] + pre;
  // Row r starts where the run of invocation r * WG / PER starts: its prefix holds the start of digits
  // r and r + 8.
  if ((t * PER) % WG == 0) {
    uint r = t * PER / WG;
    s_lstart[r] = pre & 0xffffu;
    s_lstart[r + 8] = (pre >> 16) + low_total;
  }
  barrier();

  // 4. Place the run at its ranks in shared memory (every run was read in step 2). Each invocation
  // reads and bumps only its own column of counters.
  for (uint j = 0; j < PER; ++j) {
    if (t * PER + j < count) {
      uint d = (k[j] >> pc.shift) & pc.mask;
      uint c = SCAN_PAD((d & 7) * WG + t);
      uint packed = s_cnt[c];
      uint rank = d < 8u ? (packed & 0xffffu) : (packed >> 16) + low_total;
      s_key[SCAN_PAD(rank)] = k[j];
      s_val[SCAN_PAD(rank)] = v[j];
      s_cnt[c] = packed + (1u << ((d >> 3) * 16));
    }
  }
  barrier();

  // 5. Write out in sorted-tile order: position i of digit d goes to goff[d] + (i - lstart[d]).
  Uints dst_keys = Uints(pc.dst_keys);
  Uints dst_vals = Uints(pc.dst_vals);
  for (uint j = 0; j < PER; ++j) {
    uint i = j * WG + t;
    if (i < count) {
      uint key = s_key[SCAN_PAD(i)];
      uint d = (key >> pc.shift) & pc.mask;
      uint dst = s_goff[d] + i - s_lstart[d];
      dst_keys.v[dst] = key;
      dst_vals.v[dst] = s_val[SCAN_PAD(i)];
    }
  }
}
