#include "diagnose/verdict.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "diagnose/where.h"

namespace wetdem::diagnose {

double noise_floor(const std::vector<double>& null_cells, const std::vector<CellGap>& gaps) {
  double sum = 0;
  size_t quiet = 0, finite = 0;
  for (size_t k = 0; k < null_cells.size() && k < gaps.size(); ++k) {
    if (!std::isfinite(null_cells[k])) continue;
    ++finite;
    if (gaps[k].significant) continue;
    sum += null_cells[k];
    ++quiet;
  }
  return quiet ? std::min(sum / double(quiet), 1.0) * double(finite) : 0.0;
}

bool passes_margin(double loco, const Verdict& v, const VerdictRule& rule) {
  const double floor = std::min(v.floor, v.null_loco);
  return loco <= floor + rule.ratio * (v.null_loco - floor) && v.null_loco - loco >= rule.min_drop;
}

double held_out_noise(const Candidate& a, const Candidate& b) {
  const size_t m = std::min(a.loco_draws.size(), b.loco_draws.size());
  if (m < 2) return 0.0;
  double mean = 0, ss = 0;
  for (size_t d = 0; d < m; ++d) {
    // Welford's running mean and sum of squares of the paired differences.
    const double x = b.loco_draws[d] - a.loco_draws[d], dm = x - mean;
    mean += dm / double(d + 1);
    ss += dm * (x - mean);
  }
  return std::sqrt(ss / double(m - 1));
}

double tie_order_evidence(double loco_a, double loco_b, double held_noise, double fresh_a, double fresh_b,
                          double luck, double* held_z, double* fresh_z) {
  if (!(held_noise > 0) || !(luck > 0)) return std::nan("");
  constexpr double kHalfPi = 1.57079632679489662;  // a normal's sd / its mean absolute deviation = √(π/2)
  const double h = (loco_b - loco_a) / held_noise, f = (fresh_a - fresh_b) / (luck * std::sqrt(kHalfPi));
  if (held_z) *held_z = h;
  if (fresh_z) *fresh_z = f;
  return f - h;
}

double tie_margin(const Candidate& a, const VerdictRule& rule) {
  const double n = double(std::max<size_t>(1, a.loco_cells.size()));
  return rule.tie_delta * std::max(1.0, a.loco / n);
}

bool clearly_worse(const Candidate& a, const Candidate& b, const VerdictRule& rule) {
  return b.loco - a.loco >= tie_margin(a, rule);
}

double near_tie_margin(const Candidate& a, const Candidate& b, const VerdictRule& rule) {
  return std::max(2.0 * tie_margin(a, rule), rule.tie_noise * held_out_noise(a, b));
}

bool near_tie(const Candidate& a, const Candidate& b, const VerdictRule& rule) {
  return b.loco - a.loco < near_tie_margin(a, b, rule);
}

double fresh_tie_margin(double chi2_a, size_t n, const VerdictRule& rule, double luck) {
  return std::max(rule.tie_delta * std::max(1.0, chi2_a / double(std::max<size_t>(1, n))), luck);
}

bool fresh_tie(double chi2_a, double chi2_b, size_t n, const VerdictRule& rule, double luck) {
  return chi2_b - chi2_a < fresh_tie_margin(chi2_a, n, rule, luck);
}

std::vector<size_t> ties_clearly_worse_on_fresh(double first, const std::vector<double>& tied, size_t n,
                                                const VerdictRule& rule, double luck) {
  std::vector<size_t> out;
  if (!std::isfinite(first)) return out;
  for (size_t i = 0; i < tied.size(); ++i)
    if (std::isfinite(tied[i]) && !fresh_tie(first, tied[i], n, rule, luck)) out.push_back(i);
  return out;
}

Verdict decide(const std::vector<Cell>& cells, const std::vector<std::vector<Prediction>>& baselines,
               const std::vector<Family>& families, const VerdictRule& rule) {
  if (baselines.empty()) throw std::invalid_argument("decide: one baseline per refit setting, at least one");
  Verdict v;
  v.null_loco_cells = loco_null_cells(cells, baselines);
  for (double x : v.null_loco_cells) v.null_loco += x;
  v.null_refit = fit_null_refit(cells, baselines);
  std::vector<double> null_se;  // of the model as calibrated, for the held-out scores that use it
  for (size_t k = 0; k < cells.size(); ++k)
    null_se.push_back(k < baselines.front().size() ? baselines.front()[k].se : std::nan(""));
  for (const Family& fam : families) {
    if (fam.ems.empty() || fam.refit_of.size() != fam.ems.size() || fam.shape_of.size() != fam.ems.size())
      throw std::invalid_argument("decide: candidate '" + fam.effect +
                                  "' needs one member index per emulator");
    Candidate c;
    c.effect = fam.effect;
    c.screen = fam.screen;
    std::vector<double> fold_strengths;
    c.loco_cells = loco_cells(cells, fam.ems, &fold_strengths,
                              rule.held_out == HeldOut::kLogDensity ? &null_se : nullptr);
    for (double x : c.loco_cells) c.loco += x;
    const ProfileFit f = fit_profile(cells, fam.ems);
    c.fit = f.fit;
    // The reported interval: the Δχ² interval profiled over the family's other members (shapes, refit
    // settings), widened by the jackknife over conditions and by the emulator's own noise (fit.h); the
    // member's probed range bounds the last two. The verdict and the runs the fit asks for do not use it.
    widen_by_profile(c.fit, cells, fam.ems, f.member);
    widen_by_condition_jackknife(c.fit, fold_strengths, fam.ems[f.member].u_lo(), fam.ems[f.member].u_hi());
    widen_by_emulator_noise(c.fit, cells, fam.ems[f.member]);
    set_two_se_interval(c.fit, fam.ems[f.member].u_lo(), fam.ems[f.member].u_hi());
    c.member = f.member;
    c.refit = fam.refit_of[f.member];
    c.shape = fam.shape_of[f.member];
    v.ranking.push_back(c);
  }
  std::stable_sort(v.ranking.begin(), v.ranking.end(),
                   [](const Candidate& a, const Candidate& b) { return a.loco < b.loco; });
  const std::vector<CellGap> g = where(cells, baselines.front(), rule.q);
  const bool any = has_gap(g, rule.table_level);
  v.floor = noise_floor(v.null_loco_cells, g);
  const auto passes = [&](const Candidate& c) { return passes_margin(c.loco, v, rule); };
  // The held-out scores' noise (VerdictRule::tie_noise), for the candidates it can make near ties: the best
  // and every candidate that passes the effect margin (any of them may be named first later).
  if (rule.tie_noise > 0 && rule.tie_draws >= 2 && !v.ranking.empty()) {
    const auto anchors = anchor_draws(size_t(rule.tie_draws), baselines.size(), cells.size(), 20261129);
    for (size_t i = 0; i < v.ranking.size(); ++i) {
      Candidate& c = v.ranking[i];
      if (i > 0 && !passes(c)) continue;
      const Family& fam = *std::find_if(families.begin(), families.end(),
                                        [&](const Family& f) { return f.effect == c.effect; });
      uint64_t seed = 1469598103934665603ull;  // FNV-1a of the name: each candidate's own probe draws
      for (unsigned char ch : c.effect) seed = (seed ^ ch) * 1099511628211ull;
      c.loco_draws = loco_draws(cells, fam.ems, fam.refit_of, anchors, seed,
                                rule.held_out == HeldOut::kLogDensity ? &null_se : nullptr);
    }
  }
  if (!v.ranking.empty()) choose(v, v.ranking.front().effect);
  v.effect.clear();  // chosen only once the rule below says so
  // With refit, a gap the null closes at its re-fitted setting (no cell significant there, by the same rule)
  // needs no effect: the analogue of no_gap for the re-fitted model.
  const auto closed = [&] {
    if (baselines.size() < 2 || v.null_refit == 0) return false;
    return !has_gap(where(cells, baselines[v.null_refit], rule.q), rule.table_level);
  };
  if (!any) {
    v.kind = "no_gap";
  } else if (closed()) {
    v.kind = "refit";
  } else if (!v.ranking.empty() && passes(v.ranking.front())) {
    v.kind = "effect";
    v.effect = v.ranking.front().effect;
    for (size_t i = 1; i < v.ranking.size(); ++i)
      if (passes(v.ranking[i]) && !clearly_worse(v.ranking.front(), v.ranking[i], rule))
        v.tied.push_back(v.ranking[i].effect);
  } else {
    v.kind = "unexplained";
  }
  return v;
}

Verdict decide(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
               const std::vector<Response>& responses, const std::vector<double>& screens,
               const VerdictRule& rule) {
  if (screens.size() != responses.size())
    throw std::invalid_argument("decide: one screen score per response");
  std::vector<Family> fams;
  for (size_t i = 0; i < responses.size(); ++i)
    fams.push_back({responses[i].effect, screens[i], {Emulator(baseline, responses[i])}, {0}, {0}});
  return decide(cells, std::vector<std::vector<Prediction>>{baseline}, fams, rule);
}

namespace {
bool in(const std::vector<std::string>& list, const std::string& e) {
  return std::find(list.begin(), list.end(), e) != list.end();
}
}  // namespace

void choose(Verdict& v, std::string effect) {
  const auto it = std::find_if(v.ranking.begin(), v.ranking.end(),
                               [&](const Candidate& c) { return c.effect == effect; });
  if (it == v.ranking.end()) return;
  std::rotate(v.ranking.begin(), it, it + 1);
  v.effect = std::move(effect);
  const double loco = v.ranking.front().loco, excess = v.null_loco - std::min(v.floor, v.null_loco);
  v.held_out_shrink = v.null_loco > 0 ? 1.0 - loco / v.null_loco : 0.0;
  v.held_out_gap_shrink = excess > 0 ? (v.null_loco - loco) / excess : 0.0;
}

std::vector<std::string> name_only_seen(Verdict& v, const std::vector<std::string>& unseen,
                                        const std::vector<std::string>& rejected, const VerdictRule& rule) {
  std::vector<std::string> notes;
  if (v.kind != "effect" || v.ranking.empty()) return notes;
  const auto passes = [&](const Candidate& c) { return passes_margin(c.loco, v, rule); };
  const auto chosen = std::find_if(v.ranking.begin(), v.ranking.end(), [&](const Candidate& c) {
    return passes(c) && !in(unseen, c.effect) && !in(rejected, c.effect);
  });
  if (chosen == v.ranking.end()) {
    for (const Candidate& c : v.ranking)
      if (passes(c))
        notes.push_back(fmt::format(
            "verdict: `{}` passes the held-out rule ({:.1f} against the null's {:.1f}), but its probes "
            "cannot show it apart from noise{}: with no candidate the table can see beside it, the verdict "
            "is unexplained",
            c.effect, c.loco, v.null_loco, in(rejected, c.effect) ? " and fresh runs did not keep it" : ""));
    v.kind = "unexplained";
    v.effect.clear();
    v.tied.clear();
    return notes;
  }
  if (chosen != v.ranking.begin())
    notes.push_back(fmt::format(
        "verdict: `{}` is named first though `{}` scores better held out ({:.1f} against {:.1f}): the probes "
        "cannot show `{}` apart from noise",
        chosen->effect, v.ranking.front().effect, chosen->loco, v.ranking.front().loco,
        v.ranking.front().effect));
  choose(v, chosen->effect);
  const Candidate& c = v.ranking.front();
  v.tied.clear();
  for (size_t i = 1; i < v.ranking.size(); ++i) {
    const Candidate& o = v.ranking[i];
    if (!passes(o) || clearly_worse(c, o, rule) || in(rejected, o.effect)) continue;
    v.tied.push_back(o.effect);
    if (in(unseen, o.effect))
      notes.push_back(fmt::format(
          "verdict: `{}` is tied with `{}` on its held-out score ({:.1f} against {:.1f}) though its probes "
          "cannot show it apart from noise; fresh runs at its fitted strength decide it",
          o.effect, c.effect, o.loco, c.loco));
  }
  return notes;
}

FreshJudgement unseen_on_fresh(double chi2_chosen, double chi2_unseen, size_t n, const VerdictRule& rule,
                               double luck) {
  const auto margin = [&](double best) {
    return std::max(rule.tie_delta * std::max(1.0, best / double(std::max<size_t>(1, n))), luck);
  };
  if (chi2_unseen - chi2_chosen >= margin(chi2_chosen)) return FreshJudgement::kDrop;
  if (chi2_chosen - chi2_unseen >= margin(chi2_unseen)) return FreshJudgement::kSwap;
  return FreshJudgement::kKeep;
}

FreshJudgement seen_on_fresh(const Candidate& chosen, const Candidate& other, double chi2_chosen,
                             double chi2_other, size_t n, const VerdictRule& rule, double luck) {
  const FreshJudgement j = unseen_on_fresh(chi2_chosen, chi2_other, n, rule, luck);
  if (j == FreshJudgement::kKeep && other.loco < chosen.loco) return FreshJudgement::kSwap;
  return j;
}

bool stays_tied(const Candidate& first, const Candidate& c, double chi2_first, double chi2_c, size_t n,
                const VerdictRule& rule, double luck) {
  return !clearly_worse(first, c, rule) || fresh_tie(chi2_first, chi2_c, n, rule, luck);
}

bool fresh_confirms(double chi2_before, double chi2_fresh, const VerdictRule& rule, double luck) {
  return chi2_fresh <= chi2_before - std::max(rule.min_drop, luck);
}

size_t confirmed_instead(double chi2_before, const std::vector<double>& fresh_chi2,
                         const std::vector<bool>& eligible, const VerdictRule& rule, double luck) {
  if (eligible.size() != fresh_chi2.size())
    throw std::invalid_argument("confirmed_instead: one flag per fresh check");
  size_t best = kNone;
  for (size_t i = 1; i < fresh_chi2.size(); ++i) {
    const double x = fresh_chi2[i];
    if (!eligible[i] || !std::isfinite(x) || !fresh_confirms(chi2_before, x, rule, luck)) continue;
    if (best == kNone || x < fresh_chi2[best]) best = i;
  }
  return best;
}

size_t best_fresh_round(const std::vector<double>& round_chi2, double last_chi2, double margin) {
  size_t pick = kNone;
  for (size_t i = 0; i < round_chi2.size(); ++i)
    if (std::isfinite(round_chi2[i]) && (pick == kNone || round_chi2[i] < round_chi2[pick])) pick = i;
  if (pick == kNone || !std::isfinite(last_chi2)) return pick;
  return round_chi2[pick] < last_chi2 - std::max(0.0, margin) ? pick : kNone;
}

size_t closer_fresh_round(const std::vector<FreshOutcome>& rounds, const FreshOutcome& last) {
  if (!std::isfinite(last.chi2)) return kNone;  // best_fresh_round already restores any round that ran
  size_t pick = kNone;
  for (size_t i = 0; i < rounds.size(); ++i) {
    const FreshOutcome& r = rounds[i];
    if (!std::isfinite(r.chi2) || !(r.chi2 < last.chi2) || r.confirms != last.confirms || r.gap != last.gap)
      continue;
    if (pick == kNone || r.chi2 < rounds[pick].chi2) pick = i;
  }
  return pick;
}

std::vector<double> widen_to_fresh_ties(double& lo, double& hi, double kept_chi2,
                                        const std::vector<std::pair<double, double>>& others, double margin) {
  std::vector<double> reached;
  if (!std::isfinite(kept_chi2)) return reached;
  for (const auto& [strength, chi2] : others) {
    if (!std::isfinite(chi2) || chi2 > kept_chi2 + std::max(0.0, margin)) continue;
    if (strength >= lo && strength <= hi) continue;
    lo = std::min(lo, strength);
    hi = std::max(hi, strength);
    reached.push_back(strength);
  }
  return reached;
}

void settle_verdict(Verdict& v, const std::vector<CellGap>& after, const VerdictRule& rule) {
  if (v.kind != "effect") return;
  if (has_gap(after, rule.table_level)) v.kind = "partial";
}

void hold_by_luck(Verdict& v, const std::string& effect) {
  if (std::find(v.held_by_luck.begin(), v.held_by_luck.end(), effect) == v.held_by_luck.end())
    v.held_by_luck.push_back(effect);
}

}  // namespace wetdem::diagnose
