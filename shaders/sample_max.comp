#version 460
#extension GL_GOOGLE_include_directive : require
// Sampling, first pass over particles (sample.glsl): per run, the largest mass and kinetic energy (the scales of
// the fixed-point sums of sample_sum), and the integer sums and counts: films, pores, evaporated liquid, wall
// bridges, touching walls and the largest wall overlap (the same wall geometry as gather_kick).
#include "walls.glsl"
#include "sample.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles) return;
  uint s = parity();
  ivec4 p = IVec4s(paddr(s, PF_POS)).v[i];
  uint r = run_of_id(p.w);
  P = PRMR(r);
  Uints S = Uints(smp_addr());
  vec4 pr = Vec4s(paddr(s, PF_PROPS)).v[i];
  vec3 v = Vec4s(paddr(s, PF_VEL)).v[i].xyz, w = Vec4s(paddr(s, PF_OMG)).v[i].xyz;
  float ke = 0.5 * pr.y * dot(v, v) + 0.5 * pr.z * dot(w, w);
  if (isnan(ke) || isinf(ke))
    atomicAdd(S.v[smp_word(r, SR_NONFINITE)], 1u);
  else
    atomicMax(S.v[smp_word(r, SR_MAX_KE)], floatBitsToUint(ke));  // ke >= 0: bits order as values
  atomicMax(S.v[smp_word(r, SR_MAX_MASS)], floatBitsToUint(pr.y));
  smp_add64(r, SR_FILMS, Int64s(paddr(s, PF_FILM)).v[i]);
  smp_add64(r, SR_PORES, Int64s(paddr(s, PF_PORE)).v[i]);
  smp_add64(r, SR_EVAP, Int64s(paddr(s, PF_EVAP)).v[i]);
  vec4 pf = Vec4s(paddr(s, PF_FRAC)).v[i];
  Int64s wliq = Int64s(paddr(s, PF_WLIQ));
  for (uint k = 0u; k < 3u; ++k) {
    if (!wall_present(k, P)) continue;  // no record, and no contact (walls.glsl)
    int64_t vb = wliq.v[wall_slot(i, k, P)];
    if (vb != 0) smp_add64(r, SR_WALL_LIQ, vb);
    if (vb > 0) atomicAdd(S.v[smp_word(r, SR_WALL_BRIDGES)], 1u);
    float delta, wom;
    vec3 n;
    if (wall_geometry(k, p.xyz, pf.xyz, floatBitsToInt(pr.w), pf.w, P, delta, n, wom) && delta > 0.0) {
      atomicAdd(S.v[smp_word(r, SR_WALL_CONTACTS)], 1u);
      atomicMax(S.v[smp_word(r, SR_MAX_OVERLAP)], floatBitsToUint(delta));
    }
  }
}
