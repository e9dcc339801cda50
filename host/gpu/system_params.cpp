// The GPU system's parameters (ARCHITECTURE.md "Ensembles"): the cell grid and position ticks (setup), one
// parameter block per run, its physics on top of what every run shares, and a run's physics replaced between
// steps.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gpu/system_impl.h"

namespace wetdem {

namespace {

// The physics of one run (what an ensemble's runs may differ in): contact laws, liquid, candidate effects,
// drum speed, gravity, liquid sinks, on top of `shared`, the block of what every run shares (setup()).
gpu::GpuParams physics_block(const SimParams& q, const gpu::GpuParams& shared) {
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
  gpu::GpuParams g = shared;
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

uint32_t System::Impl::drum_wall_slots() const {
  const DrumParams& d = prm.drum;
  return 1u + (d.periodic_z ? 0u : uint32_t(d.plate_lo.present) + uint32_t(d.plate_hi.present));
}

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
  shared.wall_slots = drum_wall_slots();
  const bool present[3] = {true, !d.periodic_z && d.plate_lo.present, !d.periodic_z && d.plate_hi.present};
  for (int w = 0, k = 0; w < 3; ++w) wall_slot[w] = present[w] ? k++ : -1;
  shared_skin = skin;
  shared_range = range_pp;
  build_params();

  drop_cache();
  B = std::make_unique<BufferSet>(ctx, n, cells, uint32_t(run_prm.size()), shared.wall_slots, !fused);
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
    const gpu::GpuParams g = physics_block(q, shared);
    liquid_on |= g.liquid_on;
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

}  // namespace wetdem
