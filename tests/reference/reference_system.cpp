// The CPU reference step (§0 of ../shared/spec/physics.md): velocity Verlet, brute-force-simple neighbour
// search (sort and sweep along x), pair history in a map keyed by stable ids, walls, liquid events.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "reference/contact_law.h"
#include "reference/liquid_events.h"
#include "reference/reference.h"
#include "reference/walls.h"

namespace wetdem::ref {

ReferenceSystem::ReferenceSystem(const SimParams& prm) : prm_(prm) {}

void ReferenceSystem::set_state(const SystemState& s) {
  p_ = s.p;
  p_.resize(s.p.size());  // tolerate a state without wall records
  pairs_.clear();
  for (const PairRecord& r : s.pairs) {
    if (r.id_i >= r.id_j || r.id_j >= p_.size())
      throw std::invalid_argument("pair record needs id_i < id_j < n");
    if (!r.empty()) pairs_[{r.id_i, r.id_j}] = r;
  }
  time_ = s.time;
  step_ = s.step;
  bool wet = prm_.liq_pp.enabled;
  for (const LiquidParams& l : prm_.liq_pw) wet = wet || l.enabled;
  if (wet) events_at_rest();
}

// §5 events of the state as given, before any step (issue 12; MercuryDPM's initialiseSolve): the same
// geometry the force pass records (gaps of touching and recorded pairs, wall gaps), no force or spring.
void ReferenceSystem::events_at_rest() {
  examined_ = touching_pairs();
  for (const auto& kv : pairs_) examined_.push_back(kv.first);
  std::sort(examined_.begin(), examined_.end());
  examined_.erase(std::unique(examined_.begin(), examined_.end()), examined_.end());
  pair_gap_.assign(examined_.size(), std::numeric_limits<double>::infinity());
  for (size_t e = 0; e < examined_.size(); ++e) {
    const auto [i, j] = examined_[e];
    const glm::dvec3 d = separation(i, j);
    if (d == glm::dvec3(0.0)) continue;
    pair_gap_[e] = glm::length(d) - p_.radius[i] - p_.radius[j];
    PairRecord& rec = pairs_[examined_[e]];
    rec.id_i = i;
    rec.id_j = j;
  }
  const size_t n = p_.size();
  wall_gap_.assign(n * kNumWalls, std::numeric_limits<double>::infinity());
  for (uint32_t w = 0; w < kNumWalls; ++w) {
    if (!wall_present(prm_.drum, w)) continue;
    for (size_t i = 0; i < n; ++i) {
      glm::dvec3 nrm;
      double delta;
      if (wall_geometry(prm_.drum, w, p_.x[i], p_.radius[i], nrm, delta))
        wall_gap_[i * kNumWalls + w] = -delta;
    }
  }
  liquid_events(false);  // at rest: no sinks (they act over a step)
}

SystemState ReferenceSystem::state() const {
  SystemState s;
  s.p = p_;
  s.pairs.reserve(pairs_.size());
  for (const auto& kv : pairs_) s.pairs.push_back(kv.second);
  s.time = time_;
  s.step = step_;
  s.canonicalize();
  return s;
}

const std::vector<glm::dvec3>& ReferenceSystem::forces() const {
  return p_.f;
}
const std::vector<glm::dvec3>& ReferenceSystem::torques() const {
  return p_.t;
}
const SimParams& ReferenceSystem::params() const {
  return prm_;
}
void ReferenceSystem::set_sequential_events(bool on) {
  sequential_ = on;
}

EventCounts ReferenceSystem::read_events() {
  EventCounts e = events_;
  events_ = EventCounts{};
  return e;
}

void ReferenceSystem::step() {
  const double dt = prm_.dt;
  kick(0.5 * dt);    // with F, T of the previous step
  drift();           // x^{n+1}
  compute_forces();  // at x^{n+1} with the half-step velocities
  kick(0.5 * dt);
  liquid_events();  // §5, after the second half kick
  if (round_ & kRoundSprings) {
    const auto f32 = [](glm::dvec3& a) { a = glm::dvec3(glm::vec3(a)); };
    for (auto& kv : pairs_) f32(kv.second.spring_t), f32(kv.second.spring_r);
    for (WallRecord& r : p_.wall) f32(r.spring_t), f32(r.spring_r);
  }
  time_ += dt;
  ++step_;
}

void ReferenceSystem::kick(double h) {
  for (size_t k = 0; k < p_.size(); ++k) {
    p_.v[k] += h * (p_.f[k] / p_.mass[k] + prm_.gravity);
    p_.w[k] += h * p_.t[k] / p_.inertia[k];  // spheres: scalar inertia, no orientation needed
    if (round_ & kRoundVelocities)
      p_.v[k] = glm::dvec3(glm::vec3(p_.v[k])), p_.w[k] = glm::dvec3(glm::vec3(p_.w[k]));
  }
}

void ReferenceSystem::drift() {
  const double L = prm_.drum.length;
  for (size_t k = 0; k < p_.size(); ++k) {
    p_.x[k] += prm_.dt * p_.v[k];
    if (prm_.drum.periodic_z) {
      double& z = p_.x[k].z;
      z -= L * std::floor((z + 0.5 * L) / L);  // into [-L/2, L/2)
      if (z >= 0.5 * L) z -= L;                // rounding guards
      if (z < -0.5 * L) z = -0.5 * L;
    }
  }
}

glm::dvec3 ReferenceSystem::separation(uint32_t i, uint32_t j) const {
  glm::dvec3 d = p_.x[i] - p_.x[j];
  if (prm_.drum.periodic_z) {
    const double L = prm_.drum.length;
    d.z -= L * std::floor(d.z / L + 0.5);  // minimum image
  }
  return d;
}

std::vector<ReferenceSystem::PairKey> ReferenceSystem::touching_pairs() const {
  // Sort and sweep along x (x is never periodic): a pair can touch only if |x_i - x_j| <= r_i + r_max.
  const size_t n = p_.size();
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return p_.x[a].x < p_.x[b].x; });
  const double r_max = n ? *std::max_element(p_.radius.begin(), p_.radius.end()) : 0.0;
  std::vector<PairKey> out;
  for (size_t a = 0; a < n; ++a) {
    const uint32_t i = order[a];
    for (size_t b = a + 1; b < n; ++b) {
      const uint32_t j = order[b];
      if (p_.x[j].x - p_.x[i].x > p_.radius[i] + r_max) break;
      const double reach = p_.radius[i] + p_.radius[j];
      const glm::dvec3 d = separation(i, j);
      if (glm::dot(d, d) <= reach * reach) out.push_back({std::min(i, j), std::max(i, j)});
    }
  }
  return out;
}

void ReferenceSystem::compute_forces() {
  const size_t n = p_.size();
  std::fill(p_.f.begin(), p_.f.end(), glm::dvec3(0.0));
  std::fill(p_.t.begin(), p_.t.end(), glm::dvec3(0.0));

  // Pairs: every touching pair and every pair with history (springs, bridge, flag). A bridged pair is
  // therefore always examined, and ruptures (§5) before its record could ever be forgotten.
  examined_ = touching_pairs();
  for (const auto& kv : pairs_) examined_.push_back(kv.first);
  std::sort(examined_.begin(), examined_.end());
  examined_.erase(std::unique(examined_.begin(), examined_.end()), examined_.end());
  pair_gap_.assign(examined_.size(), std::numeric_limits<double>::infinity());

  const double range_pp = prm_.bridge_range_pp();
  for (size_t e = 0; e < examined_.size(); ++e) {
    const auto [i, j] = examined_[e];
    const glm::dvec3 d = separation(i, j);
    if (d == glm::dvec3(0.0)) continue;  // coincident centres: no normal, no force (never in a valid state)
    const ContactKinematics k = pair_kinematics(d, p_.radius[i], p_.radius[j], p_.mass[i], p_.mass[j],
                                                p_.v[i], p_.v[j], p_.w[i], p_.w[j]);
    pair_gap_[e] = -k.delta;

    PairRecord& rec = pairs_[examined_[e]];
    rec.id_i = i;
    rec.id_j = j;
    ContactHistory h{rec.spring_t, rec.spring_r, rec.bridge};
    const PairForce pf = evaluate_contact(prm_.pp, prm_.liq_pp, prm_.liquid_unit_m3, range_pp, prm_.dt, k, h);
    rec.spring_t = h.spring_t;
    rec.spring_r = h.spring_r;
    p_.f[i] += pf.force;
    p_.f[j] -= pf.force;
    p_.t[i] += pf.torque_i;
    p_.t[j] += pf.torque_j;
  }

  // Walls: one record per particle and wall, its own springs and bridge.
  wall_gap_.assign(n * kNumWalls, std::numeric_limits<double>::infinity());
  for (uint32_t w = 0; w < kNumWalls; ++w) {
    if (!wall_present(prm_.drum, w)) continue;
    const double range = prm_.bridge_range_pw(w);
    for (size_t i = 0; i < n; ++i) {
      glm::dvec3 nrm;
      double delta;
      if (!wall_geometry(prm_.drum, w, p_.x[i], p_.radius[i], nrm, delta)) continue;
      const ContactKinematics k =
          wall_kinematics(prm_.drum, w, p_.x[i], p_.radius[i], p_.mass[i], p_.v[i], p_.w[i], nrm, delta);
      wall_gap_[i * kNumWalls + w] = -delta;
      WallRecord& rec = p_.wall[i * kNumWalls + w];
      ContactHistory h{rec.spring_t, rec.spring_r, rec.bridge};
      const PairForce pf =
          evaluate_contact(prm_.pw[w], prm_.liq_pw[w], prm_.liquid_unit_m3, range, prm_.dt, k, h);
      rec.spring_t = h.spring_t;
      rec.spring_r = h.spring_r;
      p_.f[i] += pf.force;
      p_.t[i] += pf.torque_i;
    }
  }
}

void ReferenceSystem::liquid_events(bool sinks) {
  // Geometry is that of the force pass: the second half kick moves no particle.
  LiquidView view;
  view.prm = &prm_;
  view.film = &p_.film;
  view.wall = &p_.wall;
  view.wall_gap = wall_gap_;
  view.pore = &p_.pore;
  view.evaporated = &p_.evaporated;
  view.radius = &p_.radius;
  view.sinks = sinks;
  view.pairs.reserve(examined_.size());
  for (size_t e = 0; e < examined_.size(); ++e) {
    auto it = pairs_.find(examined_[e]);
    if (it == pairs_.end()) continue;
    view.pairs.push_back({examined_[e].first, examined_[e].second, pair_gap_[e], &it->second});
  }
  const EventCounts ev = sequential_ ? liquid_events_sequential(view) : liquid_events_two_phase(view);
  events_.formations += ev.formations;
  events_.ruptures += ev.ruptures;
  // Keep the map small: records with no springs, bridge or flag carry nothing.
  for (auto it = pairs_.begin(); it != pairs_.end();)
    it = it->second.empty() ? pairs_.erase(it) : std::next(it);
}

}  // namespace wetdem::ref
