// Workgroup-wide exclusive scan of one uint per invocation, shared by the scan_* and radix_* kernels.
// Uses shared memory and barriers only (no subgroup operations), so the result does not depend on the
// subgroup size (8 on lavapipe, 32 on NVIDIA) and is the same integer sum order on every device.
// The includer defines WG (= local_size_x, a multiple of 16 and at most 256) before including this file.
#ifndef WETDEM_SCAN_WG_GLSL
#define WETDEM_SCAN_WG_GLSL

// Shared arrays indexed by [i] with stride-8 per-invocation access are padded by one word per 32, so
// that the 32 invocations of a row of banks hit distinct banks (i -> i + i/32).
#define SCAN_PAD(i) ((i) + ((i) >> 5))

shared uint s_scan_part[SCAN_PAD(WG)];  // padded: the serial segment loop reads stride 16
shared uint s_scan_seg[WG / 16];
shared uint s_scan_total;

// Returns the sum of v over invocations with a lower local index; s_scan_total holds the sum over all
// invocations afterwards. Every invocation must call it (it contains barriers). Three barrier phases
// instead of log2(WG) Hillis-Steele rounds: 16-element serial segments, then one serial scan of the
// WG/16 segment sums. It ends with a barrier, so it can be called again at once.
uint wg_exclusive_scan(uint v) {
  uint t = gl_LocalInvocationID.x;
  s_scan_part[SCAN_PAD(t)] = v;
  barrier();
  if (t < WG / 16) {
    uint sum = 0;
    for (uint i = 0; i < 16; ++i) {
      uint x = s_scan_part[SCAN_PAD(t * 16 + i)];
      s_scan_part[SCAN_PAD(t * 16 + i)] = sum;
      sum += x;
    }
    s_scan_seg[t] = sum;
  }
  barrier();
  if (t == 0) {
    uint sum = 0;
    for (uint i = 0; i < WG / 16; ++i) {
      uint x = s_scan_seg[i];
      s_scan_seg[i] = sum;
      sum += x;
    }
    s_scan_total = sum;
  }
  barrier();
  uint r = s_scan_part[SCAN_PAD(t)] + s_scan_seg[t / 16];
  barrier();
  return r;
}
#endif
