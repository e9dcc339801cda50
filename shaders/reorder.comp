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
  ivec4 p = IVec4s(paddr(s, PF_POS)).v[o];
  IVec4s(paddr(t, PF_POS)).v[i] = p;
  IVec4s(T().ref_pos).v[i] = p;
  Vec4s(paddr(t, PF_VEL)).v[i] = Vec4s(paddr(s, PF_VEL)).v[o];
  Vec4s(paddr(t, PF_OMG)).v[i] = Vec4s(paddr(s, PF_OMG)).v[o];
  Vec4s(paddr(t, PF_PROPS)).v[i] = Vec4s(paddr(s, PF_PROPS)).v[o];
  Vec3s(paddr(t, PF_FORCE)).v[i] = Vec3s(paddr(s, PF_FORCE)).v[o];
  Vec3s(paddr(t, PF_TORQUE)).v[i] = Vec3s(paddr(s, PF_TORQUE)).v[o];
  Int64s(paddr(t, PF_FILM)).v[i] = Int64s(paddr(s, PF_FILM)).v[o];
  Vec4s(paddr(t, PF_FRAC)).v[i] = Vec4s(paddr(s, PF_FRAC)).v[o];
  Int64s(paddr(t, PF_PORE)).v[i] = Int64s(paddr(s, PF_PORE)).v[o];
  Int64s(paddr(t, PF_EVAP)).v[i] = Int64s(paddr(s, PF_EVAP)).v[o];
  Int64s(paddr(t, PF_PORECAP)).v[i] = Int64s(paddr(s, PF_PORECAP)).v[o];
  uint ns = P.wall_slots;  // the walls the drum has (access.glsl wall_slot)
  for (uint w = 0u; w < ns; ++w) {
    Vec4s(paddr(t, PF_WST)).v[ns * i + w] = Vec4s(paddr(s, PF_WST)).v[ns * o + w];
    Vec4s(paddr(t, PF_WSR)).v[ns * i + w] = Vec4s(paddr(s, PF_WSR)).v[ns * o + w];
    Int64s(paddr(t, PF_WLIQ)).v[ns * i + w] = Int64s(paddr(s, PF_WLIQ)).v[ns * o + w];
    Uints(paddr(t, PF_WFLAGS)).v[ns * i + w] = Uints(paddr(s, PF_WFLAGS)).v[ns * o + w];
  }
}
