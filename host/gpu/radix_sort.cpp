#include "gpu/radix_sort.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace wetdem::gpu {

namespace {
constexpr uint32_t kDigits = 1u << RadixSort::kDigitBits;
uint32_t tiles(uint32_t n) {
  return (n + RadixSort::kTile - 1) / RadixSort::kTile;
}

// Push constants, laid out as the shaders' std430 push blocks.
struct CountPush {
  uint64_t keys, hist;
  uint32_t n, shift, mask, num_tiles;
};
struct ScatterPush {
  uint64_t src_keys, src_vals, dst_keys, dst_vals, offsets;
  uint32_t n, shift, mask, num_tiles;
};
struct CopyPush {
  uint64_t src_keys, src_vals, dst_keys, dst_vals;
  uint32_t n;
};
struct TilePush {
  uint64_t keys, vals;
  uint32_t n, key_bits;
};
}  // namespace

RadixSort::RadixSort(vk::Context& ctx, uint32_t max_n)
    : max_n_(max_n),
      count_(ctx, "radix_count"),
      scatter_(ctx, "radix_scatter"),
      copy_(ctx, "radix_copy"),
      tile_(ctx, "radix_sort_tile"),
      tmp_keys_(ctx, uint64_t(max_n) * 4),
      tmp_vals_(ctx, uint64_t(max_n) * 4),
      hist_(ctx, uint64_t(tiles(max_n)) * kDigits * 4),
      scan_(ctx, tiles(max_n) * kDigits) {
  if (max_n > kMaxN) throw std::invalid_argument(fmt::format("RadixSort: max_n {} exceeds {}", max_n, kMaxN));
}

void RadixSort::record(VkCommandBuffer cb, Dispatcher& disp, uint64_t keys_addr, uint64_t vals_addr,
                       uint32_t n, uint32_t key_bits) {
  if (n > max_n_) throw std::invalid_argument(fmt::format("RadixSort: n {} exceeds max_n {}", n, max_n_));
  if (key_bits > 32) throw std::invalid_argument(fmt::format("RadixSort: key_bits {} > 32", key_bits));
  if (n == 0 || key_bits == 0) return;  // nothing to reorder
  const uint32_t nt = tiles(n);
  if (nt == 1 && one_tile_) {
    TilePush t{keys_addr, vals_addr, n, key_bits};
    disp.dispatch(cb, tile_, 1, &t, sizeof(t));
    vk::barrier(cb);
    return;
  }
  const uint32_t passes = (key_bits + kDigitBits - 1) / kDigitBits;
  uint64_t src_k = keys_addr, src_v = vals_addr, dst_k = tmp_keys_.address(), dst_v = tmp_vals_.address();
  for (uint32_t p = 0; p < passes; ++p) {
    const uint32_t shift = p * kDigitBits;
    // The last digit may be narrower: bits at and above key_bits must not take part in the order.
    const uint32_t mask = (1u << std::min(kDigitBits, key_bits - shift)) - 1u;
    CountPush c{src_k, hist_.address(), n, shift, mask, nt};
    disp.dispatch(cb, count_, nt, &c, sizeof(c));
    vk::barrier(cb);
    scan_.record(cb, disp, hist_.address(), nt * kDigits, 0);  // ends with a barrier
    ScatterPush s{src_k, src_v, dst_k, dst_v, hist_.address(), n, shift, mask, nt};
    disp.dispatch(cb, scatter_, nt, &s, sizeof(s));
    vk::barrier(cb);
    std::swap(src_k, dst_k);
    std::swap(src_v, dst_v);
  }
  if (passes % 2 == 1) {  // the result is in the scratch buffers
    CopyPush c{src_k, src_v, keys_addr, vals_addr, n};
    disp.dispatch(cb, copy_, nt, &c, sizeof(c));
    vk::barrier(cb);
  }
}

SortBenchResult bench_radix_sort(vk::Context& ctx, uint32_t n, uint32_t key_bits, int reps) {
  SortBenchResult res;
  res.n = n;
  res.key_bits = key_bits;
  res.reps = reps;
  if (n == 0 || reps <= 0) return res;
  std::mt19937 rng(12345);
  const uint32_t key_mask = key_bits >= 32 ? 0xffffffffu : (1u << key_bits) - 1u;
  std::vector<uint32_t> keys(n), vals(n);
  for (uint32_t i = 0; i < n; ++i) {
    keys[i] = rng() & key_mask;
    vals[i] = i;
  }
  vk::Buffer in_k(ctx, uint64_t(n) * 4), in_v(ctx, uint64_t(n) * 4), k(ctx, uint64_t(n) * 4),
      v(ctx, uint64_t(n) * 4);
  in_k.upload(keys);
  in_v.upload(vals);
  RadixSort sort(ctx, n);
  vk::Kernel copy(ctx, "radix_copy");
  DirectDispatcher disp;

  res.gpu_timestamps = ctx.info().timestamps;
  VkQueryPool pool = VK_NULL_HANDLE;
  if (res.gpu_timestamps) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = uint32_t(2 * reps);
    WETDEM_VK(vkCreateQueryPool(ctx.device(), &qi, nullptr, &pool));
  }
  // Warm-up sort (pipeline first use), not timed.
  auto restore = [&](VkCommandBuffer cb) {
    CopyPush c{in_k.address(), in_v.address(), k.address(), v.address(), n};
    copy.dispatch(cb, tiles(n), &c, sizeof(c));
    vk::barrier(cb);
  };
  ctx.submit_now([&](VkCommandBuffer cb) {
    restore(cb);
    sort.record(cb, disp, k.address(), v.address(), n, key_bits);
  });
  auto t0 = std::chrono::steady_clock::now();
  ctx.submit_now([&](VkCommandBuffer cb) {
    if (pool) vkCmdResetQueryPool(cb, pool, 0, uint32_t(2 * reps));
    for (int r = 0; r < reps; ++r) {
      restore(cb);
      if (pool) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool, uint32_t(2 * r));
      sort.record(cb, disp, k.address(), v.address(), n, key_bits);
      if (pool) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool, uint32_t(2 * r + 1));
    }
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double total = wall;
  if (pool) {
    std::vector<uint64_t> ts(size_t(2 * reps));
    WETDEM_VK(vkGetQueryPoolResults(ctx.device(), pool, 0, uint32_t(2 * reps), ts.size() * 8, ts.data(), 8,
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    vkDestroyQueryPool(ctx.device(), pool, nullptr);
    total = 0;
    for (int r = 0; r < reps; ++r)
      total += double(ts[2 * r + 1] - ts[2 * r]) * ctx.info().timestamp_period_ns * 1e-9;
  }
  res.seconds_per_sort = total / reps;
  res.elements_per_second = res.seconds_per_sort > 0 ? n / res.seconds_per_sort : 0;
  return res;
}

}  // namespace wetdem::gpu
