// The buffer table: device addresses of every buffer (mirror of GpuTable in host/gpu/buffer_set.h).
// Particle and pair buffers come in two sets; ctl[CTL_PARITY] says which set is current. A rebuild
// writes the reordered particles and the new list into the other set, then flips the parity.
#ifndef WETDEM_ACCESS_GLSL
#define WETDEM_ACCESS_GLSL
#include "ctl.glsl"
#include "params.glsl"

#define PF_POS 0
#define PF_VEL 1
#define PF_OMG 2
#define PF_PROPS 3
#define PF_FORCE 4   // vec4: force (xyz) and the torque's x (w)
#define PF_TORQUE 5  // vec2: the torque's y, z
#define PF_FILM 6
#define PF_WST 7
#define PF_WSR 8
#define PF_WLIQ 9
#define PF_WFLAGS 10
#define PF_NCOUNT 11
#define PF_NOFFSET 12
#define PF_FRAC 13  // vec4: sub-tick position fraction (xyz) and radius fraction (w), in ticks
#define PF_PORE 14     // int64: liquid in the pores (absorption)
#define PF_EVAP 15     // int64: liquid evaporated from this particle's film and owned bridges
#define PF_PORECAP 16  // int64: pore capacity (liquid units)
#define PF_COUNT 17

#define EF_NBR 0
#define EF_SELF 1
#define EF_MIRROR 2
#define EF_ST 3  // vec4: the tangential spring (xyz) and the rolling spring's x (w)
#define EF_SR 4  // vec2: the rolling spring's y, z
#define EF_LIQ 5
#define EF_FLAGS 6
#define EF_COUNT 7

// A uniform buffer (descriptor set 0, binding 0; vk::Context::pipeline_layout): every invocation reads the
// same addresses, one load each (lavapipe reads device addresses lane by lane, a uniform buffer at a uniform
// offset once).
layout(set = 0, binding = 0, scalar) uniform Table {
  uint64_t ctl;
  uint64_t params;
  uint64_t pset[2 * PF_COUNT];
  uint64_t eset[2 * EF_COUNT];
  uint64_t ref_pos, cell_key, sort_val, cell_start, cell_end, cnt_scan;
  // Per-entry results, written by the pair's owner at both of its entries (the mirror's at partner[e]), so
  // that the per-particle gathers read their own segment in order: force and torque on the segment's particle,
  // liquid moved to or from it.
  uint64_t pair_f, pair_t, ev, partner;
  uint64_t p_share, p_gain, p_full, p_offer;
  uint64_t own_scan, owners;  // owner entries per particle (scanned) and the owner list of the current set
  uint64_t run_of;            // ensembles: the run of each stable id (uint); unused with one run
  uint64_t smp, smp_pairs;    // sampling: reductions per run and the compact list of bridged pairs (sample.glsl)
} TBL;

layout(push_constant) uniform Push {
  uint64_t table;
  uint arg0;
  uint arg1;
} pc;

// Pair and wall flag bits (ContactFlags in include/wetdem/state.h for bit 0).
#define FLAG_WIC 1u      // was_in_contact, §5
#define FLAG_RUPT 2u     // bridge ruptures at the end of this step
#define FLAG_FORM 4u     // first touch this step: formation attempt
#define FLAG_MAPPED 8u   // old-list entry carried into the new list (rebuild only)

#define T() TBL
Uints CTL() { return Uints(T().ctl); }
// The address of a field of particle (entry) set `set`: both candidates are read at fixed offsets (one load
// each), then selected; the set index comes from the control block.
uint64_t paddr(uint set, uint field) { return set == 0u ? T().pset[field] : T().pset[PF_COUNT + field]; }
uint64_t eaddr(uint set, uint field) { return set == 0u ? T().eset[field] : T().eset[EF_COUNT + field]; }
// Run 0's parameters: the fields every run shares (counts, grid, ticks, dt, skin) are the same in each copy.
Params PRM() { return PRM0.d; }
// Specialization constant 0 (host/gpu/system.cpp): the number of runs; 0 = not given (read from PRM().runs).
layout(constant_id = 0) const uint kRuns = 0u;
// Ensembles (several independent runs in one system, docs/ensembles.md): the parameters of run r, and the
// run of a particle from its stable id. Physics reads them; with one run both are run 0's, with no load.
Params PRMR(uint r) { return ParamsRef(T().params + uint64_t(r) * uint64_t(PRM().run_stride)).d; }
uint run_of_id(int id) { return kRuns != 1u && PRM().runs > 1u ? Uints(T().run_of).v[id] : 0u; }
// The parameters of sorted particle i of set s.
Params PRM_OF(uint i, uint s) {
  if (kRuns == 1u) return PRM();
  return PRMR(run_of_id(IVec4s(paddr(s, PF_POS)).v[i].w));
}
// Per-particle wall records exist for the walls the drum has: the cylinder, and the end plates unless the
// drum is a periodic slice. Wall w of particle i is record i * wall_slots + (its rank among those walls).
uint walls_present(Params P) {
  uint m = 1u;
  if (P.period_ticks == 0) m |= (P.plate_present[0] != 0u ? 2u : 0u) | (P.plate_present[1] != 0u ? 4u : 0u);
  return m;
}
bool wall_present(uint w, Params P) { return (walls_present(P) & (1u << w)) != 0u; }
uint wall_slot(uint i, uint w, Params P) {
  return i * P.wall_slots + uint(bitCount(walls_present(P) & ((1u << w) - 1u)));
}
bool halted() { return CTL().v[CTL_HALT] != 0u; }
uint parity() { return CTL().v[CTL_PARITY]; }
#endif
