#include "gpu/profiler.h"

namespace wetdem::gpu {

namespace {
constexpr uint32_t kMaxMarks = 1u << 16;
}

Profiler::~Profiler() {
  for (auto& [cb, r] : rec_)
    if (r.pool) vkDestroyQueryPool(ctx_.device(), r.pool, nullptr);
}

void Profiler::ensure_pool(Recording& r, uint32_t count) {
  if (r.pool) return;
  VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qi.queryCount = count;
  WETDEM_VK(vkCreateQueryPool(ctx_.device(), &qi, nullptr, &r.pool));
}

void Profiler::begin(VkCommandBuffer cb) {
  if (!ctx_.info().timestamps) return;
  Recording& r = rec_[cb];
  ensure_pool(r, kMaxMarks);
  r.names.clear();
  vkCmdResetQueryPool(cb, r.pool, 0, kMaxMarks);
}

void Profiler::mark(VkCommandBuffer cb, const std::string& pass) {
  if (!ctx_.info().timestamps) return;
  Recording& r = rec_[cb];
  if (r.names.size() + 1 >= kMaxMarks) return;  // very long recordings: later passes go unprofiled
  vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, r.pool, uint32_t(r.names.size()));
  r.names.push_back(pass);
}

void Profiler::end(VkCommandBuffer cb) {
  mark(cb, "");
}

void Profiler::collect() {
  if (!ctx_.info().timestamps || rec_.empty()) return;
  auto it = rec_.find(last_);
  if (it == rec_.end()) return;
  {
    Recording& r = it->second;
    if (r.names.size() < 2) return;
    std::vector<uint64_t> ts(r.names.size());
    VkResult res = vkGetQueryPoolResults(ctx_.device(), r.pool, 0, uint32_t(ts.size()), ts.size() * 8,
                                         ts.data(), 8, VK_QUERY_RESULT_64_BIT);
    if (res != VK_SUCCESS) return;
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
      PassTiming& t = acc_[r.names[k]];
      t.name = r.names[k];
      t.seconds += double(ts[k + 1] - ts[k]) * ctx_.info().timestamp_period_ns * 1e-9;
      t.dispatches++;
    }
  }
}

std::vector<PassTiming> Profiler::timings() const {
  std::vector<PassTiming> out;
  for (auto& [k, v] : acc_) out.push_back(v);
  return out;
}

}  // namespace wetdem::gpu
