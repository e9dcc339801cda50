#version 460
#extension GL_GOOGLE_include_directive : require
// The per-particle pass of a step (physics.md §0), in the modes of pc.arg0 (modes.glsl):
//   GK_GATHER      sum the pair results of the particle's list segment in list order (owner entries: +F, T_i;
//                  mirrored entries: -F, T_j of the owner, written there by pair_force), add the walls, store
//                  F and T, second half kick. Then the largest distance between the positions of the next
//                  force evaluation and those of the last list build, for the skin test.
//   GK_SHARE       liquid pass 4a (rupture_share.glsl) on the walls' and pairs' flags of this step.
//   GK_KICK_DRIFT  the first half kick of the next step with that force, and its drift in fixed point. The
//                  fused step folds it in here (one pass fewer per step); a submit's first step, and the step
//                  recorded pass by pass, run it on its own (no GK_GATHER: F, T, v from the buffers).
//   GK_FINISH      the last workgroup opens or closes the liquid passes of this step (GK_GATE: closed when
//                  no contact was flagged for an event and no sink is on; they would change nothing) and,
//                  when none follows, takes the rebuild decision (step_control.glsl).
// Both kicks and the drift are `precise` (no fused multiply-add) and written once, so that a step gives
// bitwise the same numbers whether its kick-drift ran here or on its own: the batch lengths that decide it
// must not change a run.
#include "walls.glsl"
#include "rupture_share.glsl"
#include "step_control.glsl"
#include "modes.glsl"
layout(local_size_x = 256) in;

void gather_kick(uint i, uint s, uint mode) {
  Params P = PRM_OF(i, s);
  vec4 pr = load_v4(paddr(s, PF_PROPS), i);  // radius, mass, inertia
  vec3 g = vec3(P.gravity[0], P.gravity[1], P.gravity[2]);
  const float hdt = 0.5 * P.dt;
  vec3 v = load_v4(paddr(s, PF_VEL), i).xyz, w = load_v4(paddr(s, PF_OMG), i).xyz, F, Tq;
  if ((mode & GK_GATHER) != 0u) {
    Uints nbr_off = Uints(paddr(s, PF_NOFFSET)), nbr_cnt = Uints(paddr(s, PF_NCOUNT));
    F = vec3(0.0);
    Tq = vec3(0.0);
    uint b = nbr_off.v[i], c = nbr_cnt.v[i];
    for (uint e = b; e < b + c; ++e) {
      vec4 ft = load_v4(T().pair_f, e);  // (F, T.x); a mirrored entry holds -F of its owner: x + (-y) is x - y
      F += ft.xyz;
      Tq += vec3(ft.w, load_v2(T().pair_t, e));
    }
    for (uint k = 0u; k < 3u; ++k) wall_contact(k, i, s, P, F, Tq);
    store_v4(paddr(s, PF_FORCE), i, vec4(F, Tq.x));  // (F, T.x), (T.y, T.z): access.glsl
    store_v2(paddr(s, PF_TORQUE), i, Tq.yz);
    precise vec3 a = F / pr.y + g;
    precise vec3 al = Tq / pr.z;
    precise vec3 v1 = v + hdt * a;
    precise vec3 w1 = w + hdt * al;
    v = v1;
    w = w1;
    if ((mode & GK_LIQUID) != 0u) {  // wall events of this step: candidates for the liquid gate
      Uints wfl = Uints(paddr(s, PF_WFLAGS));
      uint wf = 0u;
      for (uint k = 0u; k < P.wall_slots; ++k) wf |= wfl.v[i * P.wall_slots + k];
      uint cand = ((wf & FLAG_RUPT) != 0u ? CAND_RUPT : 0u) | ((wf & FLAG_FORM) != 0u ? CAND_FORM : 0u);
      if (cand != 0u) atomicOr(CTL().v[CTL_CAND_WALL], cand);
    }
    if ((mode & GK_SHARE) != 0u) rupture_share(i, s, P, (CTL().v[CTL_CAND_PAIR] & CAND_RUPT) != 0u);
  } else {
    vec4 ft = load_v4(paddr(s, PF_FORCE), i);
    F = ft.xyz;
    Tq = vec3(ft.w, load_v2(paddr(s, PF_TORQUE), i));
  }
  // The next step's first half kick and drift: stored when folded here or run on its own; after a gather
  // it also gives the positions of the next force evaluation, where the list must hold every pair (the skin
  // test below), the same numbers whichever way the step is recorded.
  precise vec3 a2 = F / pr.y + g;
  precise vec3 al2 = Tq / pr.z;
  precise vec3 v2 = v + hdt * a2;
  precise vec3 w2 = w + hdt * al2;
  ivec4 p = load_i4(paddr(s, PF_POS), i);
  vec4 f = load_v4(paddr(s, PF_FRAC), i);
  // Displacement in ticks: whole ticks move the integer position, the remainder stays in the fraction.
  precise vec3 fx = f.xyz + v2 * (P.dt * P.inv_h);
  vec3 carry = roundEven(fx);
  f.xyz = fx - carry;
  p.xyz += ivec3(carry);
  p.z = wrap_z(p.z, P.period_ticks);
  if ((mode & GK_KICK_DRIFT) != 0u) {
    v = v2;
    w = w2;
    store_i4(paddr(s, PF_POS), i, p);
    store_v4(paddr(s, PF_FRAC), i, f);
  }
  store_v4(paddr(s, PF_VEL), i, vec4(v, 0.0));
  store_v4(paddr(s, PF_OMG), i, vec4(w, 0.0));
  bool gather = (mode & GK_GATHER) != 0u;
  // The skin test's displacement (step_control.glsl): the decision reads the two largest.
  if (gather) share_displacements(skin_displacements(p.xyz, load_i4(T().ref_pos, i).xyz, P));
}

// Last workgroup of the fused gather: the sizes of this step's liquid passes 4b, 4c, 4d, and the rebuild
// decision when no liquid pass follows (else 4d takes it).
void finish(uint mode) {
  Uints C = CTL();
  uint cand = atomicExchange(C.v[CTL_CAND_PAIR], 0u) | atomicExchange(C.v[CTL_CAND_WALL], 0u);
  bool liquid = (mode & GK_LIQUID) != 0u;
  bool gate = (mode & GK_GATE) != 0u;
  bool rupt = !gate || (cand & CAND_RUPT) != 0u;
  bool films = rupt || (cand & CAND_FORM) != 0u || (mode & GK_SINKS) != 0u;
  uint owners = C.v[CTL_OWNER_ARGS];
  C.v[CTL_CAND_STEP] = gate ? cand : (CAND_RUPT | CAND_FORM);
  C.v[CTL_LIQ_ARGS + 0u] = liquid && rupt ? owners : 0u;                        // 4b over owner pairs
  C.v[CTL_LIQ_ARGS + 3u] = liquid && films ? (PRM().num_particles + 255u) / 256u : 0u;  // 4c
  C.v[CTL_LIQ_ARGS + 6u] = liquid && films ? max(owners, 1u) : 0u;            // 4d: >= 1 group, it decides
  for (uint k = 0u; k < 3u; ++k) {
    C.v[CTL_LIQ_ARGS + 3u * k + 1u] = 1u;
    C.v[CTL_LIQ_ARGS + 3u * k + 2u] = 1u;
  }
  if (liquid && films) C.v[CTL_LIQ_STEPS] += 1u;
  else decide_rebuild((mode & GK_SPLIT) != 0u, true);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint mode = pc.arg0;
  if (halted()) return;
  uint s = parity();
  // A submit's first kick-drift has nothing to do when the step before it (that submit's halted step, whose
  // rebuild ran on its own) already did it.
  if ((mode & GK_UNLESS_DRIFTED) != 0u && CTL().v[CTL_DRIFTED] != 0u) return;
  if (i < PRM().num_particles) gather_kick(i, s, mode);
  if ((mode & GK_GATHER) != 0u && i == 0u) CTL().v[CTL_DRIFTED] = (mode & GK_KICK_DRIFT) != 0u ? 1u : 0u;
  if ((mode & GK_FINISH) != 0u && last_workgroup() && gl_LocalInvocationIndex == 0u) finish(mode);
}
