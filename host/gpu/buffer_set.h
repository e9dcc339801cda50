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

// Bytes per element of each field: per particle, or per wall slot of a particle (the wall fields: a particle
// keeps one record per wall the system has, wall_slots() of them: the cylinder, and the plates of a closed
// drum). Force and torque are stored as (F, T.x) in kForce and (T.y, T.z) in kTorque, an entry's springs as
// (t, r.x) in kSt and (r.y, r.z) in kSr: whole 16- and 8-byte words, which lavapipe moves in fewer loops than
// packed vec3 (table.glsl). The bytes are those of two packed vec3.
inline constexpr std::array<uint32_t, kNumParticleFields> kParticleFieldBytes = {
    16, 16, 16, 16, 16, 8, 8, 16, 16, 8, 4, 4, 4, 16, 8, 8, 8};
inline constexpr std::array<bool, kNumParticleFields> kPerWallSlot = {
    false, false, false, false, false, false, false, true, true,
    true,  true,  false, false, false, false, false, false};
inline constexpr std::array<uint32_t, kNumEntryFields> kEntryFieldBytes = {4, 4, 4, 16, 8, 8, 4};
// Bytes of particle field f per particle, and of one particle set, with `wall_slots` wall records each.
constexpr uint32_t particle_field_bytes(uint32_t f, uint32_t wall_slots) {
  return kParticleFieldBytes[f] * (kPerWallSlot[f] ? wall_slots : 1u);
}
constexpr uint32_t particle_set_bytes(uint32_t wall_slots) {
  uint32_t b = 0;
  for (uint32_t f = 0; f < kNumParticleFields; ++f) b += particle_field_bytes(f, wall_slots);
  return b;
}
constexpr uint32_t entry_set_bytes() {
  uint32_t b = 0;
  for (uint32_t f : kEntryFieldBytes) b += f;
  return b;
}
// Per-entry scratch: pair force and torque as (F, T.x) and (T.y, T.z), whole 16- and 8-byte words that
// lavapipe moves in fewer loops than packed vec3 (table.glsl), partner, owner list; the event slots (8 B)
// only when the step is recorded pass by pass (SystemOptions::fused_step off, or no 64-bit atomics).
inline constexpr uint32_t kEntryScratchBytes = 16 + 8 + 4 + 4;
inline constexpr uint32_t kEventSlotBytes = 8;

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
  // `wall_slots` wall records per particle; event_slots: allocate the per-entry event slots (the step
  // recorded pass by pass).
  BufferSet(vk::Context& ctx, uint32_t num_particles, uint32_t num_cells, uint32_t runs = 1,
            uint32_t wall_slots = 3, bool event_slots = true);
  ~BufferSet();
  BufferSet(const BufferSet&) = delete;
  BufferSet& operator=(const BufferSet&) = delete;

  // Reallocates pair set `set` (contents lost) and the per-entry scratch for at least `entries` entries.
  void grow_entries(uint32_t set, uint32_t entries);
  uint32_t capacity(uint32_t set) const { return capacity_[set]; }
  uint32_t scratch_capacity() const { return scratch_capacity_; }  // entries of the per-entry scratch
  GpuTable table() const;
  void upload_table();

  vk::Context& ctx;
  uint32_t n, cells;
  uint32_t wall_slots;
  bool event_slots;
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
  // Descriptor set 0 of the kernels (vk::Context::pipeline_layout): the table and run 0's parameter block as
  // uniform buffers. Bound once per command buffer; the table's contents change (regrowth), never its buffer.
  VkDescriptorSet descriptors = VK_NULL_HANDLE;
  // Sampling (System::sample_runs, shaders/common/sample.glsl): the reduction words (a head and one block per
  // run) and the compact list of bridged pairs, grown on demand.
  vk::Buffer smp, smp_pairs;
  uint32_t smp_pair_capacity() const { return smp_pair_capacity_; }
  void grow_sample_pairs(uint32_t pairs);  // reallocates (contents lost) and rewrites the table

 private:
  void grow_scratch(uint32_t entries);
  uint32_t capacity_[2] = {0, 0};
  uint32_t scratch_capacity_ = 0;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  uint32_t smp_pair_capacity_ = 0;
};

}  // namespace wetdem::gpu
