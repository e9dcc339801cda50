#version 460
#extension GL_GOOGLE_include_directive : require
// Pass 3: per particle, sum the pair results of its list segment in list order (owner entries: +F, T_i;
// mirrored entries: -F, T_j of the owner, written there by pair_force), add the walls, then the second half
// kick (physics.md §0).
// Also the largest predicted displacement since the last list build, for the skin test.
#include "walls.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity();
  P = PRM_OF(i, s);
  Uints nbr_off = Uints(paddr(s, PF_NOFFSET)), nbr_cnt = Uints(paddr(s, PF_NCOUNT));
  Vec4s pf = Vec4s(T().pair_f), pt = Vec4s(T().pair_t);
  vec3 F = vec3(0.0), Tq = vec3(0.0);
  uint b = nbr_off.v[i], c = nbr_cnt.v[i];
  for (uint e = b; e < b + c; ++e) {
    F += pf.v[e].xyz;  // a mirrored entry holds -F of its owner: x + (-y) is x - y exactly
    Tq += pt.v[e].xyz;
  }
  for (uint w = 0u; w < 3u; ++w) wall_contact(w, i, s, P, F, Tq);

  Vec4s vel = Vec4s(paddr(s, PF_VEL)), omg = Vec4s(paddr(s, PF_OMG));
  vec4 pr = Vec4s(paddr(s, PF_PROPS)).v[i];
  vec3 g = vec3(P.gravity[0], P.gravity[1], P.gravity[2]);
  vec3 v = vel.v[i].xyz + (0.5 * P.dt) * (F / pr.y + g);
  vel.v[i] = vec4(v, 0.0);
  omg.v[i] = vec4(omg.v[i].xyz + (0.5 * P.dt) * (Tq / pr.z), 0.0);
  Vec4s(paddr(s, PF_FORCE)).v[i] = vec4(F, 0.0);
  Vec4s(paddr(s, PF_TORQUE)).v[i] = vec4(Tq, 0.0);

  // Displacement since the last build plus one step of motion: the list must stay valid at the next
  // force evaluation (rebuild when this exceeds skin/2). Max of non-negative floats = max of their bits.
  ivec3 dp = tick_delta(IVec4s(paddr(s, PF_POS)).v[i].xyz, IVec4s(T().ref_pos).v[i].xyz, P.period_ticks);
  float disp = length(vec3(dp)) * P.h + length(v) * P.dt;
  atomicMax(CTL().v[CTL_MAX_DISP], floatBitsToUint(disp));
}
