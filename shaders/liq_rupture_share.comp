#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4a (per particle) on its own: the step recorded pass by pass (SystemOptions::fused_step off)
// and the events of an upload. The fused step runs the same function inside gather_kick.
#include "rupture_share.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity();
  rupture_share(i, s, PRM_OF(i, s), true);
}
