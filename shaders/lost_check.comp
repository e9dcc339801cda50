#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6j: an owner entry of the old list that holds a bridge but was not carried into the new list
// would lose liquid. The end-of-step rebuild order makes this impossible; this pass proves it each time.
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint e = gl_GlobalInvocationID.x;
  if (halted()) return;
  Uints C = CTL();
  if (e >= C.v[CTL_ENTRIES]) return;
  uint s = parity();
  if (Uints(eaddr(s, EF_MIRROR)).v[e] != e) return;
  uint fl = Uints(eaddr(s, EF_FLAGS)).v[e];
  if (Int64s(eaddr(s, EF_LIQ)).v[e] > 0 && (fl & FLAG_MAPPED) == 0u) atomicAdd(C.v[CTL_LOST], 1u);
}
