// System::sample_runs (issue 19): what a drum sample needs, in one transfer. Three passes reduce, per run,
// the numbers compute_observables finds on the host (host/core/observables.cpp, their CPU reference): counts
// of touching, bridged and wall pairs, liquid sums, centre of mass and kinetic energy
// (shaders/common/sample.glsl: integer atomics only, fixed-point sums on the run's own scales, so
// deterministic and, in an ensemble, bitwise what the run reduces to alone). The same submit copies the slim
// state a camera needs: positions, velocities, radii and masses, and the compact list of bridged pairs;
// springs, forces, wall records and the neighbour list stay on the device.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "gpu/system_impl.h"

namespace wetdem {

using gpu::groups_for;

namespace {

int64_t word64(const uint32_t* w, uint32_t at) {
  uint64_t u = uint64_t(w[at]) | (uint64_t(w[at + 1]) << 32);
  int64_t v;
  std::memcpy(&v, &u, 8);
  return v;
}

float word_float(const uint32_t* w, uint32_t at) {
  float f;
  std::memcpy(&f, &w[at], 4);
  return f;
}

}  // namespace

std::vector<RunSample> System::Impl::sample_runs() {
  if (!uploaded) throw std::logic_error("System::sample_runs before upload");
  namespace sw = gpu::smp;
  for (const char* nm : {"sample_max", "sample_sum", "sample_pairs"})
    if (!kernels.count(nm)) kernels[nm] = std::make_unique<vk::Kernel>(ctx, nm);
  const uint32_t runs = uint32_t(run_prm.size());
  const uint32_t words = sw::kHead + sw::kRun * runs;
  const auto c = read_ctl();
  const uint32_t s = c[ctlw::kParity];
  const uint32_t owners = c[ctlw::kOwners];
  // The compact list holds every bridged pair: at most one per owner entry. Start at a bridge per particle
  // and grow to what a sample found (the pass counts beyond the capacity; then it is run again).
  if (B->smp_pair_capacity() == 0) B->grow_sample_pairs(std::max<uint32_t>(1024, std::min(n, owners)));
  const uint64_t nb = uint64_t(n) * 16;  // pos, frac, vel, props: 16 B each per particle
  const uint64_t head = uint64_t(words) * 4;
  std::vector<uint32_t> w(words);
  for (int attempt = 0;; ++attempt) {
    const uint32_t cap = B->smp_pair_capacity();
    const uint64_t list_at = head + 4 * nb, bytes = list_at + uint64_t(cap) * 16;
    if (!smp_staging || smp_staging_bytes < bytes) {
      smp_staging.reset();
      smp_staging = std::make_unique<vk::Staging>(ctx, bytes);
      smp_staging_bytes = bytes;
    }
    std::vector<uint32_t> init(words, 0u);
    init[sw::kCapacity] = cap;
    for (uint32_t r = 0; r < runs; ++r) {
      const DrumParams& d = run_prm[r].drum;
      const float ext = float(std::max(d.radius, 0.5 * d.length));
      std::memcpy(&init[sw::kHead + sw::kRun * r + sw::kExtent], &ext, 4);
    }
    if (head > 65536) B->smp.upload(init);  // vkCmdUpdateBuffer takes at most 64 kB (~2,000 runs)
    const vk::Staging& st = *smp_staging;
    ctx.submit_now([&](VkCommandBuffer cb) {
      // The kernels read the buffer table from descriptor set 0 (access.glsl), as in record().
      vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, ctx.pipeline_layout(), 0, 1,
                              &B->descriptors, 0, nullptr);
      if (head <= 65536) vkCmdUpdateBuffer(cb, B->smp.handle(), 0, head, init.data());
      vk::barrier(cb);
      const gpu::Push p = push();
      kernels.at("sample_max")->dispatch(cb, groups_for(n), &p, sizeof(p));
      vk::barrier(cb);
      kernels.at("sample_pairs")->dispatch_indirect(cb, B->ctl.handle(), ctlw::kOwnerArgs * 4, &p, sizeof(p));
      vk::barrier(cb);
      kernels.at("sample_sum")->dispatch(cb, groups_for(n), &p, sizeof(p));
      vk::barrier(cb);
      const VkBufferCopy hc{0, 0, head};
      vkCmdCopyBuffer(cb, B->smp.handle(), st.handle(), 1, &hc);
      const gpu::ParticleField fields[] = {gpu::kPos, gpu::kFrac, gpu::kVel, gpu::kProps};
      for (int f = 0; f < 4; ++f) {
        const VkBufferCopy pc{0, head + uint64_t(f) * nb, nb};
        vkCmdCopyBuffer(cb, B->pset[s][fields[f]].handle(), st.handle(), 1, &pc);
      }
      const VkBufferCopy lc{0, list_at, uint64_t(cap) * 16};
      vkCmdCopyBuffer(cb, B->smp_pairs.handle(), st.handle(), 1, &lc);
    });
    std::memcpy(w.data(), st.map(), head);
    const uint32_t found = w[sw::kPairs];
    if (found > cap) {
      if (attempt > 0) throw std::runtime_error("sample_runs: the bridged-pair list overflowed twice");
      B->grow_sample_pairs(found + found / 4 + 1024);
      continue;
    }
    // The slim states, in each run's stable ids.
    const uint8_t* base = static_cast<const uint8_t*>(st.map()) + head;
    std::vector<int32_t> pos(4 * size_t(n));
    std::vector<float> frac(4 * size_t(n)), vel(4 * size_t(n)), props(4 * size_t(n));
    std::memcpy(pos.data(), base, nb);
    std::memcpy(frac.data(), base + nb, nb);
    std::memcpy(vel.data(), base + 2 * nb, nb);
    std::memcpy(props.data(), base + 3 * nb, nb);
    std::vector<RunSample> out(runs);
    for (uint32_t r = 0; r < runs; ++r) {
      const uint32_t m = run_off[r + 1] - run_off[r];
      ParticleArrays& p = out[r].bed.p;
      p.x.resize(m);
      p.v.resize(m);
      p.radius.resize(m);
      p.mass.resize(m);
      out[r].bed.time = time0 + double(steps) * prm.dt;
      out[r].bed.step = step0 + steps;
    }
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t id = uint32_t(pos[4 * k + 3]);
      const uint32_t r = run_of(id);
      const uint32_t i = id - run_off[r];
      ParticleArrays& p = out[r].bed.p;
      for (int a = 0; a < 3; ++a) {
        p.x[i][a] = (double(pos[4 * k + a]) + double(frac[4 * k + a])) * h;
        p.v[i][a] = vel[4 * k + a];
      }
      int32_t r_ticks;
      std::memcpy(&r_ticks, &props[4 * k + 3], 4);
      p.radius[i] = (double(r_ticks) + double(frac[4 * k + 3])) * h;
      p.mass[i] = props[4 * k + 1];
    }
    if (found > 0) {
      std::vector<uint32_t> list(4 * size_t(found));
      std::memcpy(list.data(), static_cast<const uint8_t*>(st.map()) + list_at, size_t(found) * 16);
      for (uint32_t q = 0; q < found; ++q) {
        const uint32_t a = list[4 * q], b = list[4 * q + 1];
        const uint32_t r = run_of(a);
        PairRecord rec;
        rec.id_i = a - run_off[r];
        rec.id_j = b - run_off[r];
        const uint64_t u = uint64_t(list[4 * q + 2]) | (uint64_t(list[4 * q + 3]) << 32);
        std::memcpy(&rec.bridge, &u, 8);
        out[r].bed.pairs.push_back(rec);
      }
    }
    for (uint32_t r = 0; r < runs; ++r) {
      out[r].bed.canonicalize();
      const uint32_t* b = w.data() + sw::kHead + sw::kRun * r;
      Observables& o = out[r].obs;
      o.contacts = b[sw::kContacts];
      o.bridges = b[sw::kBridges];
      o.wet_or_touching = uint64_t(b[sw::kContacts]) + b[sw::kBridges] - b[sw::kTouchBridged];
      o.f_wet = o.wet_or_touching > 0 ? double(o.bridges) / double(o.wet_or_touching) : 0.0;
      o.wall_contacts = b[sw::kWallContacts];
      o.wall_bridges = b[sw::kWallBridges];
      o.max_overlap = word_float(b, sw::kMaxOverlap);
      o.liquid_films = word64(b, sw::kFilms);
      o.liquid_bridges = word64(b, sw::kPairLiq) + word64(b, sw::kWallLiq);
      o.liquid_pores = word64(b, sw::kPores);
      o.liquid_evaporated = word64(b, sw::kEvap);
      const double ext = double(word_float(b, sw::kExtent));
      const double qm = double(word64(b, sw::kMass));
      if (qm > 0)
        o.com =
            glm::dvec3(double(word64(b, sw::kMx)), double(word64(b, sw::kMy)), double(word64(b, sw::kMz))) *
            (ext / qm);
      // A particle whose energy or position is not finite makes the energy not finite: the run's health check
      // (take_sample) reports the blow-up, as it does from a downloaded state.
      o.kinetic_energy = b[sw::kNonFinite] > 0
                             ? std::numeric_limits<double>::quiet_NaN()
                             : std::ldexp(double(word64(b, sw::kKe)) * double(word_float(b, sw::kMaxKe)),
                                          -gpu::smp::kKeBits);
    }
    return out;
  }
}

std::vector<RunSample> System::sample_runs() {
  return impl_->sample_runs();
}

}  // namespace wetdem
