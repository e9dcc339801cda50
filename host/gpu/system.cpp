// The GPU system: parameter upload, the recording of a step's passes (ARCHITECTURE.md "Passes of a step"),
// the submit loop with overflow recovery, and conversions between the host state and device buffers.
#include "wetdem/system.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
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

namespace {

struct Push {
  uint64_t table;
  uint32_t a0, a1;
};

constexpr uint32_t kGroup = 256;
uint32_t groups_for(uint64_t n) {
  return uint32_t((n + kGroup - 1) / kGroup);
}

// Records each dispatch as an indirect one whose size lives in a ctl slot; rebuild_decide writes the
// nominal size there on rebuild steps and zero otherwise. Slots are shared by equal group counts.
class GatedDispatcher final : public gpu::Dispatcher {
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
  }
  void set(VkBuffer ctl, gpu::Profiler* prof) {
    ctl_ = ctl;
    prof_ = prof;
  }
  const std::vector<uint32_t>& groups() const { return groups_; }

 private:
  VkBuffer ctl_ = VK_NULL_HANDLE;
  gpu::Profiler* prof_ = nullptr;
  std::vector<uint32_t> groups_;
};

}  // namespace

struct System::Impl {
  vk::Context& ctx;
  SimParams prm;
  SystemOptions opt;
  uint32_t n;
  double h = 0.0, inv_h = 0.0;  // tick size (m)
  gpu::GpuParams gp{};
  uint32_t cells = 0, key_bits = 1;
  std::unique_ptr<BufferSet> B;
  std::map<std::string, std::unique_ptr<vk::Kernel>> kernels;
  std::unique_ptr<gpu::RadixSort> sort;
  std::unique_ptr<gpu::Scan> scan;
  GatedDispatcher gate;
  gpu::Profiler prof;
  std::map<uint32_t, VkCommandBuffer> cached;  // recorded k-step command buffers, by k
  VkFence fence = VK_NULL_HANDLE;
  double time0 = 0.0;
  uint64_t step0 = 0, steps = 0;
  uint32_t last_steps_word = 0, last_form = 0, last_rupt = 0, last_rebuilds = 0;
  EventCounts events;
  SystemCounters ctr;
  bool uploaded = false;

  Impl(vk::Context& c, const SimParams& p, size_t num, SystemOptions o)
      : ctx(c), prm(p), opt(o), n(uint32_t(num)), prof(c) {
    if (num == 0 || num >= (1u << 31))
      throw std::invalid_argument("System: particle count must be in [1, 2^31)");
    const char* names[] = {
        "kick_drift",     "pair_force",     "gather_kick",   "liq_rupture_share", "liq_rupture_apply",
        "liq_form_offer", "liq_form_apply", "liq_form_take", "rebuild_decide",    "cell_key",
        "reorder",        "fill_u32",       "cell_ranges",   "nbr_count",         "build_args",
        "nbr_fill",       "mirror",         "history_map",   "lost_check",        "flip",
        "end_step"};
    for (const char* nm : names) kernels[nm] = std::make_unique<vk::Kernel>(ctx, nm);
    sort = std::make_unique<gpu::RadixSort>(ctx, n);
    scan = std::make_unique<gpu::Scan>(ctx, n);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    WETDEM_VK(vkCreateFence(ctx.device(), &fci, nullptr, &fence));
  }
  ~Impl() {
    vkDeviceWaitIdle(ctx.device());
    drop_cache();
    vkDestroyFence(ctx.device(), fence, nullptr);
  }

  void drop_cache() {
    for (auto& [k, cb] : cached) vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &cb);
    cached.clear();
  }

  // ---- parameters and grid -------------------------------------------------------------------------
  void setup(double r_max, double r_min) {
    // The list must hold every pair that can touch at the next force evaluation, so a skin of zero is
    // not usable: 0 selects 0.1 r_min (a rebuild every few steps at drum speeds).
    if (prm.skin <= 0.0) prm.skin = 0.1 * r_min;
    const DrumParams& d = prm.drum;
    if (!(d.radius > 0) || !(d.length > 0))
      throw std::invalid_argument("drum: radius and length must be > 0");
    if (!(prm.dt > 0)) throw std::invalid_argument("dt must be > 0");
    const double range_pp = prm.bridge_range_pp();
    const double cutoff_extra = range_pp + prm.skin;
    const double cell = 2.0 * r_max + cutoff_extra;
    // The tick depends on the drum alone (not on the particles), so quantised states stay quantised.
    const double half_extent = std::max(d.radius, 0.5 * d.length) * 1.5;
    // |ticks| < 2^29: differences of two positions fit in int32. L/2 is a whole number of ticks, so the
    // plates and the periodic length are exact.
    const double half_len_ticks = std::ceil(0.5 * d.length / (half_extent / double(1 << 29)));
    h = 0.5 * d.length / half_len_ticks;
    if (cell > 0.25 * half_extent)
      throw std::invalid_argument(
          fmt::format("particles too large for the drum: interaction distance {:.4g} m", cell));
    inv_h = 1.0 / h;
    const int64_t cell_ticks = int64_t(std::ceil(cell * inv_h));
    const double margin = cell;
    int32_t origin[3], dims[3];
    for (int a = 0; a < 2; ++a) {
      double lo = -(d.radius + margin);
      origin[a] = int32_t(std::floor(lo * inv_h));
      dims[a] = int32_t(std::ceil((2.0 * (d.radius + margin)) * inv_h / double(cell_ticks)));
    }
    int64_t period = 0;
    if (d.periodic_z) {
      period = std::llround(d.length * inv_h);
      origin[2] = int32_t(-(period / 2));
      dims[2] = int32_t(std::max<int64_t>(1, period / cell_ticks));
      if (d.length < 2.0 * cell)
        throw std::invalid_argument(
            fmt::format("drum.length: a periodic slice must be at least twice the interaction distance "
                        "({:.4g} m), got {:.4g} m",
                        cell, d.length));
    } else {
      double lo = -(0.5 * d.length + margin);
      origin[2] = int32_t(std::floor(lo * inv_h));
      dims[2] = int32_t(std::ceil((d.length + 2.0 * margin) * inv_h / double(cell_ticks)));
    }
    uint64_t ncells = uint64_t(dims[0]) * dims[1] * dims[2];
    uint32_t hash_mask = 0;
    // A domain much larger than the particles (a test box, a sparse gas) would need a huge dense grid:
    // hash the cells into a power-of-two table instead (cell order then no longer follows space).
    if (ncells > std::max<uint64_t>(8ull * n, 1u << 16)) {
      uint64_t buckets = 1024;
      while (buckets < 2ull * n) buckets *= 2;
      hash_mask = uint32_t(buckets - 1);
      ncells = buckets;
      origin[0] = origin[1] = -(1 << 30);
      if (!d.periodic_z) origin[2] = -(1 << 30);
    }
    cells = uint32_t(ncells);
    key_bits = 1;
    while ((1ull << key_bits) < ncells) ++key_bits;

    auto contact = [](const ContactParams& c) {
      gpu::GpuContact g{};
      g.E_star = float(c.E_star);
      g.G_star = float(c.G_star);
      g.phi_n = float(damping_factor(c.restitution));
      g.mu_s = float(c.mu_s);
      g.mu_r = float(c.mu_r);
      g.phi_t = float(c.phi_t);
      g.eta_r = float(c.eta_r);
      return g;
    };
    auto liquid = [&](const LiquidParams& l, double range) {
      gpu::GpuLiquid g{};
      const double pi = 3.14159265358979323846;
      g.v_min = l.v_min;
      g.v_max = l.v_max;
      g.f0_per_Rh = float(2.0 * pi * l.gamma * std::cos(l.theta));
      g.rupture_coef = float(1.0 + 0.5 * l.theta);
      g.unit_m3 = float(prm.liquid_unit_m3);
      g.range = float(range);
      g.enabled = l.enabled ? 1u : 0u;
      g.dc_q16 = uint32_t(std::lround(std::clamp(l.d_c, 0.0, 1.0) * 65536.0));
      return g;
    };
    gp = {};
    gp.pp = contact(prm.pp);
    gp.lpp = liquid(prm.liq_pp, range_pp);
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      gp.pw[w] = contact(prm.pw[w]);
      gp.lpw[w] = liquid(prm.liq_pw[w], prm.bridge_range_pw(w));
    }
    const int64_t r_ticks = std::llround(d.radius * inv_h);
    gp.drum_r_ticks = int32_t(r_ticks);
    gp.drum_r_frac = float(d.radius * inv_h - double(r_ticks));
    gp.drum_r2_ticks = r_ticks * r_ticks;
    gp.plate_z_ticks = int32_t(std::llround(0.5 * d.length * inv_h));
    gp.period_ticks = int32_t(period);
    gp.cell_ticks = int32_t(cell_ticks);
    for (int a = 0; a < 3; ++a) {
      gp.grid_origin[a] = origin[a];
      gp.grid_dims[a] = dims[a];
    }
    gp.plate_present[0] = d.plate_lo.present ? 1u : 0u;
    gp.plate_present[1] = d.plate_hi.present ? 1u : 0u;
    gp.plate_rotates[0] = d.plate_lo.rotates ? 1u : 0u;
    gp.plate_rotates[1] = d.plate_hi.rotates ? 1u : 0u;
    gp.num_particles = n;
    bool liquid_on = prm.liq_pp.enabled;
    for (auto& l : prm.liq_pw) liquid_on = liquid_on || l.enabled;
    gp.liquid_on = liquid_on ? 1u : 0u;
    gp.dt = float(prm.dt);
    gp.h = float(h);
    gp.inv_h = float(inv_h);
    gp.omega = float(d.omega);
    for (int a = 0; a < 3; ++a) gp.gravity[a] = float(prm.gravity[a]);
    gp.skin = float(prm.skin);
    gp.cutoff_extra = float(cutoff_extra);
    gp.drum_r = float(d.radius);
    gp.hash_mask = hash_mask;

    drop_cache();
    B = std::make_unique<BufferSet>(ctx, n, cells);
    B->params.upload(&gp, sizeof(gp));
    gate.set(B->ctl.handle(), opt.profile_passes ? &prof : nullptr);
  }

  // ---- recording -----------------------------------------------------------------------------------
  Push push() const { return Push{B->table_buf.address(), 0, 0}; }

  void run(VkCommandBuffer cb, const char* name, uint32_t groups) {
    Push p = push();
    if (opt.profile_passes) prof.mark(cb, name);
    kernels.at(name)->dispatch(cb, groups, &p, sizeof(p));
    vk::barrier(cb);
  }
  void run_indirect(VkCommandBuffer cb, const char* name, uint32_t word) {
    Push p = push();
    if (opt.profile_passes) prof.mark(cb, name);
    kernels.at(name)->dispatch_indirect(cb, B->ctl.handle(), word * 4, &p, sizeof(p));
    vk::barrier(cb);
  }
  void gated(VkCommandBuffer cb, const char* name, uint32_t groups) {
    Push p = push();
    gate.dispatch(cb, *kernels.at(name), groups, &p, sizeof(p));
    vk::barrier(cb);
  }

  // Rebuild chain 6a-6k (ARCHITECTURE.md); every dispatch is gated by rebuild_decide.
  void record_rebuild(VkCommandBuffer cb) {
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
    gated(cb, "nbr_count", gN);
    scan->record(cb, gate, B->cnt_scan.address(), n, B->ctl.address() + ctlw::kEntriesNeeded * 4);
    gated(cb, "build_args", 1);
    record_list_tail(cb, false);
  }

  // 6g-6k: fill, mirror, history, lost check, flip. Direct dispatches when finishing a halted rebuild.
  void record_list_tail(VkCommandBuffer cb, bool direct) {
    const uint32_t gN = groups_for(n);
    if (direct)
      run(cb, "nbr_fill", gN);
    else
      gated(cb, "nbr_fill", gN);
    run_indirect(cb, "mirror", ctlw::kBuildArgs);
    run_indirect(cb, "history_map", ctlw::kBuildArgs);
    run_indirect(cb, "lost_check", ctlw::kLostArgs);
    if (direct)
      run(cb, "flip", 1);
    else
      gated(cb, "flip", 1);
  }

  void record_step(VkCommandBuffer cb) {
    const uint32_t gN = groups_for(n);
    run(cb, "kick_drift", gN);
    run_indirect(cb, "pair_force", ctlw::kEntryArgs);
    run(cb, "gather_kick", gN);
    if (gp.liquid_on) {
      run(cb, "liq_rupture_share", gN);
      run_indirect(cb, "liq_rupture_apply", ctlw::kEntryArgs);
      run(cb, "liq_form_offer", gN);
      run_indirect(cb, "liq_form_apply", ctlw::kEntryArgs);
      run(cb, "liq_form_take", gN);
    }
    run(cb, "rebuild_decide", 1);
    record_rebuild(cb);
    run(cb, "end_step", 1);
  }

  VkCommandBuffer allocate_cb() {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = ctx.pool();
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cb;
    WETDEM_VK(vkAllocateCommandBuffers(ctx.device(), &ai, &cb));
    return cb;
  }

  template <class Fn>
  VkCommandBuffer record(Fn&& fn) {
    VkCommandBuffer cb = allocate_cb();
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    WETDEM_VK(vkBeginCommandBuffer(cb, &bi));
    if (opt.profile_passes) prof.begin(cb);
    fn(cb);
    if (opt.profile_passes) prof.end(cb);
    WETDEM_VK(vkEndCommandBuffer(cb));
    // Gate sizes are known once recorded: publish them before the first submit.
    const auto& g = gate.groups();
    if (!g.empty()) B->ctl.upload(g.data(), g.size() * 4, ctlw::kGateGroups * 4);
    return cb;
  }

  void submit(VkCommandBuffer cb) {
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    WETDEM_VK(vkResetFences(ctx.device(), 1, &fence));
    prof.submitted(cb);
    WETDEM_VK(vkQueueSubmit(ctx.queue(), 1, &si, fence));
    WETDEM_VK(vkWaitForFences(ctx.device(), 1, &fence, VK_TRUE, UINT64_MAX));
    if (opt.profile_passes) prof.collect();
  }

  std::vector<uint32_t> read_ctl() { return B->ctl.download_as<uint32_t>(32); }

  // A rebuild halted on overflow: grow the set being built, finish the rebuild (and the step).
  void recover(const std::vector<uint32_t>& c, bool finish_step) {
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
      record_list_tail(r, true);
      if (finish_step) run(r, "end_step", 1);
    });
    submit(cb);
    vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &cb);
    auto after = read_ctl();
    if (after[ctlw::kHalt]) throw std::runtime_error("neighbour list overflowed again after growing");
  }

  void check_health(const std::vector<uint32_t>& c) {
    ctr.lost_bridges = c[ctlw::kLostBridges];
    ctr.escaped = c[ctlw::kEscaped];
    ctr.entries = c[ctlw::kEntries];
    ctr.entry_capacity = std::min(B->capacity(0), B->capacity(1));
    ctr.rebuilds += uint32_t(c[ctlw::kRebuilds] - last_rebuilds);
    last_rebuilds = c[ctlw::kRebuilds];
    events.formations += uint32_t(c[ctlw::kFormations] - last_form);
    events.ruptures += uint32_t(c[ctlw::kRuptures] - last_rupt);
    last_form = c[ctlw::kFormations];
    last_rupt = c[ctlw::kRuptures];
    if (c[ctlw::kMirrorErrors]) throw std::runtime_error("neighbour list is not symmetric (internal error)");
    if (c[ctlw::kLostBridges])
      throw std::runtime_error(fmt::format("{} liquid bridge(s) left the neighbour list without rupturing",
                                           c[ctlw::kLostBridges]));
  }

  void step(uint64_t count) {
    if (!uploaded) throw std::logic_error("System::step before upload");
    while (count > 0) {
      uint32_t k = uint32_t(std::min<uint64_t>(count, std::max<uint32_t>(1, opt.steps_per_submit)));
      VkCommandBuffer& cb = cached[k];
      if (!cb)
        cb = record([&](VkCommandBuffer r) {
          for (uint32_t s = 0; s < k; ++s) record_step(r);
        });
      submit(cb);
      auto c = read_ctl();
      if (c[ctlw::kHalt]) {
        recover(c, true);
        c = read_ctl();
      }
      uint32_t done = c[ctlw::kStepsDone] - last_steps_word;
      last_steps_word = c[ctlw::kStepsDone];
      check_health(c);
      steps += done;
      count -= std::min<uint64_t>(count, done);
      if (done == 0) throw std::runtime_error("GPU step made no progress");
    }
  }

  // ---- state transfer --------------------------------------------------------------------------------
  void upload(const SystemState& s) {
    if (s.p.size() != n)
      throw std::invalid_argument(fmt::format("upload: state has {} particles, system {}", s.p.size(), n));
    double r_max = 0.0, r_min = 1e300;
    for (double r : s.p.radius) {
      if (!(r > 0)) throw std::invalid_argument("upload: particle radius must be > 0");
      r_max = std::max(r_max, r);
      r_min = std::min(r_min, r);
    }
    setup(r_max, r_min);
    time0 = s.time;
    step0 = s.step;
    steps = 0;

    // Particles into set 0 in stable-id order.
    std::vector<int32_t> pos(4 * n);
    std::vector<float> frac(4 * size_t(n));
    std::vector<float> vel(4 * n), omg(4 * n), props(4 * n), frc(4 * n), trq(4 * n);
    std::vector<float> wst(12 * size_t(n)), wsr(12 * size_t(n));
    std::vector<int64_t> wliq(3 * size_t(n));
    std::vector<uint32_t> wfl(3 * size_t(n));
    const int64_t lim = int64_t(1) << 30;
    for (uint32_t k = 0; k < n; ++k) {
      for (int a = 0; a < 3; ++a) {
        const double xt = s.p.x[k][a] * inv_h;
        int64_t t = std::llround(xt);
        frac[4 * k + a] = float(xt - double(t));
        if (a == 2 && gp.period_ticks > 0) {
          int64_t P = gp.period_ticks, lo = -(P / 2);
          t = ((t - lo) % P + P) % P + lo;
        }
        if (t <= -lim || t >= lim)
          throw std::invalid_argument(fmt::format("upload: particle {} lies far outside the drum", k));
        pos[4 * k + a] = int32_t(t);
        vel[4 * k + a] = float(s.p.v[k][a]);
        omg[4 * k + a] = float(s.p.w[k][a]);
        frc[4 * k + a] = float(s.p.f[k][a]);
        trq[4 * k + a] = float(s.p.t[k][a]);
      }
      pos[4 * k + 3] = int32_t(k);
      props[4 * k + 0] = float(s.p.radius[k]);
      props[4 * k + 1] = float(s.p.mass[k]);
      props[4 * k + 2] = float(s.p.inertia[k]);
      // Radius in ticks, bit-cast into props.w: overlaps are formed from exact integers (pair_force.comp).
      const double rt = s.p.radius[k] * inv_h;
      const int32_t r_ticks = int32_t(std::llround(rt));
      std::memcpy(&props[4 * k + 3], &r_ticks, 4);
      frac[4 * k + 3] = float(rt - double(r_ticks));
      for (uint32_t w = 0; w < kNumWalls; ++w) {
        const WallRecord& r = s.p.wall[k * kNumWalls + w];
        size_t q = 3 * size_t(k) + w;
        for (int a = 0; a < 3; ++a) {
          wst[4 * q + a] = float(r.spring_t[a]);
          wsr[4 * q + a] = float(r.spring_r[a]);
        }
        wliq[q] = r.bridge;
        wfl[q] = r.flags & kFlagWasInContact;
      }
    }
    auto& P0 = B->pset[0];
    P0[gpu::kPos].upload(pos);
    P0[gpu::kFrac].upload(frac);
    P0[gpu::kVel].upload(vel);
    P0[gpu::kOmg].upload(omg);
    P0[gpu::kProps].upload(props);
    P0[gpu::kForce].upload(frc);
    P0[gpu::kTorque].upload(trq);
    P0[gpu::kFilm].upload(s.p.film);
    P0[gpu::kWallSt].upload(wst);
    P0[gpu::kWallSr].upload(wsr);
    P0[gpu::kWallLiq].upload(wliq);
    P0[gpu::kWallFlags].upload(wfl);

    // Pair records become the "old list" of set 0 (owner entries in the lower id's segment), so that the
    // regular history-mapping pass carries them into the first real list.
    std::vector<PairRecord> recs = s.pairs;
    std::sort(recs.begin(), recs.end(), [](const PairRecord& a, const PairRecord& b) {
      return std::tie(a.id_i, a.id_j) < std::tie(b.id_i, b.id_j);
    });
    const uint32_t E = uint32_t(recs.size());
    std::vector<uint32_t> cnt(n, 0), off(n, 0), nbr(E), self(E), mir(E), fl(E);
    std::vector<float> st(4 * size_t(E)), sr(4 * size_t(E));
    std::vector<int64_t> liq(E);
    for (uint32_t e = 0; e < E; ++e) {
      const PairRecord& r = recs[e];
      if (r.id_i >= r.id_j || r.id_j >= n)
        throw std::invalid_argument("upload: pair record needs id_i < id_j < N");
      cnt[r.id_i]++;
      nbr[e] = r.id_j;
      self[e] = r.id_i;
      mir[e] = e;
      for (int a = 0; a < 3; ++a) {
        st[4 * e + a] = float(r.spring_t[a]);
        sr[4 * e + a] = float(r.spring_r[a]);
      }
      liq[e] = r.bridge;
      fl[e] = r.flags & kFlagWasInContact;
    }
    for (uint32_t k = 1; k < n; ++k) off[k] = off[k - 1] + cnt[k - 1];
    const uint32_t guess = std::max<uint32_t>(E, n * std::max<uint32_t>(opt.initial_entries_per_particle, 1));
    B->grow_entries(0, guess);
    B->grow_entries(1, guess);
    P0[gpu::kNbrCount].upload(cnt);
    P0[gpu::kNbrOffset].upload(off);
    auto& E0 = B->eset[0];
    E0[gpu::kNbr].upload(nbr);
    E0[gpu::kSelf].upload(self);
    E0[gpu::kMirror].upload(mir);
    E0[gpu::kSt].upload(st);
    E0[gpu::kSr].upload(sr);
    E0[gpu::kLiq].upload(liq);
    E0[gpu::kFlags].upload(fl);
    B->upload_table();

    std::vector<uint32_t> c(ctlw::kWords, 0);
    c[ctlw::kForceRebuild] = 1;
    c[ctlw::kEntries] = E;
    c[ctlw::kEntryArgs] = groups_for(E);
    c[ctlw::kEntryArgs + 1] = c[ctlw::kEntryArgs + 2] = 1;
    c[ctlw::kCapacity0] = B->capacity(0);
    c[ctlw::kCapacity0 + 1] = B->capacity(1);
    B->ctl.upload(c);
    last_steps_word = last_form = last_rupt = last_rebuilds = 0;

    VkCommandBuffer cb = record([&](VkCommandBuffer r) {
      run(r, "rebuild_decide", 1);
      record_rebuild(r);
    });
    submit(cb);
    vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &cb);
    auto cc = read_ctl();
    if (cc[ctlw::kHalt]) {
      recover(cc, false);
      cc = read_ctl();
    }
    if (cc[ctlw::kLostBridges])
      throw std::invalid_argument(
          fmt::format("upload: {} pair record(s) with a bridge lie beyond the interaction range",
                      cc[ctlw::kLostBridges]));
    check_health(cc);
    ctr.rebuilds = 0;
    uploaded = true;
  }

  SystemState download() {
    auto c = read_ctl();
    const uint32_t s = c[ctlw::kParity], E = c[ctlw::kEntries];
    auto& P = B->pset[s];
    auto pos = P[gpu::kPos].download_as<int32_t>(4 * size_t(n));
    auto vel = P[gpu::kVel].download_as<float>(4 * size_t(n));
    auto omg = P[gpu::kOmg].download_as<float>(4 * size_t(n));
    auto props = P[gpu::kProps].download_as<float>(4 * size_t(n));
    auto frc = P[gpu::kForce].download_as<float>(4 * size_t(n));
    auto trq = P[gpu::kTorque].download_as<float>(4 * size_t(n));
    auto film = P[gpu::kFilm].download_as<int64_t>(n);
    auto frac = P[gpu::kFrac].download_as<float>(4 * size_t(n));
    auto wst = P[gpu::kWallSt].download_as<float>(12 * size_t(n));
    auto wsr = P[gpu::kWallSr].download_as<float>(12 * size_t(n));
    auto wliq = P[gpu::kWallLiq].download_as<int64_t>(3 * size_t(n));
    auto wfl = P[gpu::kWallFlags].download_as<uint32_t>(3 * size_t(n));
    SystemState out;
    out.p.resize(n);
    out.time = time0 + double(steps) * prm.dt;
    out.step = step0 + steps;
    std::vector<uint32_t> id(n);
    for (uint32_t k = 0; k < n; ++k) {
      uint32_t i = uint32_t(pos[4 * k + 3]);
      id[k] = i;
      for (int a = 0; a < 3; ++a) {
        out.p.x[i][a] = (double(pos[4 * k + a]) + double(frac[4 * k + a])) * h;
        out.p.v[i][a] = vel[4 * k + a];
        out.p.w[i][a] = omg[4 * k + a];
        out.p.f[i][a] = frc[4 * k + a];
        out.p.t[i][a] = trq[4 * k + a];
      }
      int32_t r_ticks;
      std::memcpy(&r_ticks, &props[4 * k + 3], 4);
      out.p.radius[i] = (double(r_ticks) + double(frac[4 * k + 3])) * h;
      out.p.mass[i] = props[4 * k + 1];
      out.p.inertia[i] = props[4 * k + 2];
      out.p.film[i] = film[k];
      for (uint32_t w = 0; w < kNumWalls; ++w) {
        size_t q = 3 * size_t(k) + w;
        WallRecord& r = out.p.wall[size_t(i) * kNumWalls + w];
        for (int a = 0; a < 3; ++a) {
          r.spring_t[a] = wst[4 * q + a];
          r.spring_r[a] = wsr[4 * q + a];
        }
        r.bridge = wliq[q];
        r.flags = wfl[q] & kFlagWasInContact;
      }
    }
    auto& Es = B->eset[s];
    auto nbr = Es[gpu::kNbr].download_as<uint32_t>(E);
    auto self = Es[gpu::kSelf].download_as<uint32_t>(E);
    auto mir = Es[gpu::kMirror].download_as<uint32_t>(E);
    auto st = Es[gpu::kSt].download_as<float>(4 * size_t(E));
    auto sr = Es[gpu::kSr].download_as<float>(4 * size_t(E));
    auto liq = Es[gpu::kLiq].download_as<int64_t>(E);
    auto fl = Es[gpu::kFlags].download_as<uint32_t>(E);
    for (uint32_t e = 0; e < E; ++e) {
      if (mir[e] != e) continue;
      PairRecord r;
      r.id_i = id[self[e]];
      r.id_j = id[nbr[e]];
      if (r.id_i > r.id_j)
        throw std::runtime_error("download: owner entry is not the lower id (internal error)");
      for (int a = 0; a < 3; ++a) {
        r.spring_t[a] = st[4 * e + a];
        r.spring_r[a] = sr[4 * e + a];
      }
      r.bridge = liq[e];
      r.flags = fl[e] & kFlagWasInContact;
      if (!r.empty()) out.pairs.push_back(r);
    }
    out.canonicalize();
    return out;
  }

  std::vector<std::pair<uint32_t, uint32_t>> neighbour_pairs() {
    auto c = read_ctl();
    const uint32_t s = c[ctlw::kParity], E = c[ctlw::kEntries];
    auto pos = B->pset[s][gpu::kPos].download_as<int32_t>(4 * size_t(n));
    auto nbr = B->eset[s][gpu::kNbr].download_as<uint32_t>(E);
    auto self = B->eset[s][gpu::kSelf].download_as<uint32_t>(E);
    auto mir = B->eset[s][gpu::kMirror].download_as<uint32_t>(E);
    std::vector<std::pair<uint32_t, uint32_t>> out;
    for (uint32_t e = 0; e < E; ++e) {
      uint32_t a = uint32_t(pos[4 * self[e] + 3]), b = uint32_t(pos[4 * nbr[e] + 3]);
      // Every pair appears twice (both segments): keep the owner's entry, check the mirror's link.
      if (mir[e] == e)
        out.emplace_back(std::min(a, b), std::max(a, b));
      else if (mir[e] >= E || self[mir[e]] != nbr[e] || nbr[mir[e]] != self[e])
        throw std::runtime_error("neighbour list: mirror entry does not point at its pair");
    }
    std::sort(out.begin(), out.end());
    return out;
  }

  // ---- snapshots -------------------------------------------------------------------------------------
  std::vector<uint8_t> snapshot();
  void restore(const std::vector<uint8_t>& blob);
};

namespace {
constexpr uint64_t kSnapMagic = 0x3130504E53444D57ull;  // "WMDSNP01"
struct SnapHeader {
  uint64_t magic;
  uint32_t n, parity, entries, pad;
  double time0;
  uint64_t step0, steps;
};
void put(std::vector<uint8_t>& out, const void* p, size_t bytes) {
  const uint8_t* b = static_cast<const uint8_t*>(p);
  out.insert(out.end(), b, b + bytes);
}
}  // namespace

// Snapshot = header + ctl + skin reference + every field of the current particle set + the current list.
// The other set is scratch that the next rebuild overwrites, so this is all the state a step reads.
std::vector<uint8_t> System::Impl::snapshot() {
  auto c = B->ctl.download_as<uint32_t>(ctlw::kWords);
  SnapHeader hd{kSnapMagic, n, c[ctlw::kParity], c[ctlw::kEntries], 0, time0, step0, steps};
  std::vector<uint8_t> out;
  put(out, &hd, sizeof(hd));
  put(out, c.data(), c.size() * 4);
  auto dl = [&](const vk::Buffer& b, size_t bytes) {
    size_t at = out.size();
    out.resize(at + bytes);
    b.download(out.data() + at, bytes);
  };
  dl(B->ref_pos, size_t(n) * 16);
  for (uint32_t f = 0; f < gpu::kNumParticleFields; ++f)
    dl(B->pset[hd.parity][f], size_t(n) * gpu::kParticleFieldBytes[f]);
  for (uint32_t f = 0; f < gpu::kNumEntryFields; ++f)
    dl(B->eset[hd.parity][f], size_t(hd.entries) * gpu::kEntryFieldBytes[f]);
  return out;
}

void System::Impl::restore(const std::vector<uint8_t>& blob) {
  SnapHeader hd;
  if (blob.size() < sizeof(hd)) throw std::invalid_argument("restore: snapshot too short");
  std::memcpy(&hd, blob.data(), sizeof(hd));
  if (hd.magic != kSnapMagic) throw std::invalid_argument("restore: not a wetdem snapshot");
  if (hd.n != n)
    throw std::invalid_argument(fmt::format("restore: snapshot has {} particles, system {}", hd.n, n));
  size_t need = sizeof(hd) + ctlw::kWords * 4 + size_t(n) * 16;
  for (uint32_t f = 0; f < gpu::kNumParticleFields; ++f) need += size_t(n) * gpu::kParticleFieldBytes[f];
  for (uint32_t f = 0; f < gpu::kNumEntryFields; ++f) need += size_t(hd.entries) * gpu::kEntryFieldBytes[f];
  if (blob.size() != need) throw std::invalid_argument("restore: snapshot size does not match its header");
  const uint8_t* at = blob.data() + sizeof(hd);
  std::vector<uint32_t> c(ctlw::kWords);
  std::memcpy(c.data(), at, c.size() * 4);
  at += c.size() * 4;
  const uint8_t* ref = at;
  at += size_t(n) * 16;
  // Radii (props.x of the current set) fix the cell grid, exactly as the original upload did.
  const uint8_t* props = at;
  for (uint32_t f = 0; f < gpu::kProps; ++f) props += size_t(n) * gpu::kParticleFieldBytes[f];
  double r_max = 0.0, r_min = 1e300;
  for (uint32_t k = 0; k < n; ++k) {
    float r;
    std::memcpy(&r, props + size_t(k) * 16, 4);
    r_max = std::max(r_max, double(r));
    r_min = std::min(r_min, double(r));
  }
  setup(r_max, r_min);
  const uint32_t s = hd.parity;
  B->grow_entries(s, std::max<uint32_t>(c[ctlw::kCapacity0 + s], hd.entries));
  B->grow_entries(1 - s, std::max<uint32_t>(c[ctlw::kCapacity0 + 1 - s], 1));
  c[ctlw::kCapacity0] = B->capacity(0);
  c[ctlw::kCapacity0 + 1] = B->capacity(1);
  B->upload_table();
  B->ref_pos.upload(ref, size_t(n) * 16);
  for (uint32_t f = 0; f < gpu::kNumParticleFields; ++f) {
    size_t bytes = size_t(n) * gpu::kParticleFieldBytes[f];
    B->pset[s][f].upload(at, bytes);
    at += bytes;
  }
  for (uint32_t f = 0; f < gpu::kNumEntryFields; ++f) {
    size_t bytes = size_t(hd.entries) * gpu::kEntryFieldBytes[f];
    B->eset[s][f].upload(at, bytes);
    at += bytes;
  }
  B->ctl.upload(c);
  time0 = hd.time0;
  step0 = hd.step0;
  steps = hd.steps;
  last_steps_word = c[ctlw::kStepsDone];
  last_form = c[ctlw::kFormations];
  last_rupt = c[ctlw::kRuptures];
  last_rebuilds = c[ctlw::kRebuilds];
  uploaded = true;
}

System::System(vk::Context& ctx, const SimParams& prm, size_t num_particles, SystemOptions opt)
    : impl_(std::make_unique<Impl>(ctx, prm, num_particles, opt)) {}
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
