#version 460
#extension GL_GOOGLE_include_directive : require
// Last pass of a step (one invocation): count the completed step.
#include "access.glsl"
layout(local_size_x = 1) in;
void main() {
  Uints C = CTL();
  if (C.v[CTL_HALT] != 0u) return;
  C.v[CTL_STEPS] += 1u;
  C.v[CTL_REBUILD] = 0u;
}
