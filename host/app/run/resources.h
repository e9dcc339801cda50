// Resource check before any work (issue 12 point 1): from the case alone (no fill), the expected particle
// count, host and device memory and particle-steps; compared with the device's heap and the host's free
// memory, a case that cannot fit is refused with an error naming the key that drives it.
//
// Particles: n = fill × π D²/4 × L_sim × bed_solid_fraction / V̄_S (the PSD model's mean volume), the same
// estimate `wetdem check` prints; the fill then draws about that many.
// Device bytes: per particle, the two particle sets of host/gpu/buffer_set.h (particle_set_bytes: 188 B each
// in a periodic slice, one wall record of 44 B; 276 B in a closed drum, three), the per-particle scratch
// (ref_pos 16, cell_key/sort_val/cnt_scan/own_scan 16, liquid scratch 32: 64 B), the radix sort's ping-pong
// keys and values (8 B) and up to 8 cell-range entries of 8 B (the grid is hashed beyond 8 cells per
// particle: 64 B): 512 B in a slice, 688 B closed; per neighbour-list entry, the two entry sets
// (kEntryFieldBytes, 48 B each) and the per-entry scratch (pair_f/pair_t 24, partner 4, owners 4): 128 B. The
// byte counts follow the layout constants; tests/test_bench_traffic.cpp checks them against the buffers a
// System really allocates. Entries per particle: two-sided neighbours with centres within 2 r̄ + S_c,max +
// skin in a bed of solid fraction φ, ≈ φ (d/r̄)³ in the list; allocated: the initial capacity of 16 per
// particle, or 1.5 × the list once a rebuild overflows it (system.cpp grows a set to 1.5 × the need).
// wetdem_bench measures the list length of real beds in rotation (docs/benchmark.md "Memory"). Host bytes:
// measured, the slope of the peak resident memory of `wetdem run` on lavapipe between the demo slice (1,834
// particles, 113 MB) and a 5x longer one (9,091 particles, 141 MB): 4.0 kB per particle. On lavapipe that
// includes the device buffers (device memory is host memory there), so it errs high on a GPU.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "app/case/case.h"
#include "gpu/buffer_set.h"

namespace wetdem::vk {
class Context;
}

namespace wetdem::app {

struct ResourceEstimate {
  double particles = 0;             // expected n
  double entries_in_list = 0;       // neighbour-list entries per particle expected in a settled bed
  double entries_per_particle = 0;  // neighbour-list entries allocated per particle (with regrow headroom)
  double device_bytes = 0;
  double host_bytes = 0;
  double r_min = 0;       // smallest radius of the PSD model (m)
  double t_rayleigh = 0;  // Rayleigh time of r_min (s)
  double dt = 0;          // the time step a run will take (s), and what sets it
  std::string dt_reason;
  double steps = 0;           // settle + duration over dt
  double particle_steps = 0;  // particles × steps
  std::string driver_key;     // the key the message names: what makes n large
};

struct Available {
  std::optional<double> device_bytes;  // largest device-local heap; unknown without a device
  std::string device;
  std::optional<double> host_bytes;  // /proc/meminfo MemAvailable; unknown where absent
};

// From the buffer layout (host/gpu/buffer_set.h): two particle sets, the per-particle scratch, the cell
// ranges; two entry sets and the per-entry scratch. tests/test_bench_traffic.cpp checks them against a
// System's buffers.
// One particle set, with the wall records of a periodic slice (the cylinder) or of a closed drum (three
// walls).
constexpr double particle_set_bytes(bool periodic_slice) {
  return double(gpu::particle_set_bytes(periodic_slice ? 1u : 3u));
}
inline constexpr double kEntrySetBytes = gpu::entry_set_bytes();
// ref_pos; cell_key, sort_val, cnt_scan, own_scan; p_share, p_gain, p_full, p_offer
inline constexpr double kParticleScratchBytes = 16 + 4 * 4 + 4 * 8;
// pair_f, pair_t ((F, T.x) and (T.y, T.z)); partner, owners (the fused step needs no event slots)
inline constexpr double kEntryScratchBytes = gpu::kEntryScratchBytes;
inline constexpr double kSortScratchBytes = 2 * 4;           // radix sort ping-pong keys, values
inline constexpr double kDeviceCellBytesPerParticle = 64.0;  // <= 8 cells x (start, end) per particle
constexpr double device_bytes_per_particle(bool periodic_slice) {
  return 2.0 * particle_set_bytes(periodic_slice) + kParticleScratchBytes + kSortScratchBytes +
         kDeviceCellBytesPerParticle;
}
inline constexpr double kDeviceBytesPerEntry = 2.0 * kEntrySetBytes + kEntryScratchBytes;
inline constexpr double kInitialEntriesPerParticle = 16.0;  // SystemOptions::initial_entries_per_particle
inline constexpr double kHostBytesPerParticle = 4000.0;
// Throughput `wetdem check` quotes: lavapipe on 2 idle cores, the fused step (docs/benchmark.md, 24 Nov
// 2026): the 410-particle flowing drum at ~2.1e5 particle-steps/s and the 1,834-particle demo slice at
// ~6.3e5. Per particle a small drum costs more (fixed work per dispatch, rebuilds every few steps of a fast
// bed), so the rate is interpolated in log(particles) between the two and held at the end values outside
// them.
double lavapipe_throughput(double particles);
inline constexpr const char* kLavapipeThroughputSource =
    "lavapipe on 2 idle CPU cores, from drums of 410 and 1,834 particles (docs/benchmark.md); a GPU is "
    "faster";

ResourceEstimate estimate_resources(const Case& c);

// A periodic slice needs every interaction range below half its period (minimum image): the check the run
// makes after the fill (prepare.cpp), made here from the case alone (the PSD model's largest diameter and
// mean volume) so that a study, twin or diagnosis refuses such a case before any run. Throws
// CaseError("drum.slice_thickness", ...).
void check_reach(const Case& c);

// A size in bytes for people: three significant digits and a decimal unit (1.23 MB, 24.7 GB).
std::string bytes_text(double b);

// MemAvailable of /proc/meminfo in bytes, empty where the file or line is missing.
std::optional<double> host_available_bytes();
// Size of the largest DEVICE_LOCAL memory heap of the context's device.
double device_heap_bytes(const vk::Context& ctx);

// Throws CaseError(e.driver_key, ...) naming the need and what is available when the estimate exceeds 90 %
// of the device heap or of the host's available memory.
void check_resources(const ResourceEstimate& e, const Available& a);

// Lines for `wetdem check`: particles, memory, particle-steps, and the time at `throughput` particle-steps/s.
std::string describe_resources(const ResourceEstimate& e, double throughput,
                               const std::string& throughput_source);

}  // namespace wetdem::app
