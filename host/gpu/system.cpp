// The GPU system: parameter upload, the recording of a step's passes (ARCHITECTURE.md "Passes of a step")
// and the submit loop with overflow recovery. State transfer and snapshots: system_state.cpp.
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
  const char* names[] = {
      "kick_drift",     "pair_force",       "gather_kick",   "liq_rupture_share", "liq_rupture_apply",
      "liq_form_offer", "liq_form_apply",   "liq_form_take", "rebuild_decide",    "cell_key",
      "reorder",        "fill_u32",         "cell_ranges",   "nbr_count",         "build_args",
      "nbr_fill",       "mirror",           "history_map",   "lost_check",        "flip",
      "end_step",       "liq_upload_flags", "owner_count",   "owner_fill"};
  for (const char* nm : names) kernels[nm] = std::make_unique<vk::Kernel>(ctx, nm);
  sort = std::make_unique<gpu::RadixSort>(ctx, n);
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
}

namespace {

// The physics of one run (what an ensemble's runs may differ in): contact laws, liquid, candidate effects,
// drum speed, gravity, liquid sinks. setup() adds what every run shares.
gpu::GpuParams physics_block(const SimParams& q) {
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
  auto liquid = [](const LiquidParams& l, double range, double unit_m3) {
    gpu::GpuLiquid g{};
    const double pi = 3.14159265358979323846;
    g.v_min = l.v_min;
    g.v_max = l.v_max;
    g.f0_per_Rh = float(2.0 * pi * l.gamma * std::cos(l.theta));
    g.rupture_coef = float(1.0 + 0.5 * l.theta_r());  // hysteresis: rupture at the receding angle
    g.unit_m3 = float(unit_m3);
    g.range = float(range);
    g.enabled = l.enabled ? 1u : 0u;
    g.dc_q16 = uint32_t(std::lround(std::clamp(l.d_c, 0.0, 1.0) * 65536.0));
    return g;
  };
  auto effects = [](const ContactParams& c, const LiquidParams& l) {
    gpu::GpuEffects g{};
    const double pi = 3.14159265358979323846;
    g.visc_eta = float(l.viscosity);
    g.visc_smin = float(l.lubrication_cutoff);
    g.f0r_per_Rh = float(2.0 * pi * l.gamma * std::cos(l.theta_r()));
    g.adhesion = float(1.5 * pi * c.surface_energy);
    return g;
  };
  gpu::GpuParams g{};
  g.pp = contact(q.pp);
  g.fx[0] = effects(q.pp, q.liq_pp);
  for (uint32_t w = 0; w < kNumWalls; ++w) g.fx[1 + w] = effects(q.pw[w], q.liq_pw[w]);
  g.lpp = liquid(q.liq_pp, q.bridge_range_pp(), q.liquid_unit_m3);
  for (uint32_t w = 0; w < kNumWalls; ++w) {
    g.pw[w] = contact(q.pw[w]);
    g.lpw[w] = liquid(q.liq_pw[w], q.bridge_range_pw(w), q.liquid_unit_m3);
  }
  g.plate_rotates[0] = q.drum.plate_lo.rotates ? 1u : 0u;
  g.plate_rotates[1] = q.drum.plate_hi.rotates ? 1u : 0u;
  bool wet = q.liq_pp.enabled;
  for (auto& l : q.liq_pw) wet = wet || l.enabled;
  // The sinks live in the liquid passes (4c): they run every step when either is on, bridges or not.
  const LiquidSinkParams& sk = q.sinks;
  if (sk.absorbs()) {
    g.absorb_mode = std::isinf(sk.absorption_rate) ? 2u : 1u;
    const uint64_t a = loss_fraction_q64(sk.absorption_rate * q.dt);
    g.absorb_q64[0] = uint32_t(a);
    g.absorb_q64[1] = uint32_t(a >> 32);
  }
  if (sk.evaporates()) {
    g.evap_on = 1u;
    const uint64_t e = loss_fraction_q64(q.dt / sk.evaporation_time);
    g.evap_q64[0] = uint32_t(e);
    g.evap_q64[1] = uint32_t(e >> 32);
  }
  g.liquid_on = (wet || g.absorb_mode != 0u || g.evap_on != 0u) ? 1u : 0u;
  g.omega = float(q.drum.omega);
  for (int a = 0; a < 3; ++a) g.gravity[a] = float(q.gravity[a]);
  return g;
}

}  // namespace

uint32_t System::Impl::run_of(uint32_t id) const {
  return uint32_t(std::upper_bound(run_off.begin(), run_off.end(), id) - run_off.begin()) - 1u;
}

void System::Impl::setup(double r_max, double r_min) {
  setup_r_max = r_max;
  setup_r_min = r_min;
  // The list must hold every pair that can touch at the next force evaluation, so a skin of zero is
  // not usable: 0 selects 0.1 r_min (a rebuild every few steps at drum speeds).
  for (size_t r = 0; r < run_prm.size(); ++r) {
    SimParams& q = run_prm[r];
    if (q.skin <= 0.0) q.skin = 0.1 * r_min;
    const DrumParams& d = q.drum;
    if (!(d.radius > 0) || !(d.length > 0))
      throw std::invalid_argument("drum: radius and length must be > 0");
    if (!(q.dt > 0)) throw std::invalid_argument("dt must be > 0");
    for (const LiquidParams* l : {&q.liq_pp, &q.liq_pw[0], &q.liq_pw[1], &q.liq_pw[2]})
      if (l->viscosity > 0 && !(l->lubrication_cutoff > 0))
        throw std::invalid_argument(
            "liquid: viscosity > 0 needs lubrication_cutoff > 0 (S = max(gap, S_min))");
    // Runs stepped together share the clock, the position ticks (set by the drum's size) and the cell grid.
    const SimParams& z = run_prm[0];
    auto same = [&](bool eq, const char* key) {
      if (!eq)
        throw std::invalid_argument(fmt::format(
            "ensemble: run {} has another {} than run 0; runs stepped together must share it", r, key));
    };
    same(q.dt == z.dt, "dt");
    same(d.radius == z.drum.radius, "drum.radius");
    same(d.length == z.drum.length, "drum.length");
    same(d.periodic_z == z.drum.periodic_z, "drum periodicity");
    same(d.plate_lo.present == z.drum.plate_lo.present && d.plate_hi.present == z.drum.plate_hi.present,
         "set of end plates");
  }
  prm = run_prm[0];
  // One list and one rebuild schedule for all runs: the thinnest skin decides the rebuilds, the widest
  // bridge range the list. Segments are in a canonical order (nbr_fill.comp), so a run's result does not
  // depend on either: extra pairs add exact zeros, extra rebuilds change nothing.
  double skin = prm.skin, range_pp = prm.bridge_range_pp();
  for (const SimParams& q : run_prm) {
    skin = std::min(skin, q.skin);
    range_pp = std::max(range_pp, q.bridge_range_pp());
  }
  const DrumParams& d = prm.drum;
  const double cutoff_extra = range_pp + skin;
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
  const uint64_t n_run = run_off[1] - run_off[0];  // the grid choice of one run (the largest one's below)
  uint64_t largest = n_run;
  for (size_t r = 1; r + 1 < run_off.size(); ++r)
    largest = std::max<uint64_t>(largest, run_off[r + 1] - run_off[r]);
  uint64_t ncells = uint64_t(dims[0]) * dims[1] * dims[2];
  uint32_t hash_mask = 0;
  // A domain much larger than the particles (a test box, a sparse gas) would need a huge dense grid:
  // hash the cells into a power-of-two table instead (cell order then no longer follows space).
  if (ncells > std::max<uint64_t>(8ull * largest, 1u << 16)) {
    uint64_t buckets = 1024;
    while (buckets < 2ull * largest) buckets *= 2;
    hash_mask = uint32_t(buckets - 1);
    ncells = buckets;
    origin[0] = origin[1] = -(1 << 30);
    if (!d.periodic_z) origin[2] = -(1 << 30);
  }
  const uint64_t all_cells = ncells * run_prm.size();
  if (all_cells >= (1ull << 32)) throw std::invalid_argument("ensemble: too many cells for 32-bit cell keys");
  cells = uint32_t(all_cells);
  key_bits = 1;
  while ((1ull << key_bits) < all_cells) ++key_bits;

  // What every run shares.
  shared = {};
  const int64_t r_ticks = std::llround(d.radius * inv_h);
  shared.drum_r_ticks = int32_t(r_ticks);
  shared.drum_r_frac = float(d.radius * inv_h - double(r_ticks));
  shared.drum_r2_ticks = r_ticks * r_ticks;
  shared.plate_z_ticks = int32_t(std::llround(0.5 * d.length * inv_h));
  shared.period_ticks = int32_t(period);
  shared.cell_ticks = int32_t(cell_ticks);
  for (int a = 0; a < 3; ++a) {
    shared.grid_origin[a] = origin[a];
    shared.grid_dims[a] = dims[a];
  }
  shared.plate_present[0] = d.plate_lo.present ? 1u : 0u;
  shared.plate_present[1] = d.plate_hi.present ? 1u : 0u;
  shared.num_particles = n;
  shared.dt = float(prm.dt);
  shared.h = float(h);
  shared.inv_h = float(inv_h);
  shared.skin = float(skin);
  shared.cutoff_extra = float(cutoff_extra);
  shared.drum_r = float(d.radius);
  shared.hash_mask = hash_mask;
  shared.runs = uint32_t(run_prm.size());
  shared.run_stride = uint32_t(sizeof(gpu::GpuParams));
  shared.cells_per_run = uint32_t(ncells);
  shared_skin = skin;
  shared_range = range_pp;
  build_params();

  drop_cache();
  B = std::make_unique<BufferSet>(ctx, n, cells, uint32_t(run_prm.size()));
  B->params.upload(gps.data(), gps.size() * sizeof(gpu::GpuParams));
  if (run_prm.size() > 1) {
    std::vector<uint32_t> run(n);
    for (uint32_t id = 0; id < n; ++id) run[id] = run_of(id);
    B->run_of.upload(run);
  }
  gate.set(B->ctl.handle(), opt.profile_passes ? &prof : nullptr);
}

void System::Impl::build_params() {
  gps.clear();
  uint32_t liquid_on = 0u;
  for (const SimParams& q : run_prm) {
    gpu::GpuParams g = physics_block(q);
    liquid_on |= g.liquid_on;
    g.drum_r2_ticks = shared.drum_r2_ticks;
    g.drum_r_ticks = shared.drum_r_ticks;
    g.plate_z_ticks = shared.plate_z_ticks;
    g.period_ticks = shared.period_ticks;
    g.cell_ticks = shared.cell_ticks;
    for (int a = 0; a < 3; ++a) {
      g.grid_origin[a] = shared.grid_origin[a];
      g.grid_dims[a] = shared.grid_dims[a];
    }
    g.plate_present[0] = shared.plate_present[0];
    g.plate_present[1] = shared.plate_present[1];
    g.num_particles = shared.num_particles;
    g.dt = shared.dt;
    g.h = shared.h;
    g.inv_h = shared.inv_h;
    g.skin = shared.skin;
    g.cutoff_extra = shared.cutoff_extra;
    g.drum_r = shared.drum_r;
    g.drum_r_frac = shared.drum_r_frac;
    g.hash_mask = shared.hash_mask;
    g.runs = shared.runs;
    g.run_stride = shared.run_stride;
    g.cells_per_run = shared.cells_per_run;
    gps.push_back(g);
  }
  // The liquid passes run when any run needs them (for a dry run they change nothing).
  for (gpu::GpuParams& g : gps) g.liquid_on = liquid_on;
  gp = gps[0];
}

void System::Impl::set_run_params(size_t r, const SimParams& p) {
  if (r >= run_prm.size()) throw std::invalid_argument(fmt::format("set_run_params: no run {}", r));
  if (!uploaded) throw std::logic_error("System::set_run_params before upload");
  SimParams q = p;
  if (q.skin <= 0.0) q.skin = run_prm[r].skin;
  const SimParams& z = run_prm[r];
  auto same = [&](bool eq, const char* key) {
    if (!eq)
      throw std::invalid_argument(
          fmt::format("set_run_params: run {}: {} cannot change in a System", r, key));
  };
  same(q.dt == z.dt, "dt");
  same(q.drum.radius == z.drum.radius && q.drum.length == z.drum.length, "the drum's size");
  same(q.drum.periodic_z == z.drum.periodic_z, "the drum's periodicity");
  same(q.drum.plate_lo.present == z.drum.plate_lo.present &&
           q.drum.plate_hi.present == z.drum.plate_hi.present,
       "the set of end plates");
  same(q.skin >= shared_skin, "the skin (thinner than the rebuild schedule's)");
  same(q.bridge_range_pp() <= shared_range, "the bridge range (wider than the list's)");
  run_prm[r] = q;
  if (r == 0) prm = q;
  build_params();
  drop_cache();  // the liquid passes may now run or not
  B->params.upload(gps.data(), gps.size() * sizeof(gpu::GpuParams));
}

void System::Impl::run(VkCommandBuffer cb, const char* name, uint32_t groups) {
  Push p = push();
  if (opt.profile_passes) prof.mark(cb, name);
  kernels.at(name)->dispatch(cb, groups, &p, sizeof(p));
  vk::barrier(cb);
}

void System::Impl::run_indirect(VkCommandBuffer cb, const char* name, uint32_t word) {
  Push p = push();
  if (opt.profile_passes) prof.mark(cb, name);
  kernels.at(name)->dispatch_indirect(cb, B->ctl.handle(), word * 4, &p, sizeof(p));
  vk::barrier(cb);
}

void System::Impl::gated(VkCommandBuffer cb, const char* name, uint32_t groups) {
  Push p = push();
  gate.dispatch(cb, *kernels.at(name), groups, &p, sizeof(p));
  vk::barrier(cb);
}

// Rebuild chain 6a-6n (ARCHITECTURE.md); every dispatch is gated by rebuild_decide.
void System::Impl::record_rebuild(VkCommandBuffer cb) {
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

// 6g-6n: fill, mirror, history, lost check, owner list, flip. Direct dispatches when finishing a halted
// rebuild.
void System::Impl::record_list_tail(VkCommandBuffer cb, bool direct) {
  const uint32_t gN = groups_for(n);
  if (direct)
    run(cb, "nbr_fill", gN);
  else
    gated(cb, "nbr_fill", gN);
  run_indirect(cb, "mirror", ctlw::kBuildArgs);
  run_indirect(cb, "history_map", ctlw::kBuildArgs);
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
    run(cb, "flip", 1);
  } else {
    gated(cb, "owner_fill", gN);
    gated(cb, "flip", 1);
  }
}

void System::Impl::record_step(VkCommandBuffer cb, bool split) {
  const uint32_t gN = groups_for(n);
  run(cb, "kick_drift", gN);
  run_indirect(cb, "pair_force", ctlw::kOwnerArgs);
  run(cb, "gather_kick", gN);
  if (gp.liquid_on) {
    run(cb, "liq_rupture_share", gN);
    run_indirect(cb, "liq_rupture_apply", ctlw::kOwnerArgs);
    run(cb, "liq_form_offer", gN);
    run_indirect(cb, "liq_form_apply", ctlw::kOwnerArgs);
    run(cb, "liq_form_take", gN);
  }
  if (split) {
    // Ends the step, or halts it (and the rest of the command buffer) when it must rebuild; see step().
    gpu::Push p = push();
    p.a0 = 1;
    if (opt.profile_passes) prof.mark(cb, "rebuild_decide");
    kernels.at("rebuild_decide")->dispatch(cb, 1, &p, sizeof(p));
    vk::barrier(cb);
    return;
  }
  run(cb, "rebuild_decide", 1);
  record_rebuild(cb);
  run(cb, "end_step", 1);
}

// Split rebuilds: steps per submit. A batch that ends before the next rebuild costs a host round trip; one
// that halts early costs its remaining steps, each a few empty dispatches. On the H100 (README "GPU") a round
// trip cost about as much as 20 halted steps, so a batch runs past the estimated next rebuild by half an
// interval; if none came, shorter batches follow. One command buffer is recorded per batch length.
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
    record_list_tail(r, true);
    if (finish_step) run(r, "end_step", 1);
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
        for (auto& [len, old] : *m) vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &old);
        m->clear();
      }
    VkCommandBuffer& cb = split ? plain[k] : cached[k];
    if (!cb)
      cb = record([&](VkCommandBuffer r) {
        for (uint32_t s = 0; s < k; ++s) record_step(r, split);
      });
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
          record_rebuild(r);
          run(r, "end_step", 1);
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
