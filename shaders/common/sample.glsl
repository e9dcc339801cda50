// Device reductions of a sample (issue 19; host/gpu/system_sample.cpp, System::sample_runs): per run, the
// counts, liquid sums, centre of mass and kinetic energy that compute_observables (host/core/observables.cpp,
// the CPU reference) finds from a downloaded state, so that a sample downloads no more than its camera needs.
// Deterministic by construction: only integer atomics (sums of integers are exact in any order; 64-bit sums as
// two 32-bit words with the carry counted) and maxima of non-negative float bits (order-independent). Float
// quantities enter as fixed-point integers scaled by the run's own maxima (pass sample_max), so a run in an
// ensemble reduces to bitwise the numbers it reduces to alone. Layout: mirror of host/gpu/gpu_layout.h `smp`.
#ifndef WETDEM_SAMPLE_GLSL
#define WETDEM_SAMPLE_GLSL
#include "access.glsl"

#define SMP_PAIRS 0     // compact list: bridged pairs written so far (may exceed the capacity: then regrown)
#define SMP_CAPACITY 1  // entries the list holds
#define SMP_HEAD 4      // words before the first run's block
#define SMP_RUN 32      // words per run
// Within a run's block (int64 as two words, low first):
#define SR_MASS 0
#define SR_MX 2
#define SR_MY 4
#define SR_MZ 6
#define SR_KE 8
#define SR_FILMS 10
#define SR_PORES 12
#define SR_EVAP 14
#define SR_WALL_LIQ 16
#define SR_PAIR_LIQ 18
#define SR_CONTACTS 20
#define SR_BRIDGES 21
#define SR_TOUCH_BRIDGED 22
#define SR_WALL_CONTACTS 23
#define SR_WALL_BRIDGES 24
#define SR_NONFINITE 25    // particles whose kinetic energy or position is not finite
#define SR_MAX_OVERLAP 26  // float bits
#define SR_MAX_MASS 27     // float bits (pass sample_max)
#define SR_MAX_KE 28       // float bits (pass sample_max)
#define SR_EXTENT 29       // float: the drum's half extent max(R, L/2) (m), written by the host
// Fixed-point scales: q = round(value / run maximum * 2^bits).
#define SMP_MASS_BITS 34.0
#define SMP_KE_BITS 36.0

// The sample block and the compact list of bridged pairs (uvec4: id_i, id_j, volume low, volume high).
uint64_t smp_addr() { return T().smp; }
uint64_t smp_pairs_addr() { return T().smp_pairs; }

uint smp_word(uint run, uint w) { return SMP_HEAD + run * SMP_RUN + w; }

// Exact 64-bit sum with 32-bit atomics: the low words' carries are counted into the high word, so the final
// (hi, lo) is the 64-bit sum of every value mod 2^64 whatever the order (two's complement: signed too).
void smp_add64(uint run, uint w, int64_t v) {
  Uints S = Uints(smp_addr());
  uint64_t u = uint64_t(v);
  uint lo = uint(u & 0xffffffffUL), hi = uint(u >> 32);
  if (lo != 0u) {
    uint old = atomicAdd(S.v[smp_word(run, w)], lo);
    if (old + lo < old) hi += 1u;
  }
  if (hi != 0u) atomicAdd(S.v[smp_word(run, w + 1u)], hi);
}
#endif
