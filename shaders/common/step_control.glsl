// The end of a step's passes (ARCHITECTURE.md "Passes of a step"): the rebuild decision and, in the fused
// step, the test that finds the last workgroup of a dispatch, which takes that decision (and opens the gate
// of the liquid passes) without a dispatch of its own.
#ifndef WETDEM_STEP_CONTROL_GLSL
#define WETDEM_STEP_CONTROL_GLSL
#include "geom.glsl"

// A halted submit's remaining steps: every pass of a step is then sized to zero workgroups (its invocations
// would only return), until the chain that the host runs next reopens them (flip).
void close_step_passes() {
  Uints C = CTL();
  C.v[CTL_STEP_ARGS] = 0u;
  C.v[CTL_OWNER_ARGS] = 0u;
  for (uint k = 0u; k < 3u; ++k) C.v[CTL_LIQ_ARGS + 3u * k] = 0u;
}

// Whether the list's pairs may have closed in by the skin, by the two largest displacements of one frame.
bool skin_reached(float d1, float d2, uint rule, float skin) {
  return (rule & SKIN_TOP_TWO) != 0u ? d1 + d2 > skin : d1 > 0.5 * skin;
}

// Decides whether this step ends with a neighbour-list rebuild, and opens or closes the gate: every gated
// dispatch of the rebuild chain reads its size from ctl[CTL_GATE_ARGS + 4k]. split: the chain is not recorded
// after this step; a rebuild step halts with CTL_HALT = 2 and the host submits the chain on its own
// (host/gpu/system.cpp). count: a step that does not rebuild is counted here (what end_step does). One
// invocation; the displacement is read and reset with an atomic, as other workgroups wrote it with atomics.
void decide_rebuild(bool split, bool count) {
  Uints C = CTL();
  Params P = PRM();
  float disp = uintBitsToFloat(atomicExchange(C.v[CTL_MAX_DISP], 0u));
  float disp2 = uintBitsToFloat(atomicExchange(C.v[CTL_MAX_DISP2], 0u));
  float fdisp = uintBitsToFloat(atomicExchange(C.v[CTL_MAX_FDISP], 0u));
  float fdisp2 = uintBitsToFloat(atomicExchange(C.v[CTL_MAX_FDISP2], 0u));
  // A pair unlisted at the build was at least skin farther apart than its interaction range; since then it
  // has closed in by at most d_i + d_j <= disp + disp2 (the classic rule bounds that by 2 disp), in the lab
  // frame and in the drum's alike: the list is complete while either bound stays within the skin.
  uint rule = C.v[CTL_SKIN_RULE];
  bool moved = skin_reached(disp, disp2, rule, P.skin);
  if ((rule & SKIN_DRUM_FRAME) != 0u) moved = moved && skin_reached(fdisp, fdisp2, rule, P.skin);
  bool rebuild = C.v[CTL_FORCE_REBUILD] != 0u || moved;
  C.v[CTL_FORCE_REBUILD] = 0u;
  C.v[CTL_REBUILD] = rebuild ? 1u : 0u;
  C.v[CTL_SINCE_BUILD] = rebuild ? 0u : C.v[CTL_SINCE_BUILD] + 1u;
  if (rebuild) C.v[CTL_REBUILDS] += 1u;
  for (uint k = 0u; k < CTL_MAX_GATES; ++k) {
    C.v[CTL_GATE_ARGS + 4u * k] = rebuild ? C.v[CTL_GATE_GROUPS + k] : 0u;
    C.v[CTL_GATE_ARGS + 4u * k + 1u] = 1u;
    C.v[CTL_GATE_ARGS + 4u * k + 2u] = 1u;
  }
  // Passes over the list being built are sized by build_args on rebuild steps; closed otherwise.
  if (!rebuild) C.v[CTL_BUILD_ARGS] = 0u;
  // The old list is checked for bridges that would leave with a pair (must not happen, ARCHITECTURE.md).
  C.v[CTL_LOST_ARGS] = rebuild ? C.v[CTL_ENTRY_ARGS] : 0u;
  C.v[CTL_LOST_ARGS + 1u] = 1u;
  C.v[CTL_LOST_ARGS + 2u] = 1u;
  if (split && rebuild) {
    C.v[CTL_HALT] = CTL_HALT_FOR_REBUILD;
    close_step_passes();
  }
  if (count && !rebuild) C.v[CTL_STEPS] += 1u;  // end_step: CTL_REBUILD is already 0
}

// The skin test's displacements (m) of a particle at p since the list was built with it at ref (ticks), in
// the lab frame (x) and in the drum's (y), and their share in the test: the largest and the second largest
// of each are kept with integer atomics (max of non-negative float bits; the value a larger one displaces, or
// the smaller of the two, goes on to the second, so the pair ends as the two largest in any order).
//
// In the drum's frame (SKIN_DRUM_FRAME) the reference is first turned about the drum axis (z, through the tick
// origin) by the angle the drum has turned since the build, a = omega dt (steps since the build + 1): a
// rotation keeps every pair distance (and the periodic z images), so |x_i - x_j| - |x_i,ref - x_j,ref| <=
// |x_i - R x_i,ref| + |x_j - R x_j,ref| for any R the same for both, and a bed that turns with the drum has not
// moved. The bound holds whatever the angle, so the angle only decides how tight it is (a run's drum speed,
// per run in an ensemble: pairs never cross runs). A flowing layer moves more in the drum's frame than in the
// lab's (its rigid velocity is across the flow), hence both bounds, and the tighter one decides. R is made
// exactly orthogonal to float precision by normalising (cos, sin), whatever the driver's sin precision;
// x - R ref = (x - ref) + (I - R) ref keeps the large coordinates out of the subtraction, and a margin of
// 2 ticks + 1e-6 |ref| covers the float rounding.
vec2 skin_displacements(ivec3 p, ivec3 ref, Params P) {
  vec3 d = vec3(tick_delta(p, ref, P.period_ticks));
  float lab = length(d) * P.h;
  if ((CTL().v[CTL_SKIN_RULE] & SKIN_DRUM_FRAME) == 0u || P.omega == 0.0) return vec2(lab);
  float a = P.omega * P.dt * float(CTL().v[CTL_SINCE_BUILD] + 1u);
  vec2 cs = vec2(cos(a), sin(a));
  cs *= inversesqrt(dot(cs, cs));
  vec2 r = vec2(ref.xy);
  float om = 1.0 - cs.x;  // exact in float while cos >= 0.5 (Sterbenz)
  d.xy += vec2(om * r.x + cs.y * r.y, om * r.y - cs.y * r.x);
  return vec2(lab, (length(d) + 2.0 + 1e-6 * length(r)) * P.h);
}

// The two words only grow during the pass (the decision resets them), so a displacement no larger than the
// second largest seen so far cannot enter the two largest: most invocations read one word and skip both
// atomics (a stale read only lets one through that was not needed), instead of contending on two addresses.
void share_max2(uint first, uint second, float disp) {
  uint b = floatBitsToUint(disp);
  if (b <= CTL().v[second]) return;
  uint old = atomicMax(CTL().v[first], b);
  atomicMax(CTL().v[second], min(old, b));
}

void share_displacements(vec2 disp) {
  share_max2(CTL_MAX_DISP, CTL_MAX_DISP2, disp.x);
  if ((CTL().v[CTL_SKIN_RULE] & SKIN_DRUM_FRAME) != 0u) share_max2(CTL_MAX_FDISP, CTL_MAX_FDISP2, disp.y);
}

// True in the one workgroup of this dispatch that finishes last, after every other workgroup's writes
// (made visible before it counted itself). Every invocation must call it, in uniform control flow; the last
// workgroup resets the counter for the next pass. The classic last-block reduction: integer atomics only.
shared bool s_last_group;
bool last_workgroup() {
  memoryBarrierBuffer();
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    uint total = gl_NumWorkGroups.x * gl_NumWorkGroups.y * gl_NumWorkGroups.z;
    uint done = atomicAdd(CTL().v[CTL_DONE_GROUPS], 1u) + 1u;
    s_last_group = done == total;
    if (done == total) {
      memoryBarrierBuffer();
      atomicExchange(CTL().v[CTL_DONE_GROUPS], 0u);
    }
  }
  barrier();
  return s_last_group;
}
#endif
