#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6n (one invocation): the new set (and its owner list) becomes current. pc.arg0 = 1: this ends the
// step (the fused step's gated chain: its rebuild decision counted only the steps that do not rebuild).
#include "access.glsl"
layout(local_size_x = 1) in;
void main() {
  Uints C = CTL();
  if (C.v[CTL_HALT] != 0u) return;
  C.v[CTL_PARITY] = 1u - C.v[CTL_PARITY];
  C.v[CTL_ENTRIES] = C.v[CTL_ENTRIES_NEEDED];
  C.v[CTL_ENTRY_ARGS] = C.v[CTL_BUILD_ARGS];
  C.v[CTL_ENTRY_ARGS + 1u] = 1u;
  C.v[CTL_ENTRY_ARGS + 2u] = 1u;
  C.v[CTL_OWNERS] = C.v[CTL_OWNERS_NEEDED];
  C.v[CTL_OWNER_ARGS] = (C.v[CTL_OWNERS_NEEDED] + 255u) / 256u;
  C.v[CTL_OWNER_ARGS + 1u] = 1u;
  C.v[CTL_OWNER_ARGS + 2u] = 1u;
  C.v[CTL_STEP_ARGS] = (PRM().num_particles + 255u) / 256u;  // reopened after a halted submit
  C.v[CTL_STEP_ARGS + 1u] = 1u;
  C.v[CTL_STEP_ARGS + 2u] = 1u;
  if (pc.arg0 != 0u) {
    C.v[CTL_STEPS] += 1u;
    C.v[CTL_REBUILD] = 0u;
  }
}
