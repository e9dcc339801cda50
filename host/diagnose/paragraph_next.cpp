// The paragraph's sentences on the next measurement (paragraph_next.h): what a laboratory should measure,
// where, and how often, to separate a tie or to close an open interval.
#include "diagnose/paragraph_next.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "diagnose/effects.h"
#include "diagnose/next_bound.h"
#include "diagnose/next_experiment.h"
#include "diagnose/observables.h"

namespace wetdem::diagnose {

std::string assay_instrument(const std::string& observable) {
  const ObservableSpec* o = find_observable(observable);
  return o ? o->instrument : observable;
}

std::string next_sentence(const Report& r) {
  if (r.next.proposals.empty())
    return r.next.note.empty() ? "" : " No separating measurement was found: " + r.next.note + ".";
  std::string s;
  const Proposal& q = r.next.proposals.front();
  s += fmt::format(
      " **Next experiment:** measure `{}` at {}{}: the two fitted models differ there by {:.1f} σ (`{}` "
      "{:.4g} ± {:.2g}, `{}` {:.4g} ± {:.2g}, measurement noise {:.3g}{}).",
      q.observable, q.condition,
      q.assay
          ? fmt::format(" ({}an assay the table does not have: {})",
                        q.in_table ? "a condition of the table, with " : "", assay_instrument(q.observable))
      : q.in_table ? " (a condition of the table: measure it again, more precisely)"
                   : "",
      q.separation, r.next.effect_a, q.model_a, q.se_a, r.next.effect_b, q.model_b, q.se_b, q.sigma,
      q.seeds == 1 ? "; one seed each: no condition separated them by 2 σ on its first seed" : "");
  // What the verdict needs to decide the tie on fresh runs (needed_separation), at least kDecisive.
  const double needed = std::max(kDecisive, r.next.needed);
  const std::string needs =
      fmt::format("the verdict needs about {:.1f} σ (its tie rule on fresh runs{})", needed,
                  r.next.needed > kDecisive ? ", set by the model's own seed luck or scatter" : "");
  if (std::isfinite(q.refit_separation))
    s += fmt::format(
        " Once each re-fits its strength to the other's value there, {:.1f} σ remain{}.", q.refit_separation,
        q.refit_separation < needed ? "; " + needs + ": on its own this measurement may not decide" : "");
  const double single = judged_separation(q.refit_separation, q.separation);
  if (single < needed && r.next.repeats > 1)
    s += fmt::format(
        " Made **{} times** and entered as their mean (σ {:.3g}/√{}), it would reach the {:.1f} σ the "
        "verdict needs.",
        r.next.repeats, q.sigma, r.next.repeats, needed);
  if (!r.next.pairs.empty() && pair_beats_single(r.next.pairs.front(), q)) {
    const ProposalPair& w = r.next.pairs.front();
    s += fmt::format(
        " **Better, two measurements together:** `{}` at {} and `{}` at {}, {:.1f} σ after re-fit (more "
        "than the single one made twice, √2 × {:.1f}): one model can re-fit to either value, not to "
        "both{}.",
        w.first.observable, w.first.condition, w.second.observable, w.second.condition, w.refit_separation,
        single,
        w.refit_separation < needed
            ? fmt::format(
                  ". Even the pair is short of the {:.1f} σ the verdict needs: with more replicates the "
                  "seed luck, and so that need, falls",
                  needed)
            : fmt::format(", enough for the {:.1f} σ the verdict needs", needed));
  }
  // The assay on every sample, only when that is the stronger experiment.
  if (!r.next.series.empty() &&
      judged_separation(r.next.series.front().refit_separation, r.next.series.front().separation) > single) {
    const AssaySeries& a = r.next.series.front();
    const std::string how =
        std::isfinite(a.refit_separation)
            ? fmt::format("{:.1f} σ once each model re-fits to all of them", a.refit_separation)
            : fmt::format("{:.1f} σ", a.separation);
    s += a.observable == q.observable
             ? fmt::format(" Made on every sample of the table ({} conditions), it separates them by {}.",
                           a.conditions, how)
             : fmt::format(" The assay `{}` on every sample of the table separates them by {} together.",
                           a.observable, how);
  }
  return s;
}

// The measurement that would close the chosen effect's open interval (next_bound.h), when the stage ran.
std::string bound_sentence(const Report& r) {
  const BoundExperiment& b = r.bound;
  if (b.effect.empty() || b.proposals.empty()) return "";
  const std::string key = effect_spec(b.effect).strength;
  const Proposal& q = b.proposals.front();
  size_t beyond = 0;
  for (const Proposal& x : b.proposals) beyond += x.in_table ? 0 : 1;
  const std::string ends = fmt::format("{} = {:.3g} from {:.3g}", key, b.closed, b.open);
  if (const Proposal* k = q.separation < kDecisive ? repeated_bound(b) : nullptr) {
    const double after =
        std::fabs(k->model_a - k->model_b) /
        std::sqrt(k->sigma * k->sigma / double(k->repeats) + k->se_a * k->se_a + k->se_b * k->se_b);
    return fmt::format(
        " **To bound `{}`:** no single measurement tried (the table's own, and {} beyond it) tells {} by "
        "{:.0f} σ (the best: `{}` at {}, {:.1f} σ). Where the runs of the two ends differ by more than their "
        "own error, a repeated one does: measure `{}` at {}{} **{} times** and enter the mean (σ {:.3g}/√{} "
        "= {:.3g}); the ends then lie {:.1f} σ apart ({:.4g} ± {:.2g} against {:.4g} ± {:.2g}{}).",
        b.effect, beyond, ends, kDecisive, q.observable, q.condition, q.separation, k->observable,
        k->condition, k->in_table ? " (a condition of the table: make it again)" : "", k->repeats, k->sigma,
        k->repeats, k->sigma / std::sqrt(double(k->repeats)), after, k->model_a, k->se_a, k->model_b, k->se_b,
        k->seeds == 1 ? "; one seed each" : "");
  }
  if (q.separation < kDecisive)
    return fmt::format(
        " **`{}`'s {} stays open:** no measurement tried (the table's own, and {} beyond it) tells {} by "
        "{:.0f} σ (the best: `{}` at {}, {:.1f} σ); conditions further from these, or a direct measurement "
        "of the effect, would be needed to bound it.",
        b.effect, key, beyond, ends, kDecisive, q.observable, q.condition, q.separation);
  const std::string where = q.assay      ? fmt::format(" ({}an assay the table does not have: {})",
                                                  q.in_table ? "a condition of the table, with " : "",
                                                       assay_instrument(q.observable))
                            : q.in_table ? " (a condition of the table: measure it again, more precisely)"
                                         : "";
  return fmt::format(
      " **To bound `{}`:** the table cannot tell {} ({}); measure `{}` at {}{}: there they differ by {:.1f} "
      "σ ({:.4g} ± {:.2g} against {:.4g} ± {:.2g}, measurement noise {:.3g}{}), so one measurement would "
      "close the interval.",
      b.effect, ends,
      b.both    ? "any strength probed fits"
      : b.above ? "it is open above"
                : "it is open below",
      q.observable, q.condition, where, q.separation, q.model_a, q.se_a, q.model_b, q.se_b, q.sigma,
      q.seeds == 1 ? "; one seed each" : "");
}

}  // namespace wetdem::diagnose
