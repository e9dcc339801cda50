#version 460
#extension GL_GOOGLE_include_directive : require
// Liquid pass 4e (per particle): films give what the new bridges took (gather over the list segment).
#include "liquid.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity();
  Uints off = Uints(paddr(s, PF_NOFFSET)), cnt = Uints(paddr(s, PF_NCOUNT));
  Uints mirror = Uints(eaddr(s, EF_MIRROR));
  Int64s ev_a = Int64s(T().ev_a), ev_b = Int64s(T().ev_b);
  int64_t taken = 0;
  uint b = off.v[i], c = cnt.v[i];
  for (uint e = b; e < b + c; ++e) {
    uint o = mirror.v[e];
    taken += (o == e) ? ev_a.v[o] : ev_b.v[o];
  }
  Int64s(paddr(s, PF_FILM)).v[i] -= taken;
}
