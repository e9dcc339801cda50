// Integer liquid arithmetic (physics.md §5, ARCHITECTURE.md "Liquid"). Every transfer moves an integer
// amount from one place to another; fractions use 16-bit fixed point so that every device and the CPU
// reference compute the same integers.
#ifndef WETDEM_LIQUID_GLSL
#define WETDEM_LIQUID_GLSL
#include "access.glsl"

// floor(V * q / 65536) for 0 <= q <= 65536 and 0 <= V < 2^47, without 64-bit overflow.
int64_t mul_q16(int64_t V, uint q) {
  int64_t Q = int64_t(q);
  return (V >> 16) * Q + (((V & 0xFFFFl) * Q) >> 16);
}

// The part of V that goes to side a when V is split in proportion to a : b (a, b >= 0, a + b > 0),
// clamped so that neither side gets more than its weight allows: result in [max(0, V - b), min(V, a)].
int64_t split_proportional(int64_t V, int64_t a, int64_t b) {
  if (a + b <= 0) return 0;
  uint q = uint((uint64_t(a) << 16) / uint64_t(a + b));
  int64_t pa = mul_q16(V, q);
  return clamp(pa, max(int64_t(0), V - b), min(V, a));
}

// floor(V * F / 2^64) for 0 <= V < 2^63 and a 64-bit fraction F = (lo, hi) (params.h loss_fraction_q64):
// schoolbook product on 32-bit limbs, exact.
int64_t mul_q64(int64_t V, uint F[2]) {
  if (V <= 0) return 0;
  uint64_t v = uint64_t(V);
  uint64_t vl = v & 0xFFFFFFFFul, vh = v >> 32;
  uint64_t fl = uint64_t(F[0]), fh = uint64_t(F[1]);
  uint64_t ll = vl * fl, lh = vl * fh, hl = vh * fl, hh = vh * fh;
  uint64_t mid = (ll >> 32) + (lh & 0xFFFFFFFFul) + (hl & 0xFFFFFFFFul);
  return int64_t(hh + (lh >> 32) + (hl >> 32) + (mid >> 32));
}
#endif
