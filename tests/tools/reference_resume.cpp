// wetdem_reference_resume: continues a run from its checkpoint on the double-precision CPU reference and,
// in lockstep, on the GPU passes, and writes the bed's centre-of-mass angle of both and how far their
// particles have moved apart at every sample (issue 22, docs/closed-slice.md "Lockstep with the
// double-precision reference"). Both start from the GPU's own state at the checkpoint, so a difference in the
// peak is made by the steps after it: float32 on the GPU against double on the reference, and the order of
// their operations.
//
//   wetdem_reference_resume RUN_DIR --until SECONDS [--csv FILE] [--no-gpu] [--from-start]
//                           [--float32 velocities|springs|both] [--hand-over [--hand-over-at SECONDS]]
//                           [--every STEPS] [--worst] [--sequential-events]
//
// RUN_DIR: a run folder with a checkpoint (`wetdem run ... --stop-after-steps K`); with --from-start, any
// run folder of the case: both codes start from the case's inserted bed at step 0 (as uploaded to the GPU),
// settle with the drum at rest and turn it from run.settle on. SECONDS: simulated time (from the run's
// start) to step to. --float32: the reference stores those fields in float32, as the GPU passes do (which
// field's precision moves the release). --hand-over: when the drum starts turning, the GPU takes the
// reference's settled bed (System::upload) and both go on from it (is the settled bed what differs?);
// --hand-over-at: at that time instead (a sample time), to find when in the settling the difference is made.
// --every: a sample every STEPS steps instead of the case's interval; --worst: at every sample, the particle
// farthest apart in the two codes (position, velocity, nearest wall) and the pairs whose bridges differ, to
// find the first event that parts them. --sequential-events: the reference applies the liquid events of a
// step one pair after another in id order, walls after pairs (MercuryDPM's order), instead of the two-phase
// rule. The reference is serial (a 1,800-particle slice: ~2 min per simulated second on one core): a tool for
// investigations; CI only checks that it runs and that both codes agree over a few steps.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "app/drum/aor.h"
#include "app/output/checkpoint.h"
#include "app/run/run.h"
#include "app/run/session.h"
#include "reference/reference.h"
#include "vk/context.h"

using namespace wetdem;

namespace {

struct Args {
  std::string run_dir, csv;
  double until = 0.0;
  bool gpu = true;
  bool from_start = false;
  bool hand_over = false;
  double hand_over_at = -1.0;  // seconds; < 0: when the drum starts turning
  uint32_t float32 = 0;        // ref::ReferenceSystem::RoundField bits
  uint64_t every = 0;          // steps per sample (0: the case's sample interval)
  bool worst = false;          // print the particle farthest apart and the bridges that differ
  bool sequential = false;  // the reference applies liquid events one pair after another (MercuryDPM's way)
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const char* key) {
      if (i + 1 >= argc) throw std::invalid_argument(std::string(key) + ": needs a value");
      return std::string(argv[++i]);
    };
    if (s == "--until")
      a.until = std::stod(value("--until"));
    else if (s == "--csv")
      a.csv = value("--csv");
    else if (s == "--no-gpu")
      a.gpu = false;
    else if (s == "--from-start")
      a.from_start = true;
    else if (s == "--hand-over")
      a.hand_over = true;
    else if (s == "--hand-over-at")
      a.hand_over = true, a.hand_over_at = std::stod(value("--hand-over-at"));
    else if (s == "--every") {
      const long k = std::stol(value("--every"));
      if (k < 1) throw std::invalid_argument("--every: steps per sample, >= 1");
      a.every = uint64_t(k);
    } else if (s == "--worst")
      a.worst = true;
    else if (s == "--sequential-events")
      a.sequential = true;
    else if (s == "--float32") {
      const std::string f = value("--float32");
      if (f == "velocities")
        a.float32 = ref::ReferenceSystem::kRoundVelocities;
      else if (f == "springs")
        a.float32 = ref::ReferenceSystem::kRoundSprings;
      else if (f == "both")
        a.float32 = ref::ReferenceSystem::kRoundVelocities | ref::ReferenceSystem::kRoundSprings;
      else
        throw std::invalid_argument("--float32: velocities, springs or both, got '" + f + "'");
    } else if (!s.empty() && s[0] == '-')
      throw std::invalid_argument("unknown option " + s);
    else
      a.run_dir = s;
  }
  if (a.run_dir.empty()) throw std::invalid_argument("RUN_DIR: missing (a run folder with a checkpoint)");
  if (!(a.until > 0.0)) throw std::invalid_argument("--until: missing or not a positive time in seconds");
  if (a.hand_over && !a.gpu) throw std::invalid_argument("--hand-over: needs the GPU (not with --no-gpu)");
  return a;
}

// Largest and mean distance between the two codes' particles (same stable ids).
std::pair<double, double> apart(const SystemState& a, const SystemState& b) {
  double mx = 0.0, sum = 0.0;
  for (size_t i = 0; i < a.p.size(); ++i) {
    const double d = glm::length(a.p.x[i] - b.p.x[i]);
    mx = std::max(mx, d);
    sum += d;
  }
  return {mx, a.p.size() ? sum / double(a.p.size()) : 0.0};
}

// How the two codes' contact springs compare (same stable ids): for pair springs present in both and for wall
// springs, Σ|ξ_gpu| / Σ|ξ_ref| (a float32 spring that loses slow creep increments is shorter) and
// Σ|ξ_gpu - ξ_ref| / Σ|ξ_ref|; and the bridges each code holds.
struct SpringStats {
  double t_ratio = 0, t_diff = 0, r_ratio = 0, r_diff = 0;
  double wall_t_ratio = 0, wall_t_diff = 0, wall_r_ratio = 0, wall_r_diff = 0;
  long bridges_ref = 0, bridges_gpu = 0;
  long long bridge_units_ref = 0, bridge_units_gpu = 0;  // Σ pair bridge volumes (liquid units)
  long bridges_differing = 0;                            // pairs whose bridge volumes differ
};

SpringStats springs(const SystemState& ref, const SystemState& gpu) {
  std::map<std::pair<uint32_t, uint32_t>, const PairRecord*> g;
  for (const PairRecord& r : gpu.pairs) g[{r.id_i, r.id_j}] = &r;
  double st[3] = {0, 0, 0}, sr[3] = {0, 0, 0};  // Σ|ref|, Σ|gpu|, Σ|diff|
  SpringStats out;
  for (const PairRecord& r : ref.pairs) {
    out.bridges_ref += r.bridge > 0;
    out.bridge_units_ref += r.bridge;
    const auto it = g.find({r.id_i, r.id_j});
    out.bridges_differing += (it == g.end() ? 0 : it->second->bridge) != r.bridge;
    if (it == g.end()) continue;
    st[0] += glm::length(r.spring_t), st[1] += glm::length(it->second->spring_t);
    st[2] += glm::length(r.spring_t - it->second->spring_t);
    sr[0] += glm::length(r.spring_r), sr[1] += glm::length(it->second->spring_r);
    sr[2] += glm::length(r.spring_r - it->second->spring_r);
  }
  for (const PairRecord& r : gpu.pairs) out.bridges_gpu += r.bridge > 0, out.bridge_units_gpu += r.bridge;
  double wt[3] = {0, 0, 0}, wr[3] = {0, 0, 0};
  for (size_t k = 0; k < ref.p.wall.size() && k < gpu.p.wall.size(); ++k) {
    const WallRecord &a = ref.p.wall[k], &b = gpu.p.wall[k];
    wt[0] += glm::length(a.spring_t), wt[1] += glm::length(b.spring_t),
        wt[2] += glm::length(a.spring_t - b.spring_t);
    wr[0] += glm::length(a.spring_r), wr[1] += glm::length(b.spring_r),
        wr[2] += glm::length(a.spring_r - b.spring_r);
  }
  const auto q = [](double a, double b) { return b > 0 ? a / b : std::nan(""); };
  out.t_ratio = q(st[1], st[0]), out.t_diff = q(st[2], st[0]);
  out.r_ratio = q(sr[1], sr[0]), out.r_diff = q(sr[2], sr[0]);
  out.wall_t_ratio = q(wt[1], wt[0]), out.wall_t_diff = q(wt[2], wt[0]);
  out.wall_r_ratio = q(wr[1], wr[0]), out.wall_r_diff = q(wr[2], wr[0]);
  return out;
}

// The particle farthest apart, and the pairs whose bridge volumes differ (up to 8), one line each.
void print_worst(const SystemState& a, const SystemState& b, double radius) {
  size_t w = 0;
  double dw = -1.0;
  for (size_t i = 0; i < a.p.size(); ++i)
    if (const double d = glm::length(a.p.x[i] - b.p.x[i]); d > dw) dw = d, w = i;
  const auto v3 = [](const glm::dvec3& x) { return fmt::format("({:.6e}, {:.6e}, {:.6e})", x.x, x.y, x.z); };
  const glm::dvec3 &xr = a.p.x[w], &xg = b.p.x[w];
  std::printf("  worst id %zu r %.4e apart %.3e wall gap %.3e\n    x ref %s gpu %s\n    v ref %s gpu %s\n", w,
              a.p.radius[w], dw, radius - std::hypot(xr.x, xr.y) - a.p.radius[w], v3(xr).c_str(),
              v3(xg).c_str(), v3(a.p.v[w]).c_str(), v3(b.p.v[w]).c_str());
  // The worst particle's touching neighbours by brute force in each code, and whether that code holds a
  // contact record (a spring or bridge) for the pair.
  for (const SystemState* st : {&a, &b}) {
    std::map<uint32_t, const PairRecord*> rec;
    for (const PairRecord& r : st->pairs)
      if (r.id_i == w || r.id_j == w) rec[r.id_i == w ? r.id_j : r.id_i] = &r;
    for (size_t j = 0; j < st->p.size(); ++j) {
      if (j == w) continue;
      const double gap = glm::length(st->p.x[w] - st->p.x[j]) - st->p.radius[w] - st->p.radius[j];
      const auto it = rec.find(uint32_t(j));
      if (gap < 0 || it != rec.end())
        std::printf("    %s: with %zu gap %.3e, record %s spring %.3e bridge %lld\n",
                    st == &a ? "ref" : "gpu", j, gap, it != rec.end() ? "yes" : "NO",
                    it != rec.end() ? glm::length(it->second->spring_t) : 0.0,
                    it != rec.end() ? (long long)it->second->bridge : 0LL);
    }
  }
  std::map<std::pair<uint32_t, uint32_t>, int64_t> vb;
  for (const PairRecord& r : b.pairs) vb[{r.id_i, r.id_j}] = r.bridge;
  std::map<std::pair<uint32_t, uint32_t>, int64_t> va;
  for (const PairRecord& r : a.pairs) va[{r.id_i, r.id_j}] = r.bridge;
  int shown = 0;
  for (const auto& [k, bv] : vb) va.emplace(k, 0);
  for (const auto& [k, av] : va) {
    const auto it = vb.find(k);
    const int64_t bv = it == vb.end() ? 0 : it->second;
    if (av == bv) continue;
    if (shown++ < 8) {
      const double gap =
          glm::length(a.p.x[k.first] - a.p.x[k.second]) - a.p.radius[k.first] - a.p.radius[k.second];
      std::printf("    bridge %u-%u: ref %lld gpu %lld (gap ref %.3e m)\n", k.first, k.second, (long long)av,
                  (long long)bv, gap);
    }
  }
  if (shown > 8) std::printf("    ... %d pairs differ\n", shown);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse(argc, argv);
    app::RunOptions ro;
    ro.resume_dir = args.run_dir;
    const app::Case c = app::resolve_case(ro);
    const app::Prepared prep = app::prepare_run(c);
    vk::ContextOptions co;
    co.quiet = true;
    vk::Context ctx(co);
    const auto say = [](const std::string& l) { std::fprintf(stderr, "%s\n", l.c_str()); };
    std::unique_ptr<app::DrumSession> session;
    if (args.from_start) {
      session = std::make_unique<app::DrumSession>(ctx, prep, say);
    } else {
      const app::Checkpoint ck = app::load_checkpoint(args.run_dir);
      if (ck.host.value("radii_hash", "") != prep.radii_hash)
        throw std::runtime_error("the checkpoint's particles differ from the case's fill (another build?)");
      session = std::make_unique<app::DrumSession>(ctx, prep, ck, say);
    }
    app::DrumSession& gpu = *session;
    const app::Schedule& sch = gpu.schedule();
    const double dt = prep.derived.dt;
    const uint64_t last = std::min<uint64_t>(sch.total, app::Schedule::steps(args.until, dt));

    // The reference takes the GPU's state as it is (for a fresh start: the inserted bed with the bridges the
    // upload formed on touching pairs) and the drum's phase of that step.
    ref::ReferenceSystem ref(app::phase_params(prep.prm, sch.rotating(gpu.step())));
    ref.set_float32_storage(args.float32);
    ref.set_sequential_events(args.sequential);
    ref.set_state(gpu.state());
    const double radius = prep.prm.drum.radius;
    const double t_rot = double(sch.n_settle) * dt;

    std::ofstream csv;
    if (!args.csv.empty()) {
      csv.open(args.csv);
      if (!csv) throw std::runtime_error("--csv: cannot write " + args.csv);
      csv << "time_s,time_rotating_s,aor_ref_deg,aor_gpu_deg,apart_max_m,apart_mean_m,"
             "spring_t_ratio,spring_t_diff,spring_r_ratio,spring_r_diff,"
             "wall_t_ratio,wall_t_diff,wall_r_ratio,wall_r_diff,"
             "bridges_ref,bridges_gpu,bridge_units_ref,bridge_units_gpu,bridges_differing\n";
    }
    const uint64_t hand_step =
        args.hand_over_at < 0 ? sch.n_settle : app::Schedule::steps(args.hand_over_at, dt);
    double peak_ref = -1.0, peak_gpu = -1.0, t_peak_ref = 0.0, t_peak_gpu = 0.0;
    for (uint64_t s = gpu.step(); s <= last;) {
      const SystemState sr = ref.state();
      const AorSample ar = dynamic_aor(sr, radius);
      double ag = std::nan(""), dmax = std::nan(""), dmean = std::nan("");
      SpringStats ss;
      if (args.gpu) {
        const SystemState sg = gpu.state();
        ss = springs(sr, sg);
        ag = dynamic_aor(sg, radius).abs_deg;
        std::tie(dmax, dmean) = apart(sr, sg);
        if (ag > peak_gpu) peak_gpu = ag, t_peak_gpu = double(s) * dt - t_rot;
      }
      if (ar.abs_deg > peak_ref) peak_ref = ar.abs_deg, t_peak_ref = double(s) * dt - t_rot;
      const double t = double(s) * dt;
      if (csv)
        csv << fmt::format("{:.6f},{:.6f},{:.4f},{:.4f},{:.4e},{:.4e},", t, t - t_rot, ar.abs_deg, ag, dmax,
                           dmean)
            << fmt::format("{:.6f},{:.4e},{:.6f},{:.4e},", ss.t_ratio, ss.t_diff, ss.r_ratio, ss.r_diff)
            << fmt::format("{:.6f},{:.4e},{:.6f},{:.4e},", ss.wall_t_ratio, ss.wall_t_diff, ss.wall_r_ratio,
                           ss.wall_r_diff)
            << fmt::format("{},{},{},{},{}\n", ss.bridges_ref, ss.bridges_gpu, ss.bridge_units_ref,
                           ss.bridge_units_gpu, ss.bridges_differing);
      std::printf("t %.3f s (rotating %.3f s): reference %.2f deg, GPU %.2f deg, apart max %.3g m\n", t,
                  t - t_rot, ar.abs_deg, ag, dmax);
      if (args.worst && args.gpu) print_worst(sr, gpu.state(), radius);
      std::fflush(stdout);
      if (s == last) break;
      const uint64_t every = args.every ? args.every : sch.sample;
      uint64_t to = std::min(last, (s / every + 1) * every);
      if (s < sch.n_settle) to = std::min(to, sch.n_settle);
      if (args.hand_over && s < hand_step) to = std::min(to, hand_step);
      for (uint64_t k = s; k < to; ++k) ref.step();
      if (to == sch.n_settle) ref.set_params(app::phase_params(prep.prm, true));  // the drum starts turning
      if (args.gpu)
        while (gpu.step() < to) gpu.advance(std::min(to, sch.next_stop(gpu.step())));
      if (args.hand_over && s < hand_step && to >= hand_step) {
        SystemState st = ref.state();
        st.step = to;
        gpu.system().upload(st);
      }
      s = to;
    }
    std::printf("peak: reference %.2f deg at %.2f s after rotation starts", peak_ref, t_peak_ref);
    if (args.gpu) std::printf(", GPU %.2f deg at %.2f s", peak_gpu, t_peak_gpu);
    std::printf("\n");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "wetdem_reference_resume: %s\n", e.what());
    return 1;
  }
}
