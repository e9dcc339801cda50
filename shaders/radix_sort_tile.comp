#version 460
#extension GL_GOOGLE_include_directive : require
// Radix sort of at most one tile (n <= TILE = 2048 pairs) in one workgroup and one dispatch: every 4-bit pass
// of radix_count + scan + radix_scatter done in shared memory. A small system (the flowing diagnosis drum,
// 410 particles) rebuilds its neighbour list every few steps, and the multi-pass sort is ~4 x 3 dispatches
// per rebuild whose cost on lavapipe is their launch, not their work. Each pass is radix_scatter's stable
// counting sort of the tile with the tile as the whole input (its output offsets are its in-tile ranks), so
// the result is the multi-pass sort's, bit for bit: both are stable LSD sorts by the same digits
// (GpuSort.OneTileSortIsTheMultiPassSort). No atomics: deterministic.
#include "table.glsl"
#define WG 256
#define PER 8
#define TILE (WG * PER)
layout(local_size_x = WG) in;
#include "scan_wg.glsl"
layout(push_constant) uniform Push {
  uint64_t keys;
  uint64_t vals;
  uint n;         // <= TILE
  uint key_bits;  // the low key_bits bits order the pairs; higher bits are carried along
} pc;
shared uint s_key[SCAN_PAD(TILE)];
shared uint s_val[SCAN_PAD(TILE)];
// Per-invocation digit counts, two 16-bit counters per word (as radix_scatter): digit d in row (d & 7),
// half (d >> 3), column t. Counts and ranks are below TILE = 2048, so a half never carries.
shared uint s_cnt[SCAN_PAD(8 * WG)];
void main() {
  uint t = gl_LocalInvocationID.x;
  uint count = min(uint(TILE), pc.n);
  Uints keys = Uints(pc.keys);
  Uints vals = Uints(pc.vals);
  for (uint j = 0; j < PER; ++j) {
    uint i = j * WG + t;
    if (i < count) {
      s_key[SCAN_PAD(i)] = keys.v[i];
      s_val[SCAN_PAD(i)] = vals.v[i];
    }
  }
  barrier();
  for (uint shift = 0; shift < pc.key_bits; shift += 4) {
    // The last digit may be narrower: bits at and above key_bits take no part in the order.
    uint mask = (1u << min(4u, pc.key_bits - shift)) - 1u;
    // 1. This invocation's contiguous run into registers; count its digits in its own column.
    for (uint r = 0; r < 8; ++r) s_cnt[SCAN_PAD(r * WG + t)] = 0;
    uint k[PER], v[PER];
    for (uint j = 0; j < PER; ++j) {
      uint i = t * PER + j;
      k[j] = i < count ? s_key[SCAN_PAD(i)] : 0u;
      v[j] = i < count ? s_val[SCAN_PAD(i)] : 0u;
      if (i < count) {
        uint d = (k[j] >> shift) & mask;
        s_cnt[SCAN_PAD((d & 7) * WG + t)] += 1u << ((d >> 3) * 16);
      }
    }
    barrier();
    // 2. Exclusive scan of the packed counters in row-major order (digit-major, invocation-minor ranks):
    // low halves rank digits 0-7, high halves digits 8-15 less the count of digits 0-7.
    uint loc[PER];
    uint sum = 0;
    for (uint j = 0; j < PER; ++j) {
      loc[j] = sum;
      sum += s_cnt[SCAN_PAD(t * PER + j)];
    }
    uint pre = wg_exclusive_scan(sum);
    uint low_total = s_scan_total & 0xffffu;
    for (uint j = 0; j < PER; ++j) s_cnt[SCAN_PAD(t * PER + j)] = loc[j] + pre;
    barrier();
    // 3. Place the run at its ranks (every run is in registers since step 1); each invocation reads and
    // bumps only its own column of counters.
    for (uint j = 0; j < PER; ++j) {
      if (t * PER + j < count) {
        uint d = (k[j] >> shift) & mask;
        uint c = SCAN_PAD((d & 7) * WG + t);
        uint packed = s_cnt[c];
        uint rank = d < 8u ? (packed & 0xffffu) : (packed >> 16) + low_total;
        s_key[SCAN_PAD(rank)] = k[j];
        s_val[SCAN_PAD(rank)] = v[j];
        s_cnt[c] = packed + (1u << ((d >> 3) * 16));
      }
    }
    barrier();
  }
  for (uint j = 0; j < PER; ++j) {
    uint i = j * WG + t;
    if (i < count) {
      keys.v[i] = s_key[SCAN_PAD(i)];
      vals.v[i] = s_val[SCAN_PAD(i)];
    }
  }
}
