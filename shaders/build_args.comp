#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6f (one invocation): after the scan, size the new list. More entries than capacity: halt the
// submit (every later pass returns at once or is sized to zero); the host grows the buffers and finishes
// this rebuild.
#include "step_control.glsl"
layout(local_size_x = 1) in;
void main() {
  Uints C = CTL();
  if (C.v[CTL_HALT] != 0u) return;
  uint need = C.v[CTL_ENTRIES_NEEDED];
  if (need > C.v[CTL_CAPACITY0 + 1u - C.v[CTL_PARITY]]) {  // capacity of the set being built
    C.v[CTL_HALT] = 1u;
    C.v[CTL_OVERFLOWS] += 1u;
    // Close the gates: sort and scan kernels do not read the halt flag, and the sorted keys, permutation and
    // counts of this rebuild must survive untouched until the host has grown the buffers and finished it.
    for (uint k = 0u; k < CTL_MAX_GATES; ++k) C.v[CTL_GATE_ARGS + 4u * k] = 0u;
    close_step_passes();
    return;
  }
  C.v[CTL_BUILD_ARGS] = (need + 255u) / 256u;
  C.v[CTL_BUILD_ARGS + 1u] = 1u;
  C.v[CTL_BUILD_ARGS + 2u] = 1u;
}
