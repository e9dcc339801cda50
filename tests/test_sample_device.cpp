// System::sample_runs (issue 19): the device's reductions of a sample against their CPU reference,
// compute_observables of the whole downloaded state; the slim state against that state; each run of an
// ensemble bitwise what it gets alone; and the drum sample taken both ways.
#include <gtest/gtest.h>

#include <cmath>

#include "support/gpu.h"
#include "support/twin.h"
#include "wetdem/observables.h"
#include "wetdem/system.h"

#ifdef WETDEM_HAVE_APP
#include "app/run/sample.h"
#endif

namespace wetdem::test {

class SampleDevice : public GpuTest {};

namespace {

// A closed wet drum (cylinder and plates, bridges on the cylinder too) or a periodic slice, turning.
SimParams wet_drum(bool periodic, double v_max_units, double omega) {
  SimParams prm = twin_drum_params(0.012, 0.012, 0.5e-3, periodic);
  prm.liq_pp.enabled = true;
  prm.liq_pp.gamma = 0.1;
  prm.liq_pp.theta = 0.5;
  prm.liq_pp.v_max = int64_t(v_max_units);
  prm.liq_pw[kWallCylinder] = prm.liq_pp;
  prm.liquid_unit_m3 = 1e-20;
  prm.drum.omega = omega;
  return prm;
}

SystemState wet_packing(const SimParams& prm, size_t n, uint64_t seed, int64_t film) {
  SystemState s = random_drum_packing(prm, n, 0.5e-3, 0.8e-3, seed, 0.2);
  for (auto& f : s.p.film) f = film;
  return s;
}

// The device's reductions against the host's over the same state.
void expect_reductions_match(const Observables& dev, const Observables& ref, const std::string& what) {
  EXPECT_EQ(dev.contacts, ref.contacts) << what;
  EXPECT_EQ(dev.bridges, ref.bridges) << what;
  EXPECT_EQ(dev.wet_or_touching, ref.wet_or_touching) << what;
  EXPECT_DOUBLE_EQ(dev.f_wet, ref.f_wet) << what;
  EXPECT_EQ(dev.wall_contacts, ref.wall_contacts) << what;
  EXPECT_EQ(dev.wall_bridges, ref.wall_bridges) << what;
  EXPECT_EQ(dev.liquid_films, ref.liquid_films) << what;
  EXPECT_EQ(dev.liquid_bridges, ref.liquid_bridges) << what;
  EXPECT_EQ(dev.liquid_pores, ref.liquid_pores) << what;
  EXPECT_EQ(dev.liquid_evaporated, ref.liquid_evaporated) << what;
  // Float quantities: float32 products on the device, fixed-point sums (2^-34 of the largest mass, 2^-36 of
  // the largest energy per particle), against double on the host.
  EXPECT_NEAR(dev.max_overlap, ref.max_overlap, 1e-5 * ref.max_overlap + 1e-12) << what;
  EXPECT_NEAR(dev.kinetic_energy, ref.kinetic_energy, 1e-5 * ref.kinetic_energy) << what;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(dev.com[a], ref.com[a], 1e-9) << what << " com[" << a << "]";
}

}  // namespace

TEST_F(SampleDevice, ReductionsMatchTheHostReferenceAndTheSlimStateMatchesTheDownload) {
  for (bool periodic : {false, true}) {
    const SimParams prm = wet_drum(periodic, 1 << 28, 4.0);
    const SystemState s0 = wet_packing(prm, 500, periodic ? 41 : 42, 1 << 27);
    System sys(gpu(), prm, s0.p.size());
    sys.upload(s0);
    for (int stop = 0; stop < 3; ++stop) {
      sys.step(stop == 0 ? 1 : 200);
      const std::vector<RunSample> rs = sys.sample_runs();
      ASSERT_EQ(rs.size(), 1u);
      const SystemState full = sys.download();
      const std::string what =
          (periodic ? "slice" : "closed") + std::string(", stop ") + std::to_string(stop);
      const Observables ref = compute_observables(full, prm);
      expect_reductions_match(rs[0].obs, ref, what);
      // The slim state: exactly the downloaded positions, velocities, radii, masses and bridged pairs.
      const SystemState& bed = rs[0].bed;
      ASSERT_EQ(bed.p.size(), full.p.size());
      EXPECT_TRUE(bed.p.film.empty() && bed.p.w.empty() && bed.p.wall.empty()) << "slim: nothing else read";
      for (size_t k = 0; k < full.p.size(); ++k) {
        ASSERT_EQ(bed.p.x[k], full.p.x[k]) << what << " particle " << k;
        ASSERT_EQ(bed.p.v[k], full.p.v[k]) << what << " particle " << k;
        ASSERT_EQ(bed.p.radius[k], full.p.radius[k]);
        ASSERT_EQ(bed.p.mass[k], full.p.mass[k]);
      }
      std::vector<PairRecord> bridged;
      for (const PairRecord& r : full.pairs)
        if (r.bridge > 0) bridged.push_back(r);
      ASSERT_EQ(bed.pairs.size(), bridged.size()) << what;
      for (size_t q = 0; q < bridged.size(); ++q) {
        EXPECT_EQ(bed.pairs[q].id_i, bridged[q].id_i);
        EXPECT_EQ(bed.pairs[q].id_j, bridged[q].id_j);
        EXPECT_EQ(bed.pairs[q].bridge, bridged[q].bridge);
      }
      EXPECT_EQ(bed.step, full.step);
      // The sample did not disturb the run: a second one is bitwise the first.
      const std::vector<RunSample> again = sys.sample_runs();
      EXPECT_EQ(again[0].obs.com, rs[0].obs.com);
      EXPECT_EQ(again[0].obs.kinetic_energy, rs[0].obs.kinetic_energy);
      if (stop == 2) {
        EXPECT_GT(ref.contacts, 100u) << what << ": the test needs a packed bed";
        EXPECT_GT(ref.bridges, 100u) << what << ": ... and bridges";
        if (!periodic) {
          EXPECT_GT(ref.wall_contacts, 10u) << what;
        }
      }
    }
  }
}

TEST_F(SampleDevice, CompactListGrowsWhenTheBridgesOutnumberIt) {
  // 1,500 particles with thick films: more bridges than particles, beyond the list's first capacity.
  const SimParams prm = wet_drum(true, 1 << 28, 0.0);
  const SystemState s0 = wet_packing(prm, 1500, 43, 1 << 28);
  System sys(gpu(), prm, s0.p.size());
  sys.upload(s0);
  sys.step(300);
  const std::vector<RunSample> rs = sys.sample_runs();
  const SystemState full = sys.download();
  size_t bridged = 0;
  for (const PairRecord& r : full.pairs) bridged += r.bridge > 0;
  EXPECT_GT(bridged, full.p.size()) << "the test needs more bridges than particles";
  EXPECT_EQ(rs[0].bed.pairs.size(), bridged);
  expect_reductions_match(rs[0].obs, compute_observables(full, prm), "grown list");
}

TEST_F(SampleDevice, EachRunOfAnEnsembleGetsBitwiseWhatItGetsAlone) {
  std::vector<SimParams> prm = {wet_drum(false, 1 << 28, 4.0), wet_drum(false, 1 << 26, 2.0),
                                wet_drum(false, 1 << 28, 6.0)};
  prm[2].liq_pp.enabled = prm[2].liq_pw[kWallCylinder].enabled = false;
  const std::vector<SystemState> s = {wet_packing(prm[0], 400, 51, 1 << 27),
                                      wet_packing(prm[1], 300, 52, 1 << 26), wet_packing(prm[2], 400, 51, 0)};
  std::vector<RunSample> alone;
  for (size_t r = 0; r < prm.size(); ++r) {
    System sys(gpu(), prm[r], s[r].p.size());
    sys.upload(s[r]);
    sys.step(250);
    alone.push_back(sys.sample_runs()[0]);
  }
  System ens(gpu(), prm, {s[0].p.size(), s[1].p.size(), s[2].p.size()});
  ens.upload_runs(s);
  ens.step(250);
  const std::vector<RunSample> together = ens.sample_runs();
  ASSERT_EQ(together.size(), 3u);
  for (size_t r = 0; r < prm.size(); ++r) {
    const Observables &a = alone[r].obs, &b = together[r].obs;
    EXPECT_EQ(a.contacts, b.contacts) << "run " << r;
    EXPECT_EQ(a.bridges, b.bridges) << "run " << r;
    EXPECT_EQ(a.wall_contacts, b.wall_contacts) << "run " << r;
    EXPECT_EQ(a.liquid_films, b.liquid_films) << "run " << r;
    EXPECT_EQ(a.liquid_bridges, b.liquid_bridges) << "run " << r;
    // Bitwise, not merely close: the fixed-point sums use the run's own scales.
    EXPECT_EQ(a.com, b.com) << "run " << r;
    EXPECT_EQ(a.kinetic_energy, b.kinetic_energy) << "run " << r;
    EXPECT_EQ(a.max_overlap, b.max_overlap) << "run " << r;
    EXPECT_EQ(alone[r].bed.p.x, together[r].bed.p.x) << "run " << r;
    EXPECT_EQ(alone[r].bed.pairs.size(), together[r].bed.pairs.size()) << "run " << r;
  }
  EXPECT_GT(alone[0].obs.bridges, 0u);
  EXPECT_EQ(alone[2].obs.bridges, 0u);
}

#ifdef WETDEM_HAVE_APP
TEST_F(SampleDevice, DrumSampleFromTheDeviceEqualsTheSampleFromTheWholeState) {
  // take_sample from the slim state and the device's reductions (what runs do) against take_sample from the
  // whole downloaded state (host reductions): the same sample up to the fixed-point sums' rounding.
  const SimParams prm = wet_drum(false, 1 << 28, 4.0);
  const SystemState s0 = wet_packing(prm, 500, 44, 1 << 27);
  System sys(gpu(), prm, s0.p.size());
  sys.upload(s0);
  sys.step(400);
  app::Prepared prep;
  prep.prm = prm;
  app::SampleContext x;
  x.prep = &prep;
  x.prm = &prm;
  x.step = 400;
  x.liquid_start = s0.total_liquid();
  bool w1 = true, w2 = true;
  auto quiet = [](const std::string&) {};
  const app::Sample a = app::take_sample(sys.sample_runs()[0], x, w1, quiet);
  const app::Sample b = app::take_sample(sys.download(), x, w2, quiet);
  EXPECT_NEAR(a.aor_signed_deg, b.aor_signed_deg, 1e-6);
  EXPECT_EQ(a.flagged, b.flagged);
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.bridges, b.bridges);
  EXPECT_EQ(a.f_wet, b.f_wet);
  EXPECT_EQ(a.liquid_films, b.liquid_films);
  EXPECT_EQ(a.liquid_bridges, b.liquid_bridges);
  for (const observe::CameraField& f : observe::kCameraFields) {
    const double u = a.camera.*(f.value), v = b.camera.*(f.value);
    if (std::isnan(v)) {
      EXPECT_TRUE(std::isnan(u)) << f.name;
    } else {
      EXPECT_NEAR(u, v, 1e-9 * std::fabs(v) + 1e-12) << f.name;
    }
  }
}
#endif

}  // namespace wetdem::test
