#version 460
#extension GL_GOOGLE_include_directive : require
// Pass 5 of the step recorded pass by pass (SystemOptions::fused_step off) and of an upload (one invocation):
// decide whether this step ends with a neighbour-list rebuild and open or close the rebuild chain's gate
// (step_control.glsl). pc.arg0 = 1 (split rebuilds: the chain is not recorded after this pass): a rebuild
// step halts here with CTL_HALT = 2, and any other step ends here, doing what end_step does. The fused step
// takes this decision in the last workgroup of its last pass instead.
#include "step_control.glsl"
layout(local_size_x = 1) in;
void main() {
  if (CTL().v[CTL_HALT] != 0u) return;
  decide_rebuild(pc.arg0 != 0u, pc.arg0 != 0u);
}
