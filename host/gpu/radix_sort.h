// Stable, deterministic LSD radix sort of (uint32 key, uint32 value) pairs at device addresses.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>

#include "gpu/dispatcher.h"
#include "gpu/scan.h"
#include "vk/buffer.h"
#include "vk/context.h"
#include "vk/kernel.h"

namespace wetdem::gpu {

class RadixSort {
 public:
  static constexpr uint32_t kDigitBits = 4;
  static constexpr uint32_t kTile = 2048;  // pairs per workgroup (256 invocations x 8)
  // The tile count must stay within the 65535 workgroups every Vulkan device allows.
  static constexpr uint32_t kMaxN = 65535u * kTile;

  // Owns ping-pong key/value buffers, the per-tile histograms and their Scan, for up to max_n pairs.
  RadixSort(vk::Context& ctx, uint32_t max_n);

  // Records a stable sort of the n pairs (keys[i], vals[i]) by the low key_bits bits of the key
  // (0..32; higher key bits are ignored and carried along). The result is back in keys/vals. Passes =
  // ceil(key_bits / 4), each: count (per-tile digit histograms), scan, scatter; one copy pass when the
  // pass count is odd. Up to one tile (n <= kTile) and with one_tile() on, every pass runs in one
  // workgroup and one dispatch instead (radix_sort_tile.comp), with the same result bit for bit. Every
  // dispatch goes through `disp` and its size depends only on n; barriers are inserted between passes and
  // after the last one. Throws if n > max_n or key_bits > 32.
  void record(VkCommandBuffer cb, Dispatcher& disp, uint64_t keys_addr, uint64_t vals_addr, uint32_t n,
              uint32_t key_bits);

  uint32_t max_n() const { return max_n_; }
  // The one-dispatch sort of a single tile (on by default; off: the multi-pass sort at any n, for the
  // benchmark's lever and the test that holds the two together).
  bool one_tile() const { return one_tile_; }
  void set_one_tile(bool on) { one_tile_ = on; }

 private:
  uint32_t max_n_;
  bool one_tile_ = true;
  vk::Kernel count_, scatter_, copy_, tile_;
  vk::Buffer tmp_keys_, tmp_vals_, hist_;
  Scan scan_;
};

// Benchmark helper: sorts `n` uniformly random keys (fixed seed) of key_bits bits `reps` times, each
// time from the same unsorted input, and reports the mean time of one record()ed sort. Timed with GPU
// timestamps around each sort when the queue supports them, else by wall clock around the submit (which
// then includes the restore copies and the submission overhead).
struct SortBenchResult {
  uint32_t n = 0, key_bits = 0;
  int reps = 0;
  double seconds_per_sort = 0;
  double elements_per_second = 0;
  bool gpu_timestamps = false;
};
SortBenchResult bench_radix_sort(vk::Context& ctx, uint32_t n, uint32_t key_bits, int reps = 10);

}  // namespace wetdem::gpu
