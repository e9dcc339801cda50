#version 460
#extension GL_GOOGLE_include_directive : require
// Pass 1 of a step (physics.md §0): first half kick with the stored force, then drift in fixed point.
#include "geom.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = parity();
  P = PRM_OF(i, s);
  IVec4s pos = IVec4s(paddr(s, PF_POS));
  Vec4s vel = Vec4s(paddr(s, PF_VEL)), omg = Vec4s(paddr(s, PF_OMG)), props = Vec4s(paddr(s, PF_PROPS));
  Vec4s force = Vec4s(paddr(s, PF_FORCE)), torque = Vec4s(paddr(s, PF_TORQUE));
  vec4 pr = props.v[i];  // radius, mass, inertia
  vec3 g = vec3(P.gravity[0], P.gravity[1], P.gravity[2]);
  vec3 v = vel.v[i].xyz + (0.5 * P.dt) * (force.v[i].xyz / pr.y + g);
  vec3 w = omg.v[i].xyz + (0.5 * P.dt) * (torque.v[i].xyz / pr.z);
  vel.v[i] = vec4(v, 0.0);
  omg.v[i] = vec4(w, 0.0);
  ivec4 p = pos.v[i];
  Vec4s frac = Vec4s(paddr(s, PF_FRAC));
  vec4 f = frac.v[i];
  // Displacement in ticks: whole ticks move the integer position, the remainder stays in the fraction.
  f.xyz += v * (P.dt * P.inv_h);
  vec3 carry = roundEven(f.xyz);
  f.xyz -= carry;
  p.xyz += ivec3(carry);
  p.z = wrap_z(p.z, P.period_ticks);
  pos.v[i] = p;
  frac.v[i] = f;
}
