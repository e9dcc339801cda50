// The GPU system: particle and contact state in Vulkan buffers, every pass of a step a compute shader.
// See ARCHITECTURE.md for the passes and buffer ownership.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "wetdem/observables.h"
#include "wetdem/params.h"
#include "wetdem/state.h"

namespace wetdem {

namespace vk {
class Context;
}

struct SystemOptions {
  uint32_t steps_per_submit = 200;             // steps recorded into one command buffer
  uint32_t initial_entries_per_particle = 16;  // neighbour-list capacity hint; grows on overflow
  bool profile_passes = false;                 // timestamp every pass (benchmarks)
  // Record steps without the rebuild chain and submit the chain on its own when a step asks for it (the
  // step halts there), instead of recording the gated chain, ~25 empty dispatches, into every step.
  // Bitwise the same result either way; see ARCHITECTURE.md "Split rebuilds".
  bool split_rebuilds = true;
  double split_min_interval = 8.0;  // ... while rebuilds are at least this many steps apart (estimated)
  // The fused step (ARCHITECTURE.md "Passes of a step"): the kick-drift of the next step and liquid pass 4a
  // run inside the gather, the films take 4b's overflow and 4d's bridges with integer atomics (no 4e), and
  // the rebuild decision is taken by the last workgroup of the step's last pass: pair_force, gather_kick and
  // 4b-4d per step instead of 9 passes. Off: every pass on its own (bitwise the same result; benchmarks).
  // Needs 64-bit buffer atomics (else off).
  bool fused_step = true;
  // ... and 4b-4d closed (zero-sized dispatches) on steps where no contact is flagged for a liquid event and
  // no sink is on: they would change nothing.
  bool liquid_gate = true;
  // The neighbour sort of up to 2,048 particles in one dispatch (radix_sort_tile.comp) instead of ~3 per
  // 4-bit pass: a small bed rebuilds every few steps. Bitwise the same order (benchmarks turn it off).
  bool one_tile_sort = true;
  // The skin test (ARCHITECTURE.md "The skin test"): each particle's displacement since the list was built is
  // measured from its reference position turned with the drum (rotation about the axis keeps every pair
  // distance, so a bed that turns with the drum has not moved), and the list is rebuilt when the two largest
  // displacements add up to the skin, not when the largest reaches half of it. Both bound every pair's
  // approach exactly; off, the classic rule (max displacement > skin/2). Results are bitwise the same
  // either way (the rebuild schedule changes no run); only the number of rebuilds changes.
  bool skin_drum_frame = true;
  bool skin_top_two = true;
};

struct PassTiming {
  std::string name;
  double seconds = 0.0;  // summed over the profiled steps
  uint64_t dispatches = 0;
};

struct SystemCounters {
  uint64_t rebuilds = 0;        // neighbour-list rebuilds so far
  uint64_t regrows = 0;         // contact-buffer regrowths (overflow, step redone)
  uint64_t split_rebuilds = 0;  // rebuilds submitted on their own (SystemOptions::split_rebuilds)
  uint64_t entry_capacity = 0;  // current neighbour-entry capacity
  uint64_t entries = 0;         // neighbour entries in the current list (both directions)
  uint64_t lost_bridges = 0;    // bridges dropped with a pair leaving the list: must stay 0
  uint64_t escaped = 0;         // particles found outside the cell grid at the last rebuild
  uint64_t steps = 0;           // steps done by this System
  uint64_t liquid_steps = 0;    // fused step: steps whose liquid passes 4b-4d ran (the gate was open)
  // Dispatches recorded per step in the last batch (zero-sized gated ones included; a submit's first
  // kick-drift shared by its steps).
  double dispatches_per_step = 0.0;
};

// ---- device memory of a System (benchmarks, resource estimates; host/gpu/system_memory.cpp) ----
// Bytes of the buffers a System owns directly, by role, from their real sizes. Sorting and scan scratch are
// not listed (vk::Context::device_bytes() counts every live buffer of a context).
struct DeviceMemory {
  uint64_t particle_sets = 0;     // both particle sets (current / being built)
  uint64_t particle_scratch = 0;  // per-particle scratch: rebuild keys, reference positions, liquid scratch
  uint64_t entry_sets = 0;        // both neighbour-entry sets, at their capacities
  uint64_t entry_scratch = 0;     // per-entry scratch: pair forces and torques, event slots
  uint64_t entry_capacity = 0;    // entries the two sets hold together
  uint64_t grid = 0;              // cell ranges
  uint64_t control = 0;           // control words, parameters, address table
  uint64_t total() const {
    return particle_sets + particle_scratch + entry_sets + entry_scratch + grid + control;
  }
};

// What a drum sample needs, computed on the device and brought back in one transfer (System::sample_runs).
struct RunSample {
  // The reductions of compute_observables (its CPU reference): touching, bridged and wall pairs, f_wet, the
  // largest overlap, liquid in films, bridges, pores and evaporated (exact integers), the centre of mass and
  // the kinetic energy (fixed-point sums on the run's own scales: ~1e-10 relative; NaN energy when a
  // particle's energy or position is not finite).
  Observables obs;
  // A slim state in the run's stable ids: p.x, p.v, p.radius and p.mass, and in `pairs` the bridged pairs
  // (ids and volume; springs and flags not read). Every other particle array is empty. Time and step set.
  SystemState bed;
};

class System {
 public:
  System(vk::Context& ctx, const SimParams& prm, size_t num_particles, SystemOptions opt = {});
  // An ensemble (docs/ensembles.md): independent runs stepped together in the same dispatches, run r with
  // sizes[r] particles and its own parameters (contact, liquid, effects, drum speed, sinks). They share the
  // clock (dt), the drum's size, periodicity and plates (the position ticks and the cell grid), and one
  // rebuild schedule; each run's cells are its own, so runs never touch, and each run is bitwise the same
  // run done alone (segment order, nbr_fill.comp). Throws std::invalid_argument naming what differs.
  System(vk::Context& ctx, const std::vector<SimParams>& runs, const std::vector<size_t>& sizes,
         SystemOptions opt = {});
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // Replaces the whole state (particles, pair and wall records, time) and rebuilds the neighbour list.
  void upload(const SystemState& s);
  // Reads the whole state back in stable-id order, canonical pair records.
  SystemState download();
  // Raw image of every GPU buffer that carries state across steps, in the device's own particle order, for
  // checkpoints: restore(snapshot()) on the same device continues bitwise as if never interrupted.
  std::vector<uint8_t> snapshot();
  void restore(const std::vector<uint8_t>& blob);

  // Ensembles: one state per run in, one per run out (each in its own stable ids from 0).
  void upload_runs(const std::vector<SystemState>& states);
  std::vector<SystemState> download_runs();
  size_t runs() const;
  const SimParams& run_params(size_t r) const;
  // Replaces run r's physics between steps (e.g. the drum starts turning): everything the runs share (dt,
  // drum size, plates, the grid) must stay, else std::invalid_argument. With one run, r = 0.
  void set_run_params(size_t r, const SimParams& prm);

  // Advances n steps; records them in as few submits as steps_per_submit allows. Grows buffers on overflow
  // and redoes the affected steps, so nothing is dropped.
  void step(uint64_t n);

  // Rebuilds the neighbour list at the end of the next step whatever the displacements (tests, restarts).
  void force_rebuild();
  // Tests: fills every buffer that is not in snapshot() (the set being built, pair results, liquid and
  // rebuild scratch) with `word`. A step must write such a buffer before it reads it, so this may not change
  // a result: a restored System starts with them zeroed, a running one holds the last step's values.
  void fill_scratch(uint32_t word);
  // The current neighbour list as (lower id, higher id) pairs, sorted: for tests against brute force.
  std::vector<std::pair<uint32_t, uint32_t>> neighbour_pairs();

  Observables observables();
  // One per run, for drum samples: the device's reductions and the slim state a camera needs (RunSample).
  // Deterministic; each run of an ensemble gets bitwise what it gets alone.
  std::vector<RunSample> sample_runs();
  EventCounts read_events();  // formations/ruptures since the last call
  SystemCounters counters() const;
  std::vector<PassTiming> pass_timings() const;
  DeviceMemory device_memory() const;  // host/gpu/system_memory.cpp
  void reset_pass_timings();

  const SimParams& params() const;
  std::string device_name() const;
  // Position quantum (m) of the fixed-point positions, valid after upload (ARCHITECTURE.md). Positions and
  // radii that are whole multiples of it are represented exactly on the device.
  double tick_size() const;
  size_t size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wetdem
