// The end of a step's passes (ARCHITECTURE.md "Passes of a step"): the rebuild decision and, in the fused
// step, the test that finds the last workgroup of a dispatch, which takes that decision (and opens the gate
// of the liquid passes) without a dispatch of its own.
#ifndef WETDEM_STEP_CONTROL_GLSL
#define WETDEM_STEP_CONTROL_GLSL
#include "access.glsl"

// A halted submit's remaining steps: every pass of a step is then sized to zero workgroups (its invocations
// would only return), until the chain that the host runs next reopens them (flip).
void close_step_passes() {
  Uints C = CTL();
  C.v[CTL_STEP_ARGS] = 0u;
  C.v[CTL_OWNER_ARGS] = 0u;
  for (uint k = 0u; k < 3u; ++k) C.v[CTL_LIQ_ARGS + 3u * k] = 0u;
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
  bool rebuild = C.v[CTL_FORCE_REBUILD] != 0u || disp > 0.5 * P.skin;
  C.v[CTL_FORCE_REBUILD] = 0u;
  C.v[CTL_REBUILD] = rebuild ? 1u : 0u;
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
