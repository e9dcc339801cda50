#include "diagnose/fit_stage.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "diagnose/fit.h"
#include "diagnose/verdict.h"
#include "diagnose/where.h"

namespace wetdem::diagnose {

namespace {

// The strongest strength the fit may reach: the physical limit, or below the cut where runs failed or cost
// too much (a margin of 1.3 under the strength that could not run).
double searchable_hi(const CandidateRuns& c, const EffectSpec& spec) {
  return std::isfinite(c.cut) ? std::min(spec.phys_hi, c.cut / 1.3) : spec.phys_hi;
}

// A run the stage has asked for: candidate c at member (refit j, shape m), strength s.
struct Knot {
  size_t c = 0, j = 0, m = 0;
  double s = 0.0;
  std::string why;  // "probe", "refine", "extend", "shape", "between", "bracket"
};

struct Stage {
  Procedure& p;
  std::vector<CandidateRuns>& cands;
  std::vector<Knot> pending;
  std::vector<int> refined, extended, members_extended, shapes_between;  // per candidate: rounds spent
  std::vector<std::map<size_t, int>> between_extended;         // per candidate: shape index -> its extensions
  std::vector<std::set<std::pair<size_t, size_t>>> bracketed;  // per candidate: members (j, m) bracketed

  Variant variant_of(const Knot& k) const {
    const CandidateRuns& c = cands[k.c];
    return p.variant(c.effect, k.s, k.j, c.shapes[k.m]);
  }

  // A strength at or above the cut cannot run: the candidate's range ends there.
  void cut(CandidateRuns& c, double s, const std::string& why) {
    if (s < c.cut) c.cut = s;
    c.notes.push_back(fmt::format("range cut at {:.3g}: {}", s, why));
    p.notes.push_back(fmt::format("{}: range cut at {:.3g}: {}", c.effect, s, why));
    for (Response& r : c.members)
      while (!r.strengths.empty() && r.strengths.back() >= c.cut) drop_knot(r, r.strengths.back());
  }

  void want(const Knot& k) {
    CandidateRuns& c = cands[k.c];
    if (k.s >= c.cut) return;
    for (double s : c.member(k.j, k.m).strengths)
      if (std::fabs(std::log(s / k.s)) < 1e-9) return;  // already a knot
    const Variant v = variant_of(k);
    if (const std::string why = p.failure(v, p.probe_seeds); !why.empty())
      return cut(c, k.s, "run failed: " + why);
    if (const std::string why = p.want(v, p.probe_seeds); !why.empty()) return cut(c, k.s, why);
    pending.push_back(k);
  }

  // Runs what is pending and adds the knots that completed.
  void collect() {
    if (pending.empty()) return;
    p.run();
    for (const Knot& k : pending) {
      CandidateRuns& c = cands[k.c];
      const Variant v = variant_of(k);
      if (const std::string why = p.failure(v, p.probe_seeds); !why.empty()) {
        cut(c, k.s, "run failed: " + why);
        continue;
      }
      if (k.s >= c.cut) continue;
      add_knot(c.member(k.j, k.m), k.s, p.probe(v, k.j));
      if (k.why == "between")
        c.notes.push_back(
            fmt::format("shape {:.3g} added between the listed shapes, at {:.3g}", c.shapes[k.m], k.s));
      if (k.why == "bracket")
        c.notes.push_back(
            fmt::format("bracketed at {:.3g}{}", k.s,
                        std::isnan(c.shapes[k.m]) ? "" : fmt::format(", shape {:.3g}", c.shapes[k.m])));
      if (k.why == "extend" || k.why == "shape")
        c.notes.push_back(
            fmt::format("{} {:.3g}{}", k.why == "extend" ? "range extended to" : "shape added at", k.s,
                        std::isnan(c.shapes[k.m]) ? "" : fmt::format(", shape {:.3g}", c.shapes[k.m])));
    }
    pending.clear();
  }

  // The next run candidate c asks for, or false when its fit is settled.
  bool ask(size_t ci, int max_rounds_left) {
    CandidateRuns& c = cands[ci];
    const EffectSpec& spec = effect_spec(c.effect);
    const Family fam = c.family(p.baselines);
    if (fam.ems.empty() || max_rounds_left <= 0) return false;
    const ProfileFit pf = fit_profile(p.tab.cells, fam.ems);
    const size_t j = fam.refit_of[pf.member], m = fam.shape_of[pf.member];
    const StrengthFit& f = pf.fit;
    // Runs are spent only on a candidate that explains something: its fit beats the null at its setting.
    if (!(f.chi2 < chi2(p.tab.cells, p.baselines[j]) - 1.0)) return false;
    const Response& r = c.member(j, m);
    const double hi = searchable_hi(c, spec);
    // 0. The best member probed at one strength only (a shape added in steps 2 or 4): a knot on each side
    // (fit.h, one_knot_bracket), once per member and whatever the `extend` allowance, since an interval may
    // not be reported as a point at the edge (issue 18, 3b).
    if (bracketed[ci].insert({j, m}).second) {
      const auto it = p.d.probes.find(c.effect);
      const std::vector<double> b = one_knot_bracket(
          r, probe_step(it != p.d.probes.end() ? it->second : spec.probes), spec.phys_lo, hi);
      for (double s : b) want({ci, j, m, s, "bracket"});
      if (!b.empty()) return true;
    }
    // 1. An edge of the probed range: extend within the physical range and below the cut.
    int limit = 0;
    const double edge = next_edge_knot(f, r, spec.phys_lo, hi, &limit);
    if (edge > 0 && extended[ci] < p.d.extend) {
      ++extended[ci];
      want({ci, j, m, edge, "extend"});
      return true;
    }
    c.at_limit = edge > 0 ? 0 : limit;
    // 2. An end of the shapes (the second parameter): a shape one step further at the fitted strength.
    if (c.shapes.size() > 1 && extended[ci] < p.d.extend) {
      const double v = c.shapes[m];
      const auto [lo_it, hi_it] = std::minmax_element(c.shapes.begin(), c.shapes.end());
      double step = 10.0;
      std::vector<double> sorted = c.shapes;
      std::sort(sorted.begin(), sorted.end());
      for (size_t i = 1; i < sorted.size(); ++i) step = std::min(step, sorted[i] / sorted[i - 1]);
      double next = 0;
      if (v == *hi_it && v * step <= spec.shape_hi) next = v * step;
      if (v == *lo_it && v / step >= spec.shape_lo) next = v / step;
      if (next > 0) {
        ++extended[ci];
        c.shapes.push_back(std::stod(fmt::format("{:.3g}", next)));
        want({ci, j, c.shapes.size() - 1, std::stod(fmt::format("{:.3g}", f.strength)), "shape"});
        return true;
      }
    }
    // 3. Another member whose own fit runs into an edge of its knots (a shape probed at one strength): extend
    // it, so that the profile compares every shape at its own best strength, not at the strength that suited
    // the default shape (fit.h, next_member_edge). A shape added between the listed ones (step 4) has its own
    // allowance, so that the listed shapes' extensions do not leave it at its one knot.
    {
      std::vector<const Response*> rs;
      bool any = false;
      for (size_t i = 0; i < fam.ems.size(); ++i) {
        const size_t m_i = fam.shape_of[i];
        const bool between = between_extended[ci].count(m_i) > 0;
        const bool open =
            between ? between_extended[ci].at(m_i) < p.d.extend : members_extended[ci] < p.d.extend;
        rs.push_back(open ? &c.member(fam.refit_of[i], m_i) : nullptr);
        any = any || open;
      }
      const MemberEdge e =
          any ? next_member_edge(p.tab.cells, fam.ems, rs, pf.member, spec.phys_lo, hi) : MemberEdge{};
      if (e.member != MemberEdge::npos) {
        const size_t m_e = fam.shape_of[e.member];
        ++(between_extended[ci].count(m_e) ? between_extended[ci].at(m_e) : members_extended[ci]);
        want({ci, fam.refit_of[e.member], m_e, e.strength, "extend"});
        return true;
      }
    }
    // 4. Between the shapes: the best listed shape leaves the table unexplained, in sample or held out, and
    // the response may bend between it and its neighbours (fit.h, next_shapes_between): the middle shapes on
    // both sides, at the fitted strength; step 3 then takes each to its own best strength, and step 5
    // refines there once it is the best.
    if (c.shapes.size() > 1 && shapes_between[ci] < p.d.refine) {
      std::vector<double> shape_of;
      for (size_t i = 0; i < fam.ems.size(); ++i) shape_of.push_back(c.shapes[fam.shape_of[i]]);
      const double level = p.d.rule.table_level > 0 ? p.d.rule.table_level : 0.01;
      bool added = false;
      for (double mid : next_shapes_between(p.tab.cells, fam.ems, shape_of, pf.member,
                                            chi2_upper_point(p.tab.cells.size(), level))) {
        if (mid < spec.shape_lo || mid > spec.shape_hi) continue;
        c.shapes.push_back(mid);
        between_extended[ci][c.shapes.size() - 1] = 0;
        want({ci, j, c.shapes.size() - 1, std::stod(fmt::format("{:.3g}", f.strength)), "between"});
        added = true;
      }
      if (added) {
        ++shapes_between[ci];
        return true;
      }
    }
    // 5. Refinement: a knot at the fitted strength.
    if (refined[ci] < p.d.refine) {
      if (const double s = next_knot(p.tab.cells, p.baselines[j], r); s > 0) {
        ++refined[ci];
        want({ci, j, m, s, "refine"});
        return true;
      }
    }
    return false;
  }
};

}  // namespace

void set_limit_notes(CandidateRuns& c) {
  static const std::string kPrefix = "the fit runs into the ";
  c.notes.erase(std::remove_if(c.notes.begin(), c.notes.end(),
                               [](const std::string& n) { return n.rfind(kPrefix, 0) == 0; }),
                c.notes.end());
  const double phys_hi = effect_spec(c.effect).phys_hi;
  if (c.at_limit > 0 && std::isfinite(c.cut) && c.cut / 1.3 < phys_hi)
    c.notes.push_back(fmt::format("{}cut range (runs at {:.3g} could not be made)", kPrefix, c.cut));
  else if (c.at_limit > 0)
    c.notes.push_back(fmt::format("{}upper end of the physical range ({:g})", kPrefix, phys_hi));
  if (c.at_limit < 0)
    c.notes.push_back(
        fmt::format("{}lower end of the range searched ({:g})", kPrefix, effect_spec(c.effect).phys_lo));
}

void settle_limit(CandidateRuns& c, const Candidate& fitted) {
  const EffectSpec& spec = effect_spec(c.effect);
  const double hi = searchable_hi(c, spec);
  int limit = 0;
  const double edge =
      next_edge_knot(fitted.fit, c.member(fitted.refit, fitted.shape), spec.phys_lo, hi, &limit);
  c.at_limit = edge > 0 ? 0 : limit;
  set_limit_notes(c);
}

std::vector<Screened> widened_candidates(const std::vector<Screened>& screened,
                                         const std::vector<std::string>& fitted, size_t screen_top) {
  std::vector<Screened> add;
  for (const Screened& s : screened) {
    if (s.strength <= 0 || std::find(fitted.begin(), fitted.end(), s.effect) != fitted.end()) continue;
    if (s.score <= 0 || add.size() >= screen_top) break;  // best first: the rest move the model away
    add.push_back(s);
  }
  return add;
}

size_t widened_top(const std::vector<Screened>& screened, const std::vector<std::string>& fitted,
                   size_t screen_top) {
  const size_t add = widened_candidates(screened, fitted, screen_top).size();
  return add > 0 ? fitted.size() + add : 0;
}

void run_fit(Procedure& p) {
  run_fit(p, p.d.screen_top);
}

void run_fit(Procedure& p, size_t top) {
  std::vector<CandidateRuns> cands;
  for (const Screened& s : p.screened) {
    if (cands.size() >= top) break;
    if (s.strength <= 0) continue;  // no probe could run
    CandidateRuns c;
    c.effect = s.effect;
    c.screen = s.score;
    c.shapes = p.d.shapes.count(s.effect) ? p.d.shapes.at(s.effect) : std::vector<double>{NAN};
    cands.push_back(c);
  }
  // The baselines of the refit settings, then every probe strength at the default shape, at every setting.
  for (size_t j = 1; j < p.settings.size(); ++j)
    if (const std::string why = p.want(p.variant("", 0, j), p.base_seeds); !why.empty())
      throw std::runtime_error("refit setting " + p.settings[j].label + ": " + why);
  Stage st{p,
           cands,
           {},
           std::vector<int>(cands.size(), 0),
           std::vector<int>(cands.size(), 0),
           std::vector<int>(cands.size(), 0),
           std::vector<int>(cands.size(), 0),
           std::vector<std::map<size_t, int>>(cands.size()),
           std::vector<std::set<std::pair<size_t, size_t>>>(cands.size())};
  for (size_t ci = 0; ci < cands.size(); ++ci) {
    const size_t m0 = cands[ci].shapes.size() / 2;
    for (double s : p.d.probes.at(cands[ci].effect))
      for (size_t j = 0; j < p.settings.size(); ++j) st.want({ci, j, m0, s, "probe"});
  }
  p.run();
  for (size_t j = p.baselines.size(); j < p.settings.size(); ++j) {  // once: a widened fit has them
    const Variant b = p.variant("", 0, j);
    if (const std::string why = p.failure(b, p.base_seeds); !why.empty())
      throw std::runtime_error("the model at refit setting " + p.settings[j].label + " failed: " + why);
    p.baselines.push_back(p.predict(b, p.base_seeds));
    p.seed1.push_back(p.predict(b, p.probe_seeds));
  }
  st.collect();
  // The other shapes at the strength fitted at the default shape (a profile over the second parameter).
  for (size_t ci = 0; ci < cands.size(); ++ci) {
    CandidateRuns& c = cands[ci];
    if (c.shapes.size() < 2) continue;
    const Family fam = c.family(p.baselines);
    if (fam.ems.empty()) continue;
    const ProfileFit pf = fit_profile(p.tab.cells, fam.ems);
    const double s = std::stod(fmt::format("{:.3g}", pf.fit.strength));
    for (size_t m = 0; m < c.shapes.size(); ++m)
      if (m != c.shapes.size() / 2) st.want({ci, fam.refit_of[pf.member], m, s, "shape"});
  }
  st.collect();
  // Rounds: each candidate in contention asks for at most one run per round; the rounds' runs go together.
  // In contention: the best by held-out score, and every candidate that passes the effect margin against the
  // null or is not clearly worse than the best (verdict.h): the runs go where they can change the verdict.
  // refine: strengths and shapes between (two a round); extend: ends, members, each shape between
  const int rounds = 2 * p.d.refine + (3 + 2 * p.d.refine) * p.d.extend + 2;
  for (int round = 0; round < rounds; ++round) {
    std::vector<Family> fams;
    std::vector<size_t> of;
    for (size_t ci = 0; ci < cands.size(); ++ci)
      if (Family f = cands[ci].family(p.baselines); !f.ems.empty()) fams.push_back(f), of.push_back(ci);
    if (fams.empty()) break;
    // The rounds read passes_margin and clearly_worse only: the held-out noise (tie_noise), which only
    // near_tie reads, is not drawn here (it costs 32 re-fits of every passing candidate per round).
    VerdictRule rule = p.d.rule;
    rule.tie_noise = 0.0;
    const Verdict v = decide(p.tab.cells, p.baselines, fams, rule);
    std::vector<bool> contend(cands.size(), false);
    for (size_t r = 0; r < v.ranking.size(); ++r) {
      const Candidate& c = v.ranking[r];
      const bool passes = passes_margin(c.loco, v, p.d.rule);
      const bool close = !clearly_worse(v.ranking.front(), c, p.d.rule);
      for (size_t i = 0; i < fams.size(); ++i)
        if (fams[i].effect == c.effect) contend[of[i]] = r == 0 || passes || close;
    }
    bool any = false;
    for (size_t ci = 0; ci < cands.size(); ++ci)
      if (contend[ci]) any = st.ask(ci, rounds - round) || any;
    if (!any) break;
    st.collect();
  }
  for (CandidateRuns& c : cands) set_limit_notes(c);
  p.fitted = cands;
}

}  // namespace wetdem::diagnose
