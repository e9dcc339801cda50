// The GPU system: the recording of a step's passes (ARCHITECTURE.md "Passes of a step")
// and the submit loop with overflow recovery. Parameters: system_params.cpp; state transfer, snapshots:
// system_state.cpp.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gpu/system_impl.h"

namespace wetdem {

using gpu::groups_for;
using gpu::Push;

namespace {
size_t total(const std::vector<size_t>& sizes) {
  size_t t = 0;
  for (size_t k : sizes) {
    if (k == 0) throw std::invalid_argument("System: every run needs at least one particle");
    t += k;
  }
  return t;
}
}  // namespace

System::Impl::Impl(vk::Context& c, const std::vector<SimParams>& runs, const std::vector<size_t>& sizes,
                   SystemOptions o)
    : ctx(c), prm(runs.at(0)), run_prm(runs), opt(o), n(uint32_t(total(sizes))), prof(c) {
  if (runs.size() != sizes.size()) throw std::invalid_argument("System: one particle count per run");
  const size_t num = total(sizes);
  if (num == 0 || num >= (1u << 31))
    throw std::invalid_argument("System: particle count must be in [1, 2^31)");
  run_off.assign(1, 0u);
  for (size_t k : sizes) run_off.push_back(run_off.back() + uint32_t(k));
  // Every kernel of a System but the sort's and the scan's.
  const char* names[] = {"pair_force",
                         "gather_kick",
                         "liq_rupture_share",
                         "liq_rupture_apply",
                         "liq_form_offer",
                         "liq_form_apply",
                         "liq_form_take",
                         "rebuild_decide",
                         "cell_key",
                         "reorder",
                         "fill_u32",
                         "cell_ranges",
                         "nbr_count",
                         "build_args",
                         "nbr_fill",
                         "mirror",
                         "history_map",
                         "lost_check",
                         "flip",
                         "end_step",
                         "liq_upload_flags",
                         "owner_count",
                         "owner_fill"};
  // Specialization constant 0: the number of runs (access.glsl: one run reads its parameters uniformly).
  for (const char* nm : names)
    kernels[nm] = std::make_unique<vk::Kernel>(ctx, nm, std::vector<uint32_t>{uint32_t(runs.size())});
  fused = opt.fused_step && ctx.info().int64_atomics;
  sort = std::make_unique<gpu::RadixSort>(ctx, n);
  sort->set_one_tile(opt.one_tile_sort);
  scan = std::make_unique<gpu::Scan>(ctx, n);
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  WETDEM_VK(vkCreateFence(ctx.device(), &fci, nullptr, &fence));
}

System::Impl::~Impl() {
  vkDeviceWaitIdle(ctx.device());
  drop_cache();
  vkDestroyFence(ctx.device(), fence, nullptr);
}

void System::Impl::drop_cache() {
  for (auto* m : {&cached, &plain}) {
    for (auto& [k, cb] : *m) vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &cb);
    m->clear();
  }
  if (chain_cb) vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &chain_cb);
  chain_cb = VK_NULL_HANDLE;
  per_step_dispatches.clear();
}

void System::Impl::run(VkCommandBuffer cb, const char* name, uint32_t groups, uint32_t a0) {
  Push p = push();
  ++n_dispatch;
  p.a0 = a0;
  if (opt.profile_passes) prof.mark(cb, name);
  kernels.at(name)->dispatch(cb, groups, &p, sizeof(p));
  vk::barrier(cb);
}

void System::Impl::run_indirect(VkCommandBuffer cb, const char* name, uint32_t word, uint32_t a0) {
  Push p = push();
  ++n_dispatch;
  p.a0 = a0;
  if (opt.profile_passes) prof.mark(cb, name);
  kernels.at(name)->dispatch_indirect(cb, B->ctl.handle(), word * 4, &p, sizeof(p));
  vk::barrier(cb);
}

void System::Impl::gated(VkCommandBuffer cb, const char* name, uint32_t groups, uint32_t a0) {
  Push p = push();
  p.a0 = a0;
  gate.dispatch(cb, *kernels.at(name), groups, &p, sizeof(p));
  vk::barrier(cb);
}

// Rebuild chain 6a-6n (ARCHITECTURE.md); every dispatch is gated by the rebuild decision. end_step: its flip
// also ends the step (the fused step's gated chain).
void System::Impl::record_rebuild(VkCommandBuffer cb, bool end_step) {
  const uint32_t gN = groups_for(n);
  gated(cb, "cell_key", gN);
  sort->record(cb, gate, B->cell_key.address(), B->sort_val.address(), n, key_bits);
  struct {
    uint64_t dst;
    uint32_t n, value;
  } fill{B->cell_start.address(), cells, 0xFFFFFFFFu};
  gate.dispatch(cb, *kernels.at("fill_u32"), groups_for(cells), &fill, sizeof(fill));
  gated(cb, "reorder", gN);
  gated(cb, "cell_ranges", gN);
  gated(cb, "nbr_count", gN, keep_stride());
  scan->record(cb, gate, B->cnt_scan.address(), n, B->ctl.address() + ctlw::kEntriesNeeded * 4);
  gated(cb, "build_args", 1);
  record_list_tail(cb, false, end_step);
}

// Candidates per particle that 6e keeps for 6g in the pair-force scratch (3 words per entry of capacity,
// at least 16 entries per particle until a regrowth): up to 32, fewer when the scratch is smaller; a particle
// with more is searched again by 6g.
uint32_t System::Impl::keep_stride() const {
  const uint64_t words = 3ull * B->scratch_capacity();
  return uint32_t(std::min<uint64_t>(32, words / std::max<uint32_t>(n, 1)));
}

// 6g-6n: fill, mirror, history, lost check, owner list, flip. Direct dispatches when finishing a halted
// rebuild.
void System::Impl::record_list_tail(VkCommandBuffer cb, bool direct, bool end_step) {
  const uint32_t gN = groups_for(n);
  // After an overflow regrowth the pair-force scratch that held 6e's candidates may be new: search again.
  if (direct)
    run(cb, "nbr_fill", gN, 0);
  else
    gated(cb, "nbr_fill", gN, keep_stride());
  run_indirect(cb, "mirror", ctlw::kBuildArgs);
  if (direct)
    run(cb, "history_map", gN);
  else
    gated(cb, "history_map", gN);
  run_indirect(cb, "lost_check", ctlw::kLostArgs);
  // 6k-6m: the owner list of the new list (count per particle, scan, fill).
  gpu::DirectDispatcher now;
  if (direct)
    run(cb, "owner_count", gN);
  else
    gated(cb, "owner_count", gN);
  scan->record(cb, direct ? static_cast<gpu::Dispatcher&>(now) : gate, B->own_scan.address(), n,
               B->ctl.address() + ctlw::kOwnersNeeded * 4);
  if (direct) {
    run(cb, "owner_fill", gN);
    run(cb, "flip", 1, end_step ? 1u : 0u);
  } else {
    gated(cb, "owner_fill", gN);
    gated(cb, "flip", 1, end_step ? 1u : 0u);
  }
}

// One step. Pass by pass (SystemOptions::fused_step off): kick-drift, pair forces, gather and second kick,
// liquid 4a-4e, the rebuild decision, the gated chain and end_step (or, split, the decision ends the step).
// Fused (ARCHITECTURE.md "Passes of a step"): pair forces; the gather with 4a, the next step's kick-drift
// (not on a batch's last step, so that a submit ends on a whole step) and, in its last workgroup, the liquid
// gate; 4b-4d behind that gate, the last workgroup of 4d (or of the gather when the gate is closed) deciding
// the rebuild; a batch's first step starts with the kick-drift on its own unless the step before did it.
void System::Impl::record_step(VkCommandBuffer cb, bool split, bool first, bool last) {
  namespace md = gpu::mode;
  // Per-particle passes read their size from ctl too: after a split halt the rest of the submit is zero-sized
  // (step_control.glsl close_step_passes) instead of launching workgroups that would only return.
  const uint32_t sN = ctlw::kStepArgs;
  if (!fused) {
    run_indirect(cb, "gather_kick", sN, md::kKickDrift);
    run_indirect(cb, "pair_force", ctlw::kOwnerArgs);
    run_indirect(cb, "gather_kick", sN, md::kGather);
    if (gp.liquid_on) {
      run_indirect(cb, "liq_rupture_share", sN);
      run_indirect(cb, "liq_rupture_apply", ctlw::kOwnerArgs);
      run_indirect(cb, "liq_form_offer", sN);
      run_indirect(cb, "liq_form_apply", ctlw::kOwnerArgs);
      run_indirect(cb, "liq_form_take", sN);
    }
    // Split: ends the step, or halts it (and the rest of the command buffer) when it must rebuild; see
    // step().
    run(cb, "rebuild_decide", 1, split ? 1u : 0u);
    if (split) return;
    record_rebuild(cb, false);
    run(cb, "end_step", 1);
    return;
  }
  if (first) run_indirect(cb, "gather_kick", sN, md::kKickDrift | md::kUnlessDrifted);
  run_indirect(cb, "pair_force", ctlw::kOwnerArgs);
  uint32_t m = md::kGather | md::kFinish | (last ? 0u : uint32_t(md::kKickDrift)) | (split ? md::kSplit : 0u);
  if (gp.liquid_on) {
    m |= md::kShare | md::kLiquid | (opt.liquid_gate ? md::kGate : 0u);
    for (const gpu::GpuParams& g : gps)
      if (g.absorb_mode != 0u || g.evap_on != 0u) m |= md::kSinks;
  }
  run_indirect(cb, "gather_kick", sN, m);
  if (gp.liquid_on) {
    run_indirect(cb, "liq_rupture_apply", ctlw::kLiqArgs, md::kAtomic);
    run_indirect(cb, "liq_form_offer", ctlw::kLiqArgs + 3, md::kAtomic | md::kGated);
    run_indirect(cb, "liq_form_apply", ctlw::kLiqArgs + 6,
                 md::kAtomic | md::kLqFinish | (split ? md::kLqSplit : 0u));
  }
  if (!split) record_rebuild(cb, true);  // its flip ends a rebuild step; the decision ended any other
}

// Split rebuilds: steps per submit. A batch that ends before the next rebuild costs a host round trip; one
// that halts early costs its remaining steps, each a few empty dispatches. On the H100 (docs/benchmark.md "On
// a GPU") a round trip cost about as much as 20 halted steps, so a batch runs past the estimated next rebuild
// by half an interval; if none came, shorter batches follow. One command buffer is recorded per batch length.
uint32_t System::Impl::plan_split_batch(uint64_t count) const {
  const double left = 1.5 * interval_est - double(since_rebuild);
  const double want = left >= 1.0 ? std::ceil(left) : std::max(1.0, std::floor(interval_est / 4.0));
  // Lengths on a ~1.5x ladder (1, 2, 3, 4, 6, 8, 12, ...), rounded up: few distinct command buffers to
  // record.
  uint32_t k = 1;
  while (double(k) < want) k = k < 4 ? k + 1 : (k % 3 == 0 ? k / 3 * 4 : k / 2 * 3);
  k = std::min<uint32_t>(k, std::max<uint32_t>(1, opt.steps_per_submit));
  return uint32_t(std::min<uint64_t>(k, count));
}

VkCommandBuffer System::Impl::allocate_cb() {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = ctx.pool();
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cb;
  WETDEM_VK(vkAllocateCommandBuffers(ctx.device(), &ai, &cb));
  return cb;
}

void System::Impl::submit(VkCommandBuffer cb) {
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cb;
  WETDEM_VK(vkResetFences(ctx.device(), 1, &fence));
  prof.submitted(cb);
  WETDEM_VK(vkQueueSubmit(ctx.queue(), 1, &si, fence));
  WETDEM_VK(vkWaitForFences(ctx.device(), 1, &fence, VK_TRUE, UINT64_MAX));
  if (opt.profile_passes) prof.collect();
}

// A rebuild halted on overflow: grow the set being built, finish the rebuild (and the step).
void System::Impl::recover(const std::vector<uint32_t>& c, bool finish_step) {
  const uint32_t need = c[ctlw::kEntriesNeeded];
  const uint32_t next = 1u - c[ctlw::kParity];
  const uint32_t cap = need + need / 2 + 1024;
  B->grow_entries(next, cap);
  B->upload_table();
  uint32_t caps[2] = {B->capacity(0), B->capacity(1)};
  B->ctl.upload(caps, sizeof(caps), ctlw::kCapacity0 * 4);
  uint32_t zero = 0;
  B->ctl.upload(&zero, 4, ctlw::kHalt * 4);
  ctr.regrows++;
  VkCommandBuffer cb = record([&](VkCommandBuffer r) {
    run(r, "build_args", 1);
    record_list_tail(r, true, finish_step);
  });
  submit(cb);
  vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &cb);
  auto after = read_ctl();
  if (after[ctlw::kHalt]) throw std::runtime_error("neighbour list overflowed again after growing");
}

void System::Impl::check_health(const std::vector<uint32_t>& c) {
  ctr.lost_bridges = c[ctlw::kLostBridges];
  ctr.escaped = c[ctlw::kEscaped];
  ctr.entries = c[ctlw::kEntries];
  ctr.entry_capacity = std::min(B->capacity(0), B->capacity(1));
  ctr.liquid_steps = c[ctlw::kLiquidSteps];
  ctr.rebuilds += uint32_t(c[ctlw::kRebuilds] - last_rebuilds);
  last_rebuilds = c[ctlw::kRebuilds];
  events.formations += uint32_t(c[ctlw::kFormations] - last_form);
  events.ruptures += uint32_t(c[ctlw::kRuptures] - last_rupt);
  last_form = c[ctlw::kFormations];
  last_rupt = c[ctlw::kRuptures];
  if (c[ctlw::kMirrorErrors]) throw std::runtime_error("neighbour list is not symmetric (internal error)");
  if (c[ctlw::kLostBridges])
    throw std::runtime_error(
        fmt::format("{} liquid bridge(s) left the neighbour list without rupturing", c[ctlw::kLostBridges]));
}

void System::Impl::step(uint64_t count) {
  if (!uploaded) throw std::logic_error("System::step before upload");
  while (count > 0) {
    // Split only while rebuilds are several steps apart: below that the round trips cost more than the
    // empty gated dispatches they save (H100: 0.72x at 3.3 steps per rebuild, 1.2-1.7x at 30-130).
    const bool split = opt.split_rebuilds && interval_est >= opt.split_min_interval;
    uint32_t k = split ? plan_split_batch(count)
                       : uint32_t(std::min<uint64_t>(count, std::max<uint32_t>(1, opt.steps_per_submit)));
    // Bounded caches: batch lengths vary with the remaining count and the plan; re-recording is cheap.
    for (auto* m : {&cached, &plain})
      if (m->size() > 32 && !m->count(k)) {
        for (auto& [len, old] : *m) {
          per_step_dispatches.erase(old);
          vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &old);
        }
        m->clear();
      }
    VkCommandBuffer& cb = split ? plain[k] : cached[k];
    if (!cb) {
      const uint64_t d0 = dispatches_recorded();
      cb = record([&](VkCommandBuffer r) {
        for (uint32_t s = 0; s < k; ++s) record_step(r, split, s == 0, s + 1 == k);
      });
      per_step_dispatches[cb] = double(dispatches_recorded() - d0) / double(k);
    }
    ctr.dispatches_per_step = per_step_dispatches[cb];
    const uint32_t rebuilds_before = last_rebuilds;
    submit(cb);
    auto c = read_ctl();
    bool halted_for_rebuild = false;
    if (c[ctlw::kHalt] == ctlw::kHaltForRebuild) {
      // The step that asked stopped after rebuild_decide (gates open): clear the halt, run its chain and end.
      halted_for_rebuild = true;
      ctr.split_rebuilds++;
      if (!chain_cb)
        chain_cb = record([&](VkCommandBuffer r) {
          vkCmdFillBuffer(r, B->ctl.handle(), ctlw::kHalt * 4, 4, 0u);
          vk::barrier(r);
          record_rebuild(r, true);
        });
      submit(chain_cb);
      c = read_ctl();
    }
    if (c[ctlw::kHalt]) {
      recover(c, true);
      c = read_ctl();
    }
    uint32_t done = c[ctlw::kStepsDone] - last_steps_word;
    last_steps_word = c[ctlw::kStepsDone];
    check_health(c);
    steps += done;
    ctr.steps += done;
    count -= std::min<uint64_t>(count, done);
    if (done == 0) throw std::runtime_error("GPU step made no progress");
    // Interval estimate: exact when a split batch halted (the rebuild was its last step); a gated batch only
    // says whether rebuilds happened in it.
    if (halted_for_rebuild) {
      interval_est = 0.5 * interval_est + 0.5 * double(since_rebuild + done);
      since_rebuild = 0;
    } else if (last_rebuilds != rebuilds_before) {
      const uint32_t r = last_rebuilds - rebuilds_before;
      interval_est = 0.5 * interval_est + 0.5 * double(done) / double(r);
      since_rebuild = 0;
    } else {
      since_rebuild += done;
      interval_est = std::max(interval_est, double(since_rebuild));
    }
    // A step() ends on a whole step: a batch's last step does not start the next one's kick-drift, and a
    // batch that halted earlier is followed by another (it did fewer steps than asked).
    if (count == 0 && c[ctlw::kDrifted] != 0u)
      throw std::runtime_error("GPU step ended half-way through a kick-drift (internal error)");
  }
}

System::System(vk::Context& ctx, const SimParams& prm, size_t num_particles, SystemOptions opt)
    : impl_(std::make_unique<Impl>(ctx, std::vector<SimParams>{prm}, std::vector<size_t>{num_particles},
                                   opt)) {}
System::System(vk::Context& ctx, const std::vector<SimParams>& runs, const std::vector<size_t>& sizes,
               SystemOptions opt)
    : impl_(std::make_unique<Impl>(ctx, runs, sizes, opt)) {}
void System::upload_runs(const std::vector<SystemState>& states) {
  if (states.size() != impl_->run_prm.size())
    throw std::invalid_argument(
        fmt::format("upload_runs: {} states for {} runs", states.size(), impl_->run_prm.size()));
  for (size_t r = 0; r < states.size(); ++r)
    if (states[r].p.size() != impl_->run_off[r + 1] - impl_->run_off[r])
      throw std::invalid_argument(fmt::format("upload_runs: run {} has {} particles, the system holds {}", r,
                                              states[r].p.size(), impl_->run_off[r + 1] - impl_->run_off[r]));
  impl_->upload(concat_states(states));
}
std::vector<SystemState> System::download_runs() {
  std::vector<size_t> sizes;
  for (size_t r = 0; r + 1 < impl_->run_off.size(); ++r)
    sizes.push_back(impl_->run_off[r + 1] - impl_->run_off[r]);
  return split_state(impl_->download(), sizes);
}
size_t System::runs() const {
  return impl_->run_prm.size();
}
const SimParams& System::run_params(size_t r) const {
  return impl_->run_prm.at(r);
}
void System::set_run_params(size_t r, const SimParams& prm) {
  impl_->set_run_params(r, prm);
}
System::~System() = default;
void System::upload(const SystemState& s) {
  impl_->upload(s);
}
SystemState System::download() {
  return impl_->download();
}
void System::step(uint64_t n) {
  impl_->step(n);
}
std::vector<uint8_t> System::snapshot() {
  return impl_->snapshot();
}
void System::restore(const std::vector<uint8_t>& blob) {
  impl_->restore(blob);
}
void System::fill_scratch(uint32_t word) {
  gpu::BufferSet& b = *impl_->B;
  const uint32_t cur = impl_->read_ctl()[ctlw::kParity];
  for (uint32_t f = 0; f < gpu::kNumParticleFields; ++f) b.pset[1 - cur][f].fill(word);
  for (uint32_t f = 0; f < gpu::kNumEntryFields; ++f) b.eset[1 - cur][f].fill(word);
  for (vk::Buffer* x : {&b.cell_key, &b.sort_val, &b.cell_start, &b.cell_end, &b.cnt_scan, &b.pair_f,
                        &b.pair_t, &b.ev, &b.p_share, &b.p_gain, &b.p_full, &b.p_offer, &b.own_scan})
    x->fill(word);
}
void System::force_rebuild() {
  uint32_t one = 1;
  impl_->B->ctl.upload(&one, 4, ctlw::kForceRebuild * 4);
}
std::vector<std::pair<uint32_t, uint32_t>> System::neighbour_pairs() {
  return impl_->neighbour_pairs();
}
Observables System::observables() {
  return compute_observables(impl_->download(), impl_->prm);
}
EventCounts System::read_events() {
  EventCounts e = impl_->events;
  impl_->events = {};
  return e;
}
SystemCounters System::counters() const {
  return impl_->ctr;
}
std::vector<PassTiming> System::pass_timings() const {
  return impl_->prof.timings();
}
void System::reset_pass_timings() {
  impl_->prof.reset();
}
const SimParams& System::params() const {
  return impl_->prm;
}
size_t System::size() const {
  return impl_->n;
}
std::string System::device_name() const {
  return impl_->ctx.info().name;
}
double System::tick_size() const {
  return impl_->h;
}

}  // namespace wetdem
