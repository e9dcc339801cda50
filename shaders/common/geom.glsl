// Fixed-point positions (ARCHITECTURE.md "Precision of positions"): a position is an integer number of
// ticks of h metres plus a float fraction of a tick in [-1/2, 1/2]; a radius likewise (props.w holds the
// integer ticks, frac.w the fraction).
#ifndef WETDEM_GEOM_GLSL
#define WETDEM_GEOM_GLSL
#include "access.glsl"

// Wraps z into [-P/2, P - P/2) on a periodic axis.
int wrap_z(int z, int P) {
  if (P <= 0) return z;
  int lo = -(P / 2);
  if (z < lo) z += P;
  else if (z >= lo + P) z -= P;
  return z;
}

// a - b in ticks with the minimum image on a periodic z axis: exact integer arithmetic.
ivec3 tick_delta(ivec3 a, ivec3 b, int P) {
  ivec3 d = a - b;
  if (P > 0) {
    int hp = P / 2;
    if (d.z > hp) d.z -= P;
    else if (d.z < -hp) d.z += P;
  }
  return d;
}

// Cell of a position. Dense grid (the drum): coordinates outside the grid are clamped to its edge cells
// and counted as escaped. Hashed grid (hash_mask != 0, domains much larger than the particles): the grid
// origin lies below every position, so coordinates are never clamped.
ivec3 cell_of(ivec3 p, Params P, out bool escaped) {
  ivec3 org = ivec3(P.grid_origin[0], P.grid_origin[1], P.grid_origin[2]);
  ivec3 c = (p - org) / P.cell_ticks;
  // A periodic axis is tiled by exactly grid_dims[2] cells of P/grid_dims[2] ticks (>= the cell edge).
  if (P.period_ticks > 0) c.z = int((int64_t(p.z - org.z) * P.grid_dims[2]) / int64_t(P.period_ticks));
  if (P.hash_mask != 0u) {
    escaped = false;
    return c;
  }
  ivec3 dims = ivec3(P.grid_dims[0], P.grid_dims[1], P.grid_dims[2]);
  ivec3 cc = clamp(c, ivec3(0), dims - 1);
  escaped = any(notEqual(c, cc)) || any(lessThan(p, org));
  return cc;
}

uint cell_index(ivec3 c, Params P) {
  if (P.hash_mask != 0u)
    return ((uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u)) & P.hash_mask;
  return uint(c.x + P.grid_dims[0] * (c.y + P.grid_dims[1] * c.z));
}

// Overlap r_i + r_j - |x_i - x_j| in ticks, with the unit normal from j to i. The large parts (integer
// ticks) enter only through exact int64 arithmetic: delta = (R^2 - d^2) / (R + d) with R^2 - d^2 split into
// an exact integer part and small float corrections, so delta keeps float32 relative precision however
// small it is, plus ~1e-7 ticks absolute.
float pair_overlap_ticks(ivec3 D, vec3 f, int Ri, float Rf, out vec3 n, out float dist) {
  int64_t D2 = int64_t(D.x) * D.x + int64_t(D.y) * D.y + int64_t(D.z) * D.z;
  vec3 Df = vec3(D);
  float corr = 2.0 * dot(Df, f) + dot(f, f);  // d^2 = D2 + corr
  dist = sqrt(float(D2) + corr);
  n = (Df + f) / dist;
  float num = float(int64_t(Ri) * int64_t(Ri) - D2) + (2.0 * float(Ri) * Rf + Rf * Rf) - corr;
  return num / (float(Ri) + Rf + dist);
}
#endif
