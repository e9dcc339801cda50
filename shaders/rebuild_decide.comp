#version 460
#extension GL_GOOGLE_include_directive : require
// Pass 5 (one invocation): decide whether this step ends with a neighbour-list rebuild, and open or close
// the gate: every gated dispatch of the rebuild chain reads its size from ctl[CTL_GATE_ARGS + 4k].
// pc.arg0 = 1 (split rebuilds: the chain is not recorded after this pass): a rebuild step halts here with
// CTL_HALT = 2, and the host submits the chain and end_step on their own (host/gpu/system.cpp); any other
// step ends here, doing what end_step does (one dispatch and barrier fewer per step).
#include "access.glsl"
layout(local_size_x = 1) in;
void main() {
  Uints C = CTL();
  if (C.v[CTL_HALT] != 0u) return;
  Params P = PRM();
  float disp = uintBitsToFloat(C.v[CTL_MAX_DISP]);
  bool rebuild = C.v[CTL_FORCE_REBUILD] != 0u || disp > 0.5 * P.skin;
  C.v[CTL_MAX_DISP] = 0u;
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
  if (pc.arg0 != 0u) {
    if (rebuild)
      C.v[CTL_HALT] = CTL_HALT_FOR_REBUILD;
    else
      C.v[CTL_STEPS] += 1u;  // end_step: CTL_REBUILD is already 0
  }
}
