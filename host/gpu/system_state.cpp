// The GPU system's state transfer: upload (host state -> device sets, pair records as the "old list" that the
// history map carries over), download (device -> canonical host state), the neighbour list for tests, and
// raw snapshots for bitwise restarts.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <tuple>

#include "gpu/system_impl.h"

namespace wetdem {

using gpu::groups_for;

namespace {
// Two vec3 a, b of element k stored split as (a, b.x) in a 16-byte word and (b.y, b.z) in an 8-byte word
// (force and torque; an entry's springs: buffer_set.h).
struct Split {
  std::vector<float> w4, w2;
  explicit Split(size_t count) : w4(4 * count), w2(2 * count) {}
  Split(std::vector<float> four, std::vector<float> two) : w4(std::move(four)), w2(std::move(two)) {}
  float& a(size_t k, int c) { return w4[4 * k + c]; }
  float& b(size_t k, int c) { return c == 0 ? w4[4 * k + 3] : w2[2 * k + c - 1]; }
};
}  // namespace

void System::Impl::upload(const SystemState& s) {
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
  std::vector<float> vel(4 * n), omg(4 * n), props(4 * n);
  Split ft(n);  // force, torque
  // One wall record per wall the drum has (buffer_set.h): the slot of wall w is its rank among them.
  const uint32_t ns = B->wall_slots;
  std::vector<float> wst(4 * size_t(ns) * n), wsr(4 * size_t(ns) * n);
  std::vector<int64_t> wliq(size_t(ns) * n);
  std::vector<uint32_t> wfl(size_t(ns) * n);
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
      ft.a(k, a) = float(s.p.f[k][a]);
      ft.b(k, a) = float(s.p.t[k][a]);
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
      if (wall_slot[w] < 0) {
        if (r.bridge != 0)
          throw std::invalid_argument(fmt::format(
              "upload: particle {} holds a bridge to wall {}, which this drum does not have", k, w));
        continue;
      }
      size_t q = size_t(ns) * k + size_t(wall_slot[w]);
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
  P0[gpu::kForce].upload(ft.w4);
  P0[gpu::kTorque].upload(ft.w2);
  P0[gpu::kFilm].upload(s.p.film);
  P0[gpu::kWallSt].upload(wst);
  P0[gpu::kWallSr].upload(wsr);
  P0[gpu::kWallLiq].upload(wliq);
  P0[gpu::kWallFlags].upload(wfl);
  // Pore store and evaporated counter (zero when the state has none); capacity from the radius (params.h).
  std::vector<int64_t> pore(n, 0), evap(n, 0), pcap(n, 0);
  for (uint32_t k = 0; k < n; ++k) {
    if (k < s.p.pore.size()) pore[k] = s.p.pore[k];
    if (k < s.p.evaporated.size()) evap[k] = s.p.evaporated[k];
    const SimParams& q = run_prm[run_of(k)];
    pcap[k] = pore_capacity_units(q.sinks.pore_capacity, s.p.radius[k], q.liquid_unit_m3);
  }
  P0[gpu::kPore].upload(pore);
  P0[gpu::kEvap].upload(evap);
  P0[gpu::kPoreCap].upload(pcap);

  // Pair records become the "old list" of set 0 (owner entries in the lower id's segment), so that the
  // regular history-mapping pass carries them into the first real list.
  std::vector<PairRecord> recs = s.pairs;
  std::sort(recs.begin(), recs.end(), [](const PairRecord& a, const PairRecord& b) {
    return std::tie(a.id_i, a.id_j) < std::tie(b.id_i, b.id_j);
  });
  const uint32_t E = uint32_t(recs.size());
  std::vector<uint32_t> cnt(n, 0), off(n, 0), nbr(E), self(E), mir(E), fl(E);
  Split sp(E);  // springs: tangential, rolling
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
      sp.a(e, a) = float(r.spring_t[a]);
      sp.b(e, a) = float(r.spring_r[a]);
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
  E0[gpu::kSt].upload(sp.w4);
  E0[gpu::kSr].upload(sp.w2);
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
  c[ctlw::kStepArgs] = groups_for(n);
  c[ctlw::kStepArgs + 1] = c[ctlw::kStepArgs + 2] = 1;
  c[ctlw::kSkinRule] = skin_rule();
  B->ctl.upload(c);
  last_steps_word = last_form = last_rupt = last_rebuilds = 0;

  VkCommandBuffer cb = record([&](VkCommandBuffer r) {
    run(r, "rebuild_decide", 1);
    record_rebuild(r, false);
  });
  submit(cb);
  vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &cb);
  auto cc = read_ctl();
  if (cc[ctlw::kHalt]) {
    recover(cc, false);
    cc = read_ctl();
  }
  if (cc[ctlw::kLostBridges])
    throw std::invalid_argument(fmt::format(
        "upload: {} pair record(s) with a bridge lie beyond the interaction range", cc[ctlw::kLostBridges]));
  check_health(cc);
  if (gp.liquid_on) {
    // §5 events of the uploaded positions (issue 12): touching pairs without a bridge or flag form their
    // bridges now, as MercuryDPM's initialiseSolve does, rather than after a separation and a new touch.
    const uint32_t gN = groups_for(n);
    // The liquid sinks act per step (over dt), not at upload: switched off for these events.
    std::vector<gpu::GpuParams> at_rest = gps;
    for (gpu::GpuParams& g : at_rest) g.absorb_mode = g.evap_on = 0u;
    B->params.upload(at_rest.data(), at_rest.size() * sizeof(gpu::GpuParams));
    // The integers of the step's own liquid passes: with integer atomics (the fused step's, no event slots)
    // or through the event slots and 4e.
    const uint32_t atomic = fused ? gpu::mode::kAtomic : 0u;
    VkCommandBuffer lb = record([&](VkCommandBuffer r) {
      run(r, "liq_upload_flags", gN);
      run(r, "liq_rupture_share", gN);
      run_indirect(r, "liq_rupture_apply", ctlw::kOwnerArgs, atomic);
      run(r, "liq_form_offer", gN, atomic);
      run_indirect(r, "liq_form_apply", ctlw::kOwnerArgs, atomic);
      if (!fused) run(r, "liq_form_take", gN);
    });
    submit(lb);
    vkFreeCommandBuffers(ctx.device(), ctx.pool(), 1, &lb);
    B->params.upload(gps.data(), gps.size() * sizeof(gpu::GpuParams));
    check_health(read_ctl());
  }
  ctr.rebuilds = 0;
  uploaded = true;
}

SystemState System::Impl::download() {
  auto c = read_ctl();
  const uint32_t s = c[ctlw::kParity], E = c[ctlw::kEntries];
  auto& P = B->pset[s];
  auto pos = P[gpu::kPos].download_as<int32_t>(4 * size_t(n));
  auto vel = P[gpu::kVel].download_as<float>(4 * size_t(n));
  auto omg = P[gpu::kOmg].download_as<float>(4 * size_t(n));
  auto props = P[gpu::kProps].download_as<float>(4 * size_t(n));
  Split ft(P[gpu::kForce].download_as<float>(4 * size_t(n)),
           P[gpu::kTorque].download_as<float>(2 * size_t(n)));
  auto film = P[gpu::kFilm].download_as<int64_t>(n);
  auto frac = P[gpu::kFrac].download_as<float>(4 * size_t(n));
  const uint32_t ns = B->wall_slots;
  auto wst = P[gpu::kWallSt].download_as<float>(4 * size_t(ns) * n);
  auto wsr = P[gpu::kWallSr].download_as<float>(4 * size_t(ns) * n);
  auto wliq = P[gpu::kWallLiq].download_as<int64_t>(size_t(ns) * n);
  auto wfl = P[gpu::kWallFlags].download_as<uint32_t>(size_t(ns) * n);
  auto pore = P[gpu::kPore].download_as<int64_t>(n);
  auto evap = P[gpu::kEvap].download_as<int64_t>(n);
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
      out.p.f[i][a] = ft.a(k, a);
      out.p.t[i][a] = ft.b(k, a);
    }
    int32_t r_ticks;
    std::memcpy(&r_ticks, &props[4 * k + 3], 4);
    out.p.radius[i] = (double(r_ticks) + double(frac[4 * k + 3])) * h;
    out.p.mass[i] = props[4 * k + 1];
    out.p.inertia[i] = props[4 * k + 2];
    out.p.film[i] = film[k];
    out.p.pore[i] = pore[k];
    out.p.evaporated[i] = evap[k];
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      if (wall_slot[w] < 0) continue;  // a wall the drum does not have: an empty record
      size_t q = size_t(ns) * k + size_t(wall_slot[w]);
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
  Split sp(Es[gpu::kSt].download_as<float>(4 * size_t(E)), Es[gpu::kSr].download_as<float>(2 * size_t(E)));
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
      r.spring_t[a] = sp.a(e, a);
      r.spring_r[a] = sp.b(e, a);
    }
    r.bridge = liq[e];
    r.flags = fl[e] & kFlagWasInContact;
    if (!r.empty()) out.pairs.push_back(r);
  }
  out.canonicalize();
  return out;
}

std::vector<std::pair<uint32_t, uint32_t>> System::Impl::neighbour_pairs() {
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

namespace {
// "WMDSNP06": 03 (02 + the radii the cell grid was sized from) with the control words of the fused step, wall
// records for the walls the drum has, and force and torque, and the pair springs, as (a, b.x) and (b.y, b.z)
// words (05: packed vec3 each).
constexpr uint64_t kSnapMagic = 0x3630504E53444D57ull;
constexpr uint64_t kSnapMagicOld[] = {0x3230504E53444D57ull, 0x3330504E53444D57ull, 0x3430504E53444D57ull,
                                      0x3530504E53444D57ull};  // 02, 03, 04, 05
struct SnapHeader {
  uint64_t magic;
  uint32_t n, parity, entries, pad;
  double time0;
  uint64_t step0, steps;
  // setup()'s inputs, exactly: the grid origin and cell size follow from them, and a grid shifted by one tick
  // bins a particle within a tick of a cell face differently, a rare event that a resumed run then diverges
  // at (seen on the H100 a thousand steps after a resume, when the grid came from the float32 radii).
  double setup_r_max, setup_r_min;
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
  SnapHeader hd{kSnapMagic, n,     c[ctlw::kParity], c[ctlw::kEntries], 0, time0,
                step0,      steps, setup_r_max,      setup_r_min};
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
    dl(B->pset[hd.parity][f], size_t(n) * gpu::particle_field_bytes(f, B->wall_slots));
  for (uint32_t f = 0; f < gpu::kNumEntryFields; ++f)
    dl(B->eset[hd.parity][f], size_t(hd.entries) * gpu::kEntryFieldBytes[f]);
  return out;
}

void System::Impl::restore(const std::vector<uint8_t>& blob) {
  SnapHeader hd;
  if (blob.size() < sizeof(hd)) throw std::invalid_argument("restore: snapshot too short");
  std::memcpy(&hd, blob.data(), sizeof(hd));
  for (uint64_t old : kSnapMagicOld)
    if (hd.magic == old)
      throw std::invalid_argument(
          fmt::format("restore: a snapshot of an older wetdem (WMDSNP0{}); start the run afresh",
                      char((old >> 56) & 0xFF)));
  if (hd.magic != kSnapMagic) throw std::invalid_argument("restore: not a wetdem snapshot");
  if (hd.n != n)
    throw std::invalid_argument(fmt::format("restore: snapshot has {} particles, system {}", hd.n, n));
  size_t need = sizeof(hd) + ctlw::kWords * 4 + size_t(n) * 16;
  for (uint32_t f = 0; f < gpu::kNumParticleFields; ++f)
    need += size_t(n) * gpu::particle_field_bytes(f, drum_wall_slots());
  for (uint32_t f = 0; f < gpu::kNumEntryFields; ++f) need += size_t(hd.entries) * gpu::kEntryFieldBytes[f];
  if (blob.size() != need) throw std::invalid_argument("restore: snapshot size does not match its header");
  const uint8_t* at = blob.data() + sizeof(hd);
  std::vector<uint32_t> c(ctlw::kWords);
  std::memcpy(c.data(), at, c.size() * 4);
  at += c.size() * 4;
  const uint8_t* ref = at;
  at += size_t(n) * 16;
  setup(hd.setup_r_max, hd.setup_r_min);
  const uint32_t s = hd.parity;
  B->grow_entries(s, std::max<uint32_t>(c[ctlw::kCapacity0 + s], hd.entries));
  B->grow_entries(1 - s, std::max<uint32_t>(c[ctlw::kCapacity0 + 1 - s], 1));
  c[ctlw::kCapacity0] = B->capacity(0);
  c[ctlw::kCapacity0 + 1] = B->capacity(1);
  B->upload_table();
  B->ref_pos.upload(ref, size_t(n) * 16);
  for (uint32_t f = 0; f < gpu::kNumParticleFields; ++f) {
    size_t bytes = size_t(n) * gpu::particle_field_bytes(f, B->wall_slots);
    B->pset[s][f].upload(at, bytes);
    at += bytes;
  }
  const uint8_t* mirror = nullptr;
  for (uint32_t f = 0; f < gpu::kNumEntryFields; ++f) {
    size_t bytes = size_t(hd.entries) * gpu::kEntryFieldBytes[f];
    if (f == gpu::kMirror) mirror = at;
    B->eset[s][f].upload(at, bytes);
    at += bytes;
  }
  // The owner list is derived from the list, not stored: the entries that own their pair, in list order.
  // Likewise each owner's partner (its mirrored entry), where the owner writes the mirror's pair results.
  std::vector<uint32_t> owners, partner(hd.entries, 0);
  for (uint32_t e = 0; e < hd.entries; ++e) {
    uint32_t m;
    std::memcpy(&m, mirror + size_t(e) * 4, 4);
    if (m == e)
      owners.push_back(e);
    else if (m < hd.entries)
      partner[m] = e;
  }
  if (!owners.empty()) B->owners.upload(owners);
  if (!partner.empty()) B->partner.upload(partner);
  c[ctlw::kOwners] = uint32_t(owners.size());
  c[ctlw::kOwnerArgs] = groups_for(owners.size());
  c[ctlw::kOwnerArgs + 1] = c[ctlw::kOwnerArgs + 2] = 1;
  c[ctlw::kStepArgs] = groups_for(n);
  c[ctlw::kStepArgs + 1] = c[ctlw::kStepArgs + 2] = 1;
  c[ctlw::kSkinRule] = skin_rule();  // this System's, not the snapshot's: the rule changes no result
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
}  // namespace wetdem
