#version 460
#extension GL_GOOGLE_include_directive : require
// Rebuild 6g: write every particle's neighbours into its CSR segment of the new list, then order the segment
// by the partners' stable ids. The per-particle gathers sum a segment in its order, so this canonical order
// makes a step's floating-point sums independent of when the list was built, of the cell grid and of the
// particle order: any rebuild schedule that keeps the list complete gives bitwise the same run (a pair the
// list holds beyond its interaction range adds exact zeros). Resumes, split or gated rebuilds, another skin
// and ensembles stepped on a common schedule rely on it (ARCHITECTURE.md "Determinism").
// The neighbours come from 6e's scratch (its first pc.arg0 candidates, in search order) when they all fit
// there; otherwise (or with pc.arg0 = 0, after an overflow regrowth reallocated the scratch) the 27 cells
// are searched again, in the same order.
#include "neighbours.glsl"
layout(local_size_x = 256) in;
void main() {
  uint i = gl_GlobalInvocationID.x;
  Params P = PRM();
  if (i >= P.num_particles || halted()) return;
  uint s = 1u - parity();
  uint off = Uints(T().cnt_scan).v[i];
  Uints(paddr(s, PF_NOFFSET)).v[i] = off;
  Uints nbr = Uints(eaddr(s, EF_NBR)), self = Uints(eaddr(s, EF_SELF));
  uint K = pc.arg0;
  uint c = Uints(paddr(s, PF_NCOUNT)).v[i];
  uint e = off;
  if (c <= K) {
    Uints keep = Uints(T().pair_f);
    for (uint q = 0u; q < c; ++q) {
      nbr.v[e] = keep.v[i * K + q];
      self.v[e] = i;
      e++;
    }
  } else {
    FOR_EACH_NEIGHBOUR(i, s, P, nbr.v[e] = j; self.v[e] = i; e++)
  }
  // Insertion sort by stable id (pos.w; unique): segments hold ~5-30 entries, once per rebuild.
  IVec4s pos = IVec4s(paddr(s, PF_POS));
  for (uint a = off + 1u; a < e; ++a) {
    uint x = nbr.v[a];
    int kx = pos.v[x].w;
    uint b = a;
    while (b > off && pos.v[nbr.v[b - 1u]].w > kx) {
      nbr.v[b] = nbr.v[b - 1u];
      --b;
    }
    nbr.v[b] = x;
  }
}
