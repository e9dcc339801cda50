// The report paragraph's sentences on what a table is silent on (paragraph.cpp): the candidates it cannot
// show, and where each would (power.h); those it shows only when strong; and, after a `no_gap`, what its
// runs rule out (limits.h).
#include "diagnose/paragraph_silent.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "diagnose/effects.h"
#include "diagnose/limits.h"
#include "diagnose/power.h"

namespace wetdem::diagnose {

namespace {

// Where a candidate the table cannot see would show, from its runs beyond the table (power.h).
std::string beyond_clause(const Reach& x) {
  if (x.beyond_tried.empty()) return "";
  // The runs beyond the table are of the strongest strength only: the promise is for that strength, and a
  // weaker truth shifts less (the flowing viscous-weak twin, 0.03 Pa s: promised 4.0 σ at 0.1 Pa s, measured
  // 1.1 σ; docs/validation.md). In proportion to the strength (a small shift is linear in it) 3 σ needs
  // strongest × 3/z: said as an estimate where no weaker run was made.
  // When weaker strengths ran there too (run_beyond, beyond_weaker), what they measured replaces the
  // estimate: the weakest that reached kVisibleZ, and the strongest under it that fell short
  // (weaker_bracket).
  const std::string at = fmt::format("{} = {:.3g}", effect_spec(x.effect).strength, x.strongest);
  if (x.beyond_z >= kVisibleZ) {
    std::string weaker =
        fmt::format("a weaker one shifts less: in proportion to the strength, 3 σ there needs about {:.3g}",
                    x.strongest * kVisibleZ / x.beyond_z);
    if (!x.beyond_weaker.empty()) {
      std::string runs;
      for (const WeakerRun& w : x.beyond_weaker)
        runs += fmt::format("{}{:.3g} ({:.1f} σ)", runs.empty() ? "" : ", ", w.strength, w.z);
      const WeakerBracket b = weaker_bracket(x.strongest, x.beyond_z, x.beyond_weaker);
      weaker = b.below > 0 ? fmt::format(
                                 "a weaker one shifts less: run there on the same seeds at {}, so 3 σ there "
                                 "needs a strength between {:.3g} and {:.3g}",
                                 runs, b.below, b.from)
                           : fmt::format(
                                 "run there on the same seeds at {} as well: a truth from about {:.3g} "
                                 "shows there",
                                 runs, b.from);
    }
    return fmt::format(
        "; **to see it, measure {} at {}**, where {} of it at {} and of the model differ by "
        "{:.1f} σ ({})",
        x.beyond_observable, x.beyond_condition,
        x.beyond_seeds == 1 ? std::string("one run") : fmt::format("{} runs each", x.beyond_seeds), at,
        x.beyond_z, weaker);
  }
  if (x.beyond_repeats > 1)
    return fmt::format(
        ", nor at {} condition(s) beyond the table in one measurement, but {} at {} moves by more than the "
        "runs' own error ({:.1f} σ of one measurement at {}, {} each): **to see it, measure it there {} "
        "times** and enter the mean",
        x.beyond_tried.size(), x.beyond_observable, x.beyond_condition, x.beyond_z, at,
        x.beyond_seeds == 1 ? std::string("one run") : fmt::format("{} runs", x.beyond_seeds),
        x.beyond_repeats);
  return fmt::format(", nor at {} condition(s) beyond the table (at most {:.1f} σ: {} at {})",
                     x.beyond_tried.size(), x.beyond_z, x.beyond_observable, x.beyond_condition);
}

// Where a table without a gap rules a candidate out at a strength its reach calls unseen (limits.h), below
// `seen_from` (where the gap search would show it): the direct comparison is the sharper test, and the
// silence of the gap search holds only below it.
std::string directly_ruled_clause(const Report& r, const std::string& effect,
                                  double seen_from = std::numeric_limits<double>::infinity()) {
  // The reach ran the default shape: so is this limit (the free-shape one is in the limits sentence).
  const Limit* l = default_limit(r.limits, effect);
  if (l && l->ruled_out_from > 0 && l->ruled_out_from < seen_from)
    return fmt::format(" (set against its runs directly, the observations rule it out from {:.3g}: above)",
                       l->ruled_out_from);
  return "";
}

}  // namespace

// The candidates this table cannot show (power.h): what the verdict is silent on, where each comes closest,
// and where it would show.
std::string blind_sentence(const Report& r) {
  std::string list;
  size_t n = 0;
  for (const Reach& x : r.reach) {
    // A candidate named in a tie on its fresh runs' confirmation is said there (paragraph.cpp, tie_sentence).
    if (x.visible || std::find(r.confirmed_on_fresh.begin(), r.confirmed_on_fresh.end(), x.effect) !=
                         r.confirmed_on_fresh.end())
      continue;
    list += list.empty() ? "" : "; ";
    list += x.strongest <= 0
                ? fmt::format("`{}` (no probe of it could run)", x.effect)
                : fmt::format(
                      "`{}` moves no cell by more than {:.1f} σ and the whole table by a χ² of {:.0f} "
                      "(visible from {:.0f}) up to {} = {:.3g}{} (closest: {} at {}){}",
                      x.effect, x.max_z, std::max(0.0, x.chi2_excess), visible_chi2_excess(r.cells.size()),
                      effect_spec(x.effect).strength, x.strongest,
                      x.extension_stop.empty() || x.extension_stop == "reach_steps"
                          ? std::string()
                          : ", " + reach_stop_words(x.extension_stop),
                      r.cells[x.cell].observable, r.cell_condition[x.cell], beyond_clause(x)) +
                      directly_ruled_clause(r, x.effect);
    ++n;
  }
  if (n == 0) return "";
  return fmt::format(
      " **What this table cannot see:** {}. The verdict neither finds nor excludes {}; a measurement where "
      "{} would move by 3 σ or more is what could.",
      list, n == 1 ? "it" : "them", n == 1 ? "it" : "each");
}

// The candidates the table shows only past the file's strongest probe (power.h, extend_reach): the verdict's
// silence on each holds only below the strength from which it would have moved a cell.
std::string strong_only_sentence(const Report& r) {
  std::string list;
  for (const Reach& x : r.reach) {
    if (!(x.visible_from > 0) || x.strongest <= 0) continue;
    list += list.empty() ? "" : "; ";
    list += fmt::format(
        "`{}` moves no cell by 3 σ up to the strongest strength probed before, {} = {:.3g}, but does "
        "at {:.3g} ({:.1f} σ on {} at {}){}",
        x.effect, effect_spec(x.effect).strength, x.extended_from, x.visible_from, x.max_z,
        r.cells[x.cell].observable, r.cell_condition[x.cell],
        directly_ruled_clause(r, x.effect, x.visible_from));
  }
  if (list.empty()) return "";
  return fmt::format(
      " **Seen only when strong:** {}. Below that strength this table cannot tell it from the model, so "
      "the verdict neither finds nor excludes it there; stronger, it would have moved a cell.",
      list);
}

// What a table without a gap rules out (limits.h): each candidate's limit where its runs bracket one, and
// the visible ones the observations still allow at the strongest strength run. The unseen ones are the
// blind sentence's.
std::string limits_sentence(const Report& r) {
  std::string out, allowed;
  const std::vector<FreeShapeLimit> free = free_shape_limits(r.limits);
  for (const Limit& l : r.limits) {
    if (&l != default_limit(r.limits, l.effect)) continue;  // other shapes: in the free-shape clause
    const auto reach =
        std::find_if(r.reach.begin(), r.reach.end(), [&](const Reach& x) { return x.effect == l.effect; });
    const EffectSpec& e = effect_spec(l.effect);
    if (l.ruled_out_from > 0) {
      std::string under = "no weaker strength was run";
      if (l.allowed_to > 0)
        under = fmt::format("{:.3g} is allowed ({:+.1f}), so the limit lies between them, about {:.3g}",
                            l.allowed_to, l.allowed_delta, l.about);
      // A second parameter changes the fingerprint (a slow sink drains less within the run): the limit
      // holds at the shape its runs had, and with the shape free only as the profile over shapes says.
      const std::string at_shape =
          e.shape.empty() ? std::string() : fmt::format(" at {} = {:g}", e.shape, l.shape);
      std::string profile;
      const auto f = std::find_if(free.begin(), free.end(),
                                  [&](const FreeShapeLimit& x) { return x.effect == l.effect; });
      if (f != free.end())
        profile = "; " + free_shape_text(*f);
      else if (!e.shape.empty())
        profile = fmt::format("; other values of the {} were not run", e.shape);
      out += fmt::format("{}`{}` from {} = {:.3g}{} (Δχ² {:+.1f}; {}{})", out.empty() ? "" : "; ", l.effect,
                         e.strength, l.ruled_out_from, at_shape, l.ruled_delta, under, profile);
    } else if (reach != r.reach.end() && reach->visible && !l.runs.empty()) {
      allowed += fmt::format("{}`{}` ({:.3g}, Δχ² {:+.1f})", allowed.empty() ? "" : ", ", l.effect,
                             l.runs.back().strength, l.runs.back().delta);
    }
  }
  if (out.empty() && allowed.empty()) return "";
  const double t = r.limits.front().threshold;
  std::string s = fmt::format(
      " **What this table rules out**, each candidate's runs set against the observations directly (a "
      "sharper test than the search for a gap, where many small shifts add up; a strength whose runs they "
      "reject by Δχ² ≥ {:.1f}, a {:g} σ shift they do not show, and by {:g} × what seed noise alone gives): "
      "{}.",
      t, kVisibleZ, kRuleOutNoiseZ, out.empty() ? std::string("no candidate at any strength run") : out);
  if (!allowed.empty())
    s += fmt::format(
        " Still allowed at the strongest strength run: {}; the table can show such a shift, but these "
        "observations do not reject it.",
        allowed);
  return s;
}

}  // namespace wetdem::diagnose
