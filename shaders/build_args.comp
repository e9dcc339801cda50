#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6f (one invocation): after the scan, size the new list. More entries than capacity: halt the
// submit (every later pass returns at once); the host grows the buffers and finishes this rebuild.
#include "access.glsl"
layout(local_size_x = 1) in;
void main() {
  Uints C = CTL();
  if (C.v[CTL_HALT] != 0u) return;
  uint need = C.v[CTL_ENTRIES_NEEDED];
  if (need > C.v[CTL_CAPACITY0 + 1u - C.v[CTL_PARITY]]) {  // capacity of the set being built
    C.v[CTL_HALT] = 1u;
    C.v[CTL_OVERFLOWS] += 1u;
    return;
  }
  C.v[CTL_BUILD_ARGS] = (need + 255u) / 256u;
  C.v[CTL_BUILD_ARGS + 1u] = 1u;
  C.v[CTL_BUILD_ARGS + 2u] = 1u;
}
