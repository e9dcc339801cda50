#version 460
#extension GL_GOOGLE_include_directive : require
// Pass 5 (one invocation): decide whether this step ends with a neighbour-list rebuild, and open or close
// the gate: every gated dispatch of the rebuild chain reads its size from ctl[CTL_GATE_ARGS + 4k].
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
}
