#version 460
#extension GL_GOOGLE_include_directive : require
// Sampling, second pass over particles (sample.glsl): per run, the mass, the mass-weighted position and the
// kinetic energy as exact integer sums of q = round(value / scale * 2^bits), the scales being the run's largest
// mass (times the drum's half extent for positions) and largest kinetic energy from sample_max. The host
// divides back: the centre of mass Σ q_mx / Σ q_m times the half extent, the energy Σ q_ke times its scale.
#include "geom.glsl"
#include "sample.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles) return;
  uint s = parity();
  ivec4 p = IVec4s(paddr(s, PF_POS)).v[i];
  uint r = run_of_id(p.w);
  Uints S = Uints(smp_addr());
  vec4 pr = Vec4s(paddr(s, PF_PROPS)).v[i];
  float m_max = uintBitsToFloat(S.v[smp_word(r, SR_MAX_MASS)]);
  float ke_max = uintBitsToFloat(S.v[smp_word(r, SR_MAX_KE)]);
  float ext = Floats(smp_addr()).v[smp_word(r, SR_EXTENT)];  // half extent of the drum (m), from the host
  float mq = pr.y / m_max;
  smp_add64(r, SR_MASS, int64_t(round(mq * exp2(SMP_MASS_BITS))));
  vec3 x = (vec3(p.xyz) + Vec4s(paddr(s, PF_FRAC)).v[i].xyz) * P.h;
  vec3 q = clamp(mq * x / ext, vec3(-1.0), vec3(1.0)) * exp2(SMP_MASS_BITS);
  if (!any(isnan(q))) {
    smp_add64(r, SR_MX, int64_t(round(q.x)));
    smp_add64(r, SR_MY, int64_t(round(q.y)));
    smp_add64(r, SR_MZ, int64_t(round(q.z)));
  } else {
    atomicAdd(S.v[smp_word(r, SR_NONFINITE)], 1u);
  }
  vec3 v = Vec4s(paddr(s, PF_VEL)).v[i].xyz, w = Vec4s(paddr(s, PF_OMG)).v[i].xyz;
  float ke = 0.5 * pr.y * dot(v, v) + 0.5 * pr.z * dot(w, w);
  if (ke_max > 0.0 && !isnan(ke) && !isinf(ke))
    smp_add64(r, SR_KE, int64_t(round(ke / ke_max * exp2(SMP_KE_BITS))));
}
