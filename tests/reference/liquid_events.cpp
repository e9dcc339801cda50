#include "reference/liquid_events.h"

#include <algorithm>
#include <cmath>

namespace wetdem::ref {

int64_t split_proportional(int64_t V, int64_t a, int64_t b, int64_t a_cap, int64_t b_cap) {
  if (V <= 0 || a + b <= 0) return 0;
  const uint64_t ua = uint64_t(a), ub = uint64_t(b), uv = uint64_t(V);
  const uint64_t q = (ua << 16) / (ua + ub);                            // a/(a+b) in 1/65536 steps, floor
  const uint64_t part = (uv >> 16) * q + (((uv & 0xFFFFu) * q) >> 16);  // V q / 65536 without overflow
  int64_t part_a = int64_t(part);
  part_a = std::max(part_a, std::max<int64_t>(0, V - b_cap));
  part_a = std::min(part_a, std::min(V, a_cap));
  return part_a;
}

// §5: d_c h computed as an integer. [ours] d_c is applied in steps of 1/65536 (q = round(65536 d_c)), so
// that every device computes the same integer: give = floor(h q / 65536), here in exact 128-bit arithmetic.
// (The GPU system's mul_q16 does the same; for d_c = 0.8, q/65536 = 0.80000305.) What is not given stays
// with the giver.
__extension__ typedef __int128 int128;
int64_t distribution_give(int64_t h, double d_c) {
  const int128 q = std::llround(std::clamp(d_c, 0.0, 1.0) * 65536.0);
  return int64_t((int128(h) * q) >> 16);
}

namespace {

constexpr uint32_t kWas = kFlagWasInContact;

// §4: S_c = (1 + theta/2) V^(1/3); with hysteresis the bridge recedes: (1 + theta_r/2) V^(1/3).
double rupture_gap(const LiquidParams& lp, int64_t bridge, double unit) {
  return rupture_distance(lp.theta_r(), double(bridge) * unit);
}

// Amount above the cap that a bridge holding `b` after receiving `received` must hand back: never more than
// it received this step ([ours]: a bridge already above its cap, e.g. after a parameter change, keeps its
// old liquid).
int64_t overflow_of(int64_t b, int64_t received, int64_t cap) {
  return std::max<int64_t>(0, std::min(b - cap, received));
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Two-phase rule, §5 "Simultaneous events". Choices the text leaves open, all [ours]:
// - A particle keeps two kinds of receipts: halves of ruptured particle-particle bridges (one sum, shared
// with
//   liq_pp.d_c over its surviving particle-particle bridges only) and whole volumes of ruptured wall bridges
//   (one receipt per wall, shared with that wall's d_c over its surviving particle-particle AND wall
//   bridges). Each receipt gives distribution_give(h, d_c) / N to each bridge; the remainder stays in the
//   particle's film.
// - Shares arriving at a bridge add up; the cap (liq_pp.v_max, or the wall's v_max) then applies once, and
// the
//   overflow returns to the two films by split_proportional of the two shares.
// - Flags: a pair without bridge and S > 0 loses kFlagWasInContact; a pair or wall with delta >= 0 and no
// flag
//   is a formation candidate only where its bridges are enabled (dry runs keep no flags). Every candidate
//   gets the flag; those above the threshold (pairs: V_f,i + V_f,j > V_min; walls: V_f,i >= V_min) are the
//   k "forming" contacts of each particle. Only a bridge that takes V_b > 0 counts as a formation.
EventCounts liquid_events_two_phase(LiquidView& L) {
  const SimParams& prm = *L.prm;
  std::vector<int64_t>& film = *L.film;
  std::vector<WallRecord>& wall = *L.wall;
  const size_t n = film.size();
  const double unit = prm.liquid_unit_m3;
  EventCounts ev;

  // Phase 1a: which bridges rupture (S >= S_c of the volume held at the end of the step), receipts.
  std::vector<int64_t> recv_pp(n, 0), recv_w(n * kNumWalls, 0);
  for (PairSlot& s : L.pairs) {
    PairRecord& r = *s.rec;
    if (r.bridge > 0 && s.gap >= rupture_gap(prm.liq_pp, r.bridge, unit)) {
      const int64_t h_i = r.bridge / 2;  // §5: equal halves, the odd unit to the higher id
      recv_pp[s.i] += h_i;
      recv_pp[s.j] += r.bridge - h_i;
      r.bridge = 0;
      r.flags &= ~kWas;
      ++ev.ruptures;
    }
  }
  for (size_t k = 0; k < n; ++k) {
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      WallRecord& r = wall[k * kNumWalls + w];
      if (r.bridge > 0 && L.wall_gap[k * kNumWalls + w] >= rupture_gap(prm.liq_pw[w], r.bridge, unit)) {
        recv_w[k * kNumWalls + w] = r.bridge;  // §5: a wall bridge gives all of V_b to the particle
        r.bridge = 0;
        r.flags &= ~kWas;
        ++ev.ruptures;
      }
    }
  }

  // Phase 1b: surviving bridges of each particle.
  std::vector<int64_t> n_pp(n, 0), n_w(n, 0);
  for (const PairSlot& s : L.pairs) {
    if (s.rec->bridge > 0) {
      ++n_pp[s.i];
      ++n_pp[s.j];
    }
  }
  for (size_t k = 0; k < n; ++k)
    for (uint32_t w = 0; w < kNumWalls; ++w) n_w[k] += wall[k * kNumWalls + w].bridge > 0 ? 1 : 0;

  // Phase 1c: per-bridge shares of each particle; remainders and undistributed liquid to its film.
  std::vector<int64_t> share_pp(n, 0), share_w(n, 0);
  for (size_t k = 0; k < n; ++k) {
    if (recv_pp[k] > 0) {
      if (n_pp[k] == 0) {
        film[k] += recv_pp[k];
      } else {
        const int64_t per = distribution_give(recv_pp[k], prm.liq_pp.d_c) / n_pp[k];
        share_pp[k] += per;
        film[k] += recv_pp[k] - per * n_pp[k];
      }
    }
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      const int64_t h = recv_w[k * kNumWalls + w];
      if (h == 0) continue;
      const int64_t nb = n_pp[k] + n_w[k];
      if (nb == 0) {
        film[k] += h;
      } else {
        const int64_t per = distribution_give(h, prm.liq_pw[w].d_c) / nb;
        share_pp[k] += per;
        share_w[k] += per;
        film[k] += h - per * nb;
      }
    }
  }

  // Phase 1d: surviving bridges take both ends' shares; overflow back in proportion to the shares.
  for (PairSlot& s : L.pairs) {
    PairRecord& r = *s.rec;
    if (r.bridge == 0) continue;
    const int64_t a = share_pp[s.i], b = share_pp[s.j];
    r.bridge += a + b;
    const int64_t o = overflow_of(r.bridge, a + b, prm.liq_pp.v_max);
    if (o > 0) {
      const int64_t back_i = split_proportional(o, a, b, a, b);
      film[s.i] += back_i;
      film[s.j] += o - back_i;
      r.bridge -= o;
    }
  }
  for (size_t k = 0; k < n; ++k) {
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      WallRecord& r = wall[k * kNumWalls + w];
      if (r.bridge == 0 || share_w[k] == 0) continue;
      r.bridge += share_w[k];
      const int64_t o = overflow_of(r.bridge, share_w[k], prm.liq_pw[w].v_max);
      film[k] += o;
      r.bridge -= o;
    }
  }

  if (L.sinks) liquid_sinks(L);

  // Phase 2: flags and formations on the films after phase 1.
  std::vector<PairSlot*> form_pp;
  std::vector<size_t> form_w;  // k * kNumWalls + w
  std::vector<int64_t> forming(n, 0);
  for (PairSlot& s : L.pairs) {
    PairRecord& r = *s.rec;
    if (r.bridge > 0) continue;
    if (s.gap > 0.0) {
      r.flags &= ~kWas;  // separated without bridge: the next touch may form one
    } else if (!(r.flags & kWas) && prm.liq_pp.enabled) {
      r.flags |= kWas;
      if (film[s.i] + film[s.j] > prm.liq_pp.v_min) {
        form_pp.push_back(&s);
        ++forming[s.i];
        ++forming[s.j];
      }
    }
  }
  for (size_t k = 0; k < n; ++k) {
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      const size_t idx = k * kNumWalls + w;
      WallRecord& r = wall[idx];
      if (r.bridge > 0) continue;
      if (L.wall_gap[idx] > 0.0) {
        r.flags &= ~kWas;
      } else if (!(r.flags & kWas) && prm.liq_pw[w].enabled) {
        r.flags |= kWas;
        if (film[k] >= prm.liq_pw[w].v_min) {
          form_w.push_back(idx);
          ++forming[k];
        }
      }
    }
  }
  std::vector<int64_t> offer(n, 0), take(n, 0);
  for (size_t k = 0; k < n; ++k)
    if (forming[k] > 0) offer[k] = film[k] / forming[k];  // §5: V_f/k each, remainder stays in the film
  for (PairSlot* s : form_pp) {
    const int64_t oi = offer[s->i], oj = offer[s->j];
    const int64_t v = std::min(oi + oj, prm.liq_pp.v_max);
    if (v <= 0) continue;
    const int64_t part_i = split_proportional(v, oi, oj, oi, oj);
    take[s->i] += part_i;
    take[s->j] += v - part_i;
    s->rec->bridge = v;
    ++ev.formations;
  }
  for (size_t idx : form_w) {
    const size_t k = idx / kNumWalls;
    const int64_t v = std::min(offer[k], prm.liq_pw[idx % kNumWalls].v_max);
    if (v <= 0) continue;
    take[k] += v;
    wall[idx].bridge = v;
    ++ev.formations;
  }
  for (size_t k = 0; k < n; ++k) film[k] -= take[k];
  return ev;
}

namespace {
__extension__ typedef unsigned __int128 U128;
// floor(V F / 2^64), in 128-bit arithmetic.
int64_t fraction_of(int64_t V, uint64_t F) {
  if (V <= 0) return 0;
  return int64_t((U128(uint64_t(V)) * U128(F)) >> 64);
}
}  // namespace

void liquid_sinks(LiquidView& L) {
  const SimParams& prm = *L.prm;
  const LiquidSinkParams& sk = prm.sinks;
  std::vector<int64_t>& film = *L.film;
  const size_t n = film.size();
  if (sk.absorbs()) {
    const bool all = std::isinf(sk.absorption_rate);
    const uint64_t F = loss_fraction_q64(sk.absorption_rate * prm.dt);
    for (size_t k = 0; k < n; ++k) {
      const int64_t cap = pore_capacity_units(sk.pore_capacity, (*L.radius)[k], prm.liquid_unit_m3);
      const int64_t want = all ? film[k] : fraction_of(film[k], F);
      const int64_t moved = std::max<int64_t>(0, std::min(want, cap - (*L.pore)[k]));
      film[k] -= moved;
      (*L.pore)[k] += moved;
    }
  }
  if (sk.evaporates()) {
    const uint64_t F = loss_fraction_q64(prm.dt / sk.evaporation_time);
    std::vector<int64_t>& ev = *L.evaporated;
    for (size_t k = 0; k < n; ++k) {
      const int64_t d = fraction_of(film[k], F);
      film[k] -= d;
      ev[k] += d;
      for (uint32_t w = 0; w < kNumWalls; ++w) {
        int64_t& b = (*L.wall)[k * kNumWalls + w].bridge;
        const int64_t dw = fraction_of(b, F);
        b -= dw;
        ev[k] += dw;
      }
    }
    for (PairSlot& s : L.pairs) {
      const int64_t d = fraction_of(s.rec->bridge, F);
      s.rec->bridge -= d;
      ev[std::min(s.i, s.j)] += d;
    }
  }
}

// ---------------------------------------------------------------------------------------------------------
// Sequential rule (MercuryDPM order): events applied one contact at a time on the current volumes.
namespace {

struct Sequential {
  LiquidView& L;
  const SimParams& prm;
  std::vector<int64_t>& film;
  std::vector<WallRecord>& wall;
  std::vector<std::vector<PairSlot*>> adj;  // pairs of each particle
  EventCounts ev;

  explicit Sequential(LiquidView& view)
      : L(view), prm(*view.prm), film(*view.film), wall(*view.wall), adj(view.film->size()) {
    for (PairSlot& s : L.pairs) {
      adj[s.i].push_back(&s);
      adj[s.j].push_back(&s);
    }
  }

  // Particle x receives h with coefficient d_c, shared over its bridges holding liquid now (walls too when
  // walls_too), each capped (overflow to x's film); the remainder to x's film.
  void distribute(size_t x, int64_t h, double d_c, bool walls_too) {
    int64_t nb = 0;
    for (PairSlot* s : adj[x]) nb += s->rec->bridge > 0 ? 1 : 0;
    if (walls_too)
      for (uint32_t w = 0; w < kNumWalls; ++w) nb += wall[x * kNumWalls + w].bridge > 0 ? 1 : 0;
    if (nb == 0) {
      film[x] += h;
      return;
    }
    const int64_t per = distribution_give(h, d_c) / nb;
    film[x] += h - per * nb;
    if (per == 0) return;
    for (PairSlot* s : adj[x]) {
      int64_t& b = s->rec->bridge;
      if (b == 0) continue;
      b += per;
      const int64_t o = overflow_of(b, per, prm.liq_pp.v_max);
      b -= o;
      film[x] += o;
    }
    if (!walls_too) return;
    for (uint32_t w = 0; w < kNumWalls; ++w) {
      int64_t& b = wall[x * kNumWalls + w].bridge;
      if (b == 0) continue;
      b += per;
      const int64_t o = overflow_of(b, per, prm.liq_pw[w].v_max);
      b -= o;
      film[x] += o;
    }
  }

  void pair_event(PairSlot& s) {
    PairRecord& r = *s.rec;
    const double unit = prm.liquid_unit_m3;
    if (r.bridge > 0) {
      if (s.gap < rupture_gap(prm.liq_pp, r.bridge, unit)) return;
      const int64_t h_i = r.bridge / 2, h_j = r.bridge - h_i;
      r.bridge = 0;
      r.flags &= ~kWas;
      ++ev.ruptures;
      distribute(s.i, h_i, prm.liq_pp.d_c, false);
      distribute(s.j, h_j, prm.liq_pp.d_c, false);
      return;
    }
    if (s.gap > 0.0) {
      r.flags &= ~kWas;
    } else if (!(r.flags & kWas) && prm.liq_pp.enabled) {
      r.flags |= kWas;
      const int64_t fi = film[s.i], fj = film[s.j];
      if (fi + fj > prm.liq_pp.v_min) {
        const int64_t v = std::min(fi + fj, prm.liq_pp.v_max);
        if (v <= 0) return;
        const int64_t part_i = split_proportional(v, fi, fj, fi, fj);
        film[s.i] -= part_i;
        film[s.j] -= v - part_i;
        r.bridge = v;
        ++ev.formations;
      }
    }
  }

  void wall_event(size_t k, uint32_t w) {
    const size_t idx = k * kNumWalls + w;
    WallRecord& r = wall[idx];
    const LiquidParams& lp = prm.liq_pw[w];
    if (r.bridge > 0) {
      if (L.wall_gap[idx] < rupture_gap(lp, r.bridge, prm.liquid_unit_m3)) return;
      const int64_t h = r.bridge;
      r.bridge = 0;
      r.flags &= ~kWas;
      ++ev.ruptures;
      distribute(k, h, lp.d_c, true);
      return;
    }
    if (L.wall_gap[idx] > 0.0) {
      r.flags &= ~kWas;
    } else if (!(r.flags & kWas) && lp.enabled) {
      r.flags |= kWas;
      if (film[k] >= lp.v_min) {
        const int64_t v = std::min(film[k], lp.v_max);
        if (v <= 0) return;
        film[k] -= v;
        r.bridge = v;
        ++ev.formations;
      }
    }
  }
};

}  // namespace

EventCounts liquid_events_sequential(LiquidView& view) {
  Sequential seq(view);
  for (PairSlot& s : view.pairs) seq.pair_event(s);
  for (size_t k = 0; k < seq.film.size(); ++k)
    for (uint32_t w = 0; w < kNumWalls; ++w) seq.wall_event(k, w);
  return seq.ev;
}

}  // namespace wetdem::ref
