#include "gpu/scan.h"

#include <fmt/core.h>

#include <stdexcept>

namespace wetdem::gpu {

namespace {
uint32_t blocks(uint32_t n) {
  return (n + Scan::kBlock - 1) / Scan::kBlock;
}

// Push constants, laid out as the shaders' std430 push blocks.
struct ReducePush {
  uint64_t data, sums;
  uint32_t n;
};
struct BlockPush {
  uint64_t data, offsets, total;
  uint32_t n;
};
}  // namespace

Scan::Scan(vk::Context& ctx, uint32_t max_n)
    : max_n_(max_n), reduce_(ctx, "scan_reduce"), block_(ctx, "scan_block") {
  if (max_n > kMaxN) throw std::invalid_argument(fmt::format("Scan: max_n {} exceeds {}", max_n, kMaxN));
  // One block-sum buffer per level that has more than one block.
  for (uint32_t m = max_n; m > kBlock; m = blocks(m)) sums_.emplace_back(ctx, uint64_t(blocks(m)) * 4);
}

void Scan::record(VkCommandBuffer cb, Dispatcher& disp, uint64_t data_addr, uint32_t n, uint64_t total_addr) {
  if (n > max_n_) throw std::invalid_argument(fmt::format("Scan: n {} exceeds max_n {}", n, max_n_));
  if (n == 0 && total_addr == 0) return;
  record_level(cb, disp, 0, data_addr, n, total_addr);
}

// Reduce-then-scan: block sums -> scan them (recursively, in place) -> scan each block from its offset.
// The top level is a single block (possibly empty), which also writes the total.
void Scan::record_level(VkCommandBuffer cb, Dispatcher& disp, size_t level, uint64_t data_addr, uint32_t n,
                        uint64_t total_addr) {
  if (n <= kBlock) {
    BlockPush p{data_addr, 0, total_addr, n};
    disp.dispatch(cb, block_, 1, &p, sizeof(p));
    vk::barrier(cb);
    return;
  }
  const uint64_t sums = sums_.at(level).address();
  ReducePush r{data_addr, sums, n};
  disp.dispatch(cb, reduce_, blocks(n), &r, sizeof(r));
  vk::barrier(cb);
  record_level(cb, disp, level + 1, sums, blocks(n), total_addr);
  BlockPush p{data_addr, sums, 0, n};
  disp.dispatch(cb, block_, blocks(n), &p, sizeof(p));
  vk::barrier(cb);
}

}  // namespace wetdem::gpu
