// Every device buffer of a GPU system and the address table the shaders read (shaders/common/access.glsl).
// Particle and pair buffers come in two sets (current / being built); ctl[kParity] says which is current.
#pragma once

#include <array>
#include <cstdint>

#include "vk/buffer.h"
#include "vk/context.h"

namespace wetdem::gpu {

// Particle fields of one set (order = PF_* in access.glsl).
enum ParticleField : uint32_t {
  kPos,
  kVel,
  kOmg,
  kProps,
  kForce,
  kTorque,
  kFilm,
  kWallSt,
  kWallSr,
  kWallLiq,
  kWallFlags,
  kNbrCount,
  kNbrOffset,
  kFrac,
  kPore,     // int64: liquid in the pores (absorption)
  kEvap,     // int64: liquid evaporated from this particle's film and owned bridges
  kPoreCap,  // int64: pore capacity (liquid units), set at upload
  kNumParticleFields
};
// Entry (neighbour-list) fields of one set (order = EF_* in access.glsl).
enum EntryField : uint32_t { kNbr, kSelf, kMirror, kSt, kSr, kLiq, kFlags, kNumEntryFields };

// Bytes per element of each field.
inline constexpr std::array<uint32_t, kNumParticleFields> kParticleFieldBytes = {
    16, 16, 16, 16, 16, 16, 8, 48, 48, 24, 12, 4, 4, 16, 8, 8, 8};
inline constexpr std::array<uint32_t, kNumEntryFields> kEntryFieldBytes = {4, 4, 4, 16, 16, 8, 4};

// Address table, std430 (all uint64), mirror of `Table` in access.glsl.
struct GpuTable {
  uint64_t ctl, params;
  uint64_t pset[2][kNumParticleFields];
  uint64_t eset[2][kNumEntryFields];
  uint64_t ref_pos, cell_key, sort_val, cell_start, cell_end, cnt_scan;
  uint64_t pair_f, pair_t, ev, partner;
  uint64_t p_share, p_gain, p_full, p_offer;
  uint64_t own_scan, owners;
  uint64_t run_of;
  uint64_t smp, smp_pairs;  // sampling (shaders/common/sample.glsl)
};

struct BufferSet {
  // `runs` parameter blocks (ensembles: one per run, docs/ensembles.md).
  BufferSet(vk::Context& ctx, uint32_t num_particles, uint32_t num_cells, uint32_t runs = 1);

  // Reallocates pair set `set` (contents lost) and the per-entry scratch for at least `entries` entries.
  void grow_entries(uint32_t set, uint32_t entries);
  uint32_t capacity(uint32_t set) const { return capacity_[set]; }
  GpuTable table() const;
  void upload_table();

  vk::Context& ctx;
  uint32_t n, cells;
  vk::Buffer ctl, params, table_buf;
  vk::Buffer pset[2][kNumParticleFields];
  vk::Buffer eset[2][kNumEntryFields];
  vk::Buffer ref_pos, cell_key, sort_val, cell_start, cell_end, cnt_scan;
  // Per-entry pair results, written by the owner at its entry and at its mirror's (partner), so that the
  // per-particle gathers read their own segment in order.
  vk::Buffer pair_f, pair_t, ev, partner;
  vk::Buffer p_share, p_gain, p_full, p_offer;
  // The owner list: the entries that evaluate their pair (mirror[e] == e), in list order, so that the passes
  // over pairs run one invocation per pair. One buffer: a rebuild writes it after the old list's last use.
  vk::Buffer own_scan, owners;
  vk::Buffer run_of;  // the run of each stable id (ensembles)
  // Sampling (System::sample_runs, shaders/common/sample.glsl): the reduction words (a head and one block per
  // run) and the compact list of bridged pairs, grown on demand.
  vk::Buffer smp, smp_pairs;
  uint32_t smp_pair_capacity() const { return smp_pair_capacity_; }
  void grow_sample_pairs(uint32_t pairs);  // reallocates (contents lost) and rewrites the table

 private:
  void grow_scratch(uint32_t entries);
  uint32_t capacity_[2] = {0, 0};
  uint32_t scratch_capacity_ = 0;
  uint32_t smp_pair_capacity_ = 0;
};

}  // namespace wetdem::gpu
