// Internals of the GPU system (include/wetdem/system.h): the Impl that owns the buffers, kernels and
// counters. system.cpp holds set-up, recording and the step loop; system_state.cpp moves state in and out.
#pragma once

#include "wetdem/system.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>

#include "gpu/buffer_set.h"
#include "gpu/dispatcher.h"
#include "gpu/gpu_layout.h"
#include "gpu/profiler.h"
#include "gpu/radix_sort.h"
#include "gpu/scan.h"
#include "vk/buffer.h"
#include "vk/context.h"
#include "vk/kernel.h"

namespace wetdem {

using gpu::BufferSet;
namespace ctlw = gpu::ctl;

namespace gpu {
struct Push {
  uint64_t table;
  uint32_t a0, a1;
};

inline constexpr uint32_t kGroup = 256;
inline uint32_t groups_for(uint64_t n) {
  return uint32_t((n + kGroup - 1) / kGroup);
}

// Records each dispatch as an indirect one whose size lives in a ctl slot; rebuild_decide writes the
// nominal size there on rebuild steps and zero otherwise. Slots are shared by equal group counts.
class GatedDispatcher final : public Dispatcher {
 public:
  void dispatch(VkCommandBuffer cb, const vk::Kernel& k, uint32_t groups, const void* push,
                uint32_t push_bytes) override {
    auto it = std::find(groups_.begin(), groups_.end(), groups);
    size_t slot = size_t(it - groups_.begin());
    if (it == groups_.end()) {
      if (groups_.size() >= ctlw::kMaxGates)
        throw std::runtime_error("too many distinct gated dispatch sizes");
      groups_.push_back(groups);
    }
    if (prof_) prof_->mark(cb, k.name());
    k.dispatch_indirect(cb, ctl_, (ctlw::kGateArgs + 4 * slot) * 4, push, push_bytes);
    ++count_;
  }
  uint64_t count() const { return count_; }  // dispatches recorded so far
  void set(VkBuffer ctl, Profiler* prof) {
    ctl_ = ctl;
    prof_ = prof;
  }
  const std::vector<uint32_t>& groups() const { return groups_; }

 private:
  VkBuffer ctl_ = VK_NULL_HANDLE;
  Profiler* prof_ = nullptr;
  std::vector<uint32_t> groups_;
  uint64_t count_ = 0;
};
}  // namespace gpu

struct System::Impl {
  vk::Context& ctx;
  SimParams prm;                   // run 0's (the only run's) parameters, skin resolved
  std::vector<SimParams> run_prm;  // ensembles: each run's parameters (docs/ensembles.md); [0] is prm
  std::vector<uint32_t> run_off;   // first stable id of each run, and n at the end
  SystemOptions opt;
  uint32_t skin_rule() const {  // ctl[kSkinRule] (SystemOptions::skin_drum_frame, skin_top_two)
    return (opt.skin_drum_frame ? ctlw::kSkinDrumFrame : 0u) | (opt.skin_top_two ? ctlw::kSkinTopTwo : 0u);
  }
  bool fused = true;  // opt.fused_step where the device has 64-bit buffer atomics
  uint32_t n;
  double h = 0.0, inv_h = 0.0;                  // tick size (m)
  double setup_r_max = 0.0, setup_r_min = 0.0;  // setup()'s inputs, kept for snapshots
  gpu::GpuParams gp{};                          // run 0's block (fields every run shares are the same in all)
  std::vector<gpu::GpuParams> gps;              // one block per run
  gpu::GpuParams shared{};                      // the fields every run shares (setup), copied into each block
  double shared_skin = 0.0, shared_range = 0.0;  // the rebuild schedule's skin, the list's bridge range
  void build_params();
  uint32_t cells = 0, key_bits = 1;
  // Wall records per particle: one per wall the drum has (buffer_set.h); the slot of wall w, -1 if absent.
  uint32_t drum_wall_slots() const;
  int wall_slot[3] = {0, 1, 2};
  std::unique_ptr<BufferSet> B;
  std::map<std::string, std::unique_ptr<vk::Kernel>> kernels;
  std::unique_ptr<gpu::RadixSort> sort;
  std::unique_ptr<gpu::Scan> scan;
  gpu::GatedDispatcher gate;
  gpu::Profiler prof;
  std::map<uint32_t, VkCommandBuffer> cached;  // recorded k-step command buffers, by k
  std::map<uint32_t, VkCommandBuffer> plain;   // the same without the rebuild chain (split rebuilds)
  VkCommandBuffer chain_cb = VK_NULL_HANDLE;   // rebuild chain ending a halted split step
  std::map<VkCommandBuffer, double> per_step_dispatches;  // dispatches recorded per step, by batch
  uint64_t n_dispatch = 0;                                // dispatches recorded by run, run_indirect, gated
  uint64_t dispatches_recorded() const { return n_dispatch + gate.count(); }
  double interval_est = 16.0;  // steps between rebuilds, running estimate (split rebuilds)
  uint64_t since_rebuild = 0;  // completed steps since the last rebuild (split rebuilds)
  VkFence fence = VK_NULL_HANDLE;
  double time0 = 0.0;
  uint64_t step0 = 0, steps = 0;
  uint32_t last_steps_word = 0, last_form = 0, last_rupt = 0, last_rebuilds = 0;
  EventCounts events;
  SystemCounters ctr;
  bool uploaded = false;

  Impl(vk::Context& c, const std::vector<SimParams>& runs, const std::vector<size_t>& sizes, SystemOptions o);
  uint32_t run_of(uint32_t id) const;  // the run of a stable id
  void set_run_params(size_t r, const SimParams& p);
  ~Impl();
  void drop_cache();
  // ---- parameters and grid -------------------------------------------------------------------------
  void setup(double r_max, double r_min);
  // ---- recording -----------------------------------------------------------------------------------
  gpu::Push push() const { return gpu::Push{B->table_buf.address(), 0, 0}; }
  void run(VkCommandBuffer cb, const char* name, uint32_t groups, uint32_t a0 = 0);
  void run_indirect(VkCommandBuffer cb, const char* name, uint32_t word, uint32_t a0 = 0);
  void gated(VkCommandBuffer cb, const char* name, uint32_t groups, uint32_t a0 = 0);
  uint32_t keep_stride() const;
  // Rebuild chain 6a-6n (ARCHITECTURE.md); every dispatch is gated by the rebuild decision. end_step: the
  // chain's flip also ends the step.
  void record_rebuild(VkCommandBuffer cb, bool end_step);
  // 6g-6n: fill, mirror, history, lost check, owner list, flip. Direct dispatches when finishing a halted
  // rebuild.
  void record_list_tail(VkCommandBuffer cb, bool direct, bool end_step);
  // One step of a batch (first / last step of the batch: the fused step's kick-drift, system.cpp).
  void record_step(VkCommandBuffer cb, bool split, bool first, bool last);
  uint32_t plan_split_batch(uint64_t count) const;
  VkCommandBuffer allocate_cb();
  template <class Fn>
  VkCommandBuffer record(Fn&& fn) {
    VkCommandBuffer cb = allocate_cb();
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    WETDEM_VK(vkBeginCommandBuffer(cb, &bi));
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, ctx.pipeline_layout(), 0, 1, &B->descriptors,
                            0, nullptr);
    if (opt.profile_passes) prof.begin(cb);
    fn(cb);
    if (opt.profile_passes) prof.end(cb);
    WETDEM_VK(vkEndCommandBuffer(cb));
    // Gate sizes are known once recorded: publish them before the first submit.
    const auto& g = gate.groups();
    if (!g.empty()) B->ctl.upload(g.data(), g.size() * 4, ctlw::kGateGroups * 4);
    return cb;
  }
  void submit(VkCommandBuffer cb);
  std::vector<uint32_t> read_ctl() { return B->ctl.download_as<uint32_t>(32); }
  void recover(const std::vector<uint32_t>& c, bool finish_step);
  void check_health(const std::vector<uint32_t>& c);
  void step(uint64_t count);
  // ---- state transfer --------------------------------------------------------------------------------
  void upload(const SystemState& s);
  SystemState download();
  std::vector<std::pair<uint32_t, uint32_t>> neighbour_pairs();
  // ---- sampling (system_sample.cpp) --------------------------------------------------------------------
  std::vector<RunSample> sample_runs();
  std::unique_ptr<vk::Staging> smp_staging;  // kept: a sample every few thousand steps reuses it
  uint64_t smp_staging_bytes = 0;
  // ---- snapshots -------------------------------------------------------------------------------------
  std::vector<uint8_t> snapshot();
  void restore(const std::vector<uint8_t>& blob);
};

}  // namespace wetdem
