#version 460
#extension GL_GOOGLE_include_directive : require
// Sampling, pass over pairs (owner list; sample.glsl): per run, touching pairs (overlap > 0, from the same
// exact-integer overlap as pair_force), bridged pairs (V_b > 0, touching or not), pairs both touching and
// bridged (f_wet's union), the bridge liquid and the largest pair overlap; and the compact list of bridged
// pairs (stable ids and volume) that the host needs for agglomerates. The list's order follows the atomic
// counter, so the host sorts it (canonical order).
#include "geom.glsl"
#include "sample.glsl"
layout(local_size_x = 256) in;
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= CTL().v[CTL_OWNERS]) return;
  uint s = parity();
  uint e = Uints(T().owners).v[k];
  uint i = Uints(eaddr(s, EF_SELF)).v[e], j = Uints(eaddr(s, EF_NBR)).v[e];
  IVec4s pos = IVec4s(paddr(s, PF_POS));
  ivec4 pi4 = pos.v[i], pj4 = pos.v[j];
  uint r = run_of_id(pi4.w);
  Params P = PRMR(r);
  Vec4s props = Vec4s(paddr(s, PF_PROPS)), frac = Vec4s(paddr(s, PF_FRAC));
  vec4 pi = props.v[i], pj = props.v[j], fi = frac.v[i], fj = frac.v[j];
  ivec3 D = tick_delta(pi4.xyz, pj4.xyz, P.period_ticks);
  vec3 n;
  float dist;
  float delta = pair_overlap_ticks(D, fi.xyz - fj.xyz, floatBitsToInt(pi.w) + floatBitsToInt(pj.w), fi.w + fj.w,
                                   n, dist) * P.h;
  int64_t vb = Int64s(eaddr(s, EF_LIQ)).v[e];
  Uints S = Uints(smp_addr());
  bool touching = delta > 0.0;
  if (touching) {
    atomicAdd(S.v[smp_word(r, SR_CONTACTS)], 1u);
    atomicMax(S.v[smp_word(r, SR_MAX_OVERLAP)], floatBitsToUint(delta));
  }
  if (vb != 0) smp_add64(r, SR_PAIR_LIQ, vb);
  if (vb > 0) {
    atomicAdd(S.v[smp_word(r, SR_BRIDGES)], 1u);
    if (touching) atomicAdd(S.v[smp_word(r, SR_TOUCH_BRIDGED)], 1u);
    uint slot = atomicAdd(S.v[SMP_PAIRS], 1u);
    if (slot < S.v[SMP_CAPACITY]) {
      uint a = uint(pi4.w), b = uint(pj4.w);
      UVec4s(smp_pairs_addr()).v[slot] = uvec4(min(a, b), max(a, b), uint(uint64_t(vb) & 0xffffffffUL),
                                             uint(uint64_t(vb) >> 32));
    }
  }
}
