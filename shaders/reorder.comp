#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6c: gather every per-particle field from the current set into the other set in cell order
// (new index i takes old index sort_val[i]); the new positions become the skin reference.
#include "access.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity(), t = 1u - s;
  uint o = Uints(T().sort_val).v[i];
  // 16-byte fields are moved as two 64-bit words (table.glsl): the same bytes in half lavapipe's loops.
  uvec4 p = load_u4(paddr(s, PF_POS), o);
  store_u4(paddr(t, PF_POS), i, p);
  store_u4(T().ref_pos, i, p);
  store_u4(paddr(t, PF_VEL), i, load_u4(paddr(s, PF_VEL), o));
  store_u4(paddr(t, PF_OMG), i, load_u4(paddr(s, PF_OMG), o));
  store_u4(paddr(t, PF_PROPS), i, load_u4(paddr(s, PF_PROPS), o));
  store_u4(paddr(t, PF_FORCE), i, load_u4(paddr(s, PF_FORCE), o));
  U64s(paddr(t, PF_TORQUE)).v[i] = U64s(paddr(s, PF_TORQUE)).v[o];
  Int64s(paddr(t, PF_FILM)).v[i] = Int64s(paddr(s, PF_FILM)).v[o];
  store_u4(paddr(t, PF_FRAC), i, load_u4(paddr(s, PF_FRAC), o));
  Int64s(paddr(t, PF_PORE)).v[i] = Int64s(paddr(s, PF_PORE)).v[o];
  Int64s(paddr(t, PF_EVAP)).v[i] = Int64s(paddr(s, PF_EVAP)).v[o];
  Int64s(paddr(t, PF_PORECAP)).v[i] = Int64s(paddr(s, PF_PORECAP)).v[o];
  uint ns = P.wall_slots;  // the walls the drum has (access.glsl wall_slot)
  for (uint w = 0u; w < ns; ++w) {
    store_u4(paddr(t, PF_WST), ns * i + w, load_u4(paddr(s, PF_WST), ns * o + w));
    store_u4(paddr(t, PF_WSR), ns * i + w, load_u4(paddr(s, PF_WSR), ns * o + w));
    Int64s(paddr(t, PF_WLIQ)).v[ns * i + w] = Int64s(paddr(s, PF_WLIQ)).v[ns * o + w];
    Uints(paddr(t, PF_WFLAGS)).v[ns * i + w] = Uints(paddr(s, PF_WFLAGS)).v[ns * o + w];
  }
}
