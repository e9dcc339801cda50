// Shrink (step 6), the candidates decided on their fresh runs rather than their probes: an unseen tie that
// its fresh runs show or leave clearly worse, an unseen lead that alone passes the held-out rule, and a tie
// named in place of a chosen effect whose fresh runs do not confirm it; and the order of a tie of seen
// candidates, where the held-out score and the fresh runs lean opposite ways, weighed each by its noise. The
// fresh runs carry no probe's seed noise and no emulator, so where they and the held-out score disagree,
// they decide, or, within a tie, weigh in (diagnosis.md, "Verdicts").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "diagnose/power.h"
#include "diagnose/shrink_steps.h"

namespace wetdem::diagnose::shrink_steps {

namespace {

// Names p.fresh[i] first: the former first stays tied unless its fresh runs are clearly worse
// (unseen_on_fresh, the luck included). The other tied candidates were tied with the former first; against
// the new one each stays tied unless it is clearly worse both held out (clearly_worse) and on fresh runs
// (fresh_tie, the luck included); those dropped go into `gone` (their fresh checks leave p.fresh after the
// caller's loop). The fresh checks follow the order.
void swap_first(Procedure& p, size_t i, std::vector<std::string>& gone) {
  const FreshCheck chosen = p.fresh.front(), f = p.fresh[i];
  const size_t n = p.tab.cells.size();
  const double luck = p.verdict.seed_luck, a = chi2_of(f.gaps_after);
  std::vector<std::string>& tied = p.verdict.tied;
  tied.erase(std::find(tied.begin(), tied.end(), f.effect));
  choose(p.verdict, f.effect);
  std::rotate(p.fresh.begin(), p.fresh.begin() + long(i), p.fresh.begin() + long(i) + 1);
  const Candidate* first = ranked(p, f.effect);
  for (const FreshCheck& t : p.fresh) {
    const Candidate* c = ranked(p, t.effect);
    if (t.effect == f.effect || t.effect == chosen.effect || !listed(tied, t.effect) || !first || !c ||
        t.after.empty() || stays_tied(*first, *c, a, chi2_of(t.gaps_after), n, p.d.rule, luck))
      continue;
    tied.erase(std::find(tied.begin(), tied.end(), t.effect));
    gone.push_back(t.effect);
    p.notes.push_back(fmt::format(
        "shrink: {} is no longer tied with {} named first: held-out χ² {:.1f} against {:.1f}, and on fresh "
        "runs {:.1f} against {:.1f}, clearly worse on both",
        t.effect, f.effect, c->loco, first->loco, chi2_of(t.gaps_after), a));
  }
  // The former first is now at index 1; the others keep their order.
  if (unseen_on_fresh(a, chi2_of(chosen.gaps_after), n, p.d.rule, luck) != FreshJudgement::kDrop)
    tied.insert(tied.begin(), chosen.effect);
}

// An unseen candidate tied held out whose fresh runs show it against the control (shows(fresh_shift)): the
// table sees it after all, so its held-out score counts as any seen candidate's (name_only_seen would have
// ranked it by that score). Named first when that score is the best and its fresh runs are not clearly worse
// than the chosen one's; dropped when they are; otherwise it stays tied. a, b: the fresh χ² of the chosen
// one and of it.
void see_on_fresh(Procedure& p, size_t i, const Shift& sh, double a, double b,
                  std::vector<std::string>& gone) {
  const FreshCheck f = p.fresh[i], chosen = p.fresh.front();
  const double luck = p.verdict.seed_luck;
  p.unseen.erase(std::find(p.unseen.begin(), p.unseen.end(), f.effect));
  p.seen_on_fresh.push_back(f.effect);
  p.notes.push_back(fmt::format(
      "shrink: {} is seen on its fresh runs: at {:.3g} they move {} at {} by {:.1f} σ and the table's χ² "
      "by {:.1f} against the model without it on the same seeds (visible from {} σ or {:.1f}); its probes "
      "alone could not show it, so its held-out score now counts as any seen candidate's",
      f.effect, f.strength, p.tab.cells[sh.cell].observable,
      p.tab.conditions[p.tab.cell_condition[sh.cell]].label, sh.max_z, sh.chi2_excess, kVisibleZ,
      visible_chi2_excess(p.tab.cells.size())));
  const Candidate *cf = ranked(p, f.effect), *cc = ranked(p, chosen.effect);
  if (!cf || !cc) return;
  const FreshJudgement j = seen_on_fresh(*cc, *cf, a, b, p.tab.cells.size(), p.d.rule, luck);
  if (j == FreshJudgement::kDrop) {
    p.verdict.tied.erase(std::find(p.verdict.tied.begin(), p.verdict.tied.end(), f.effect));
    p.unseen_rejected.push_back(f.effect);
    p.notes.push_back(fmt::format(
        "shrink: {} gives χ² {:.1f} on fresh runs at {:.3g} against {:.1f} for {}: worse by more than the "
        "tie margin and the model's own seed luck ({:.1f}); not named",
        f.effect, b, f.strength, a, chosen.effect, luck));
    return;
  }
  if (j == FreshJudgement::kSwap) {
    p.notes.push_back(fmt::format(
        "shrink: {} is named first: held-out χ² {:.1f} against {:.1f} for {}, and on fresh runs {:.1f} "
        "against {:.1f}, {} by the tie margin and the model's own seed luck ({:.1f})",
        f.effect, cf->loco, cc->loco, chosen.effect, b, a,
        unseen_on_fresh(a, b, p.tab.cells.size(), p.d.rule, luck) == FreshJudgement::kSwap
            ? "better"
            : "not clearly worse",
        luck));
    swap_first(p, i, gone);
    return;
  }
  if (unseen_on_fresh(a, b, p.tab.cells.size(), p.d.rule) != FreshJudgement::kKeep)
    hold_by_luck(p.verdict, f.effect);
}

}  // namespace

// The unseen candidates tied on their held-out scores (name_only_seen), judged on their fresh runs against
// the chosen one's: seen after all where those runs show them (see_on_fresh); otherwise (unseen_on_fresh)
// dropped when clearly worse there, named first when clearly better.
void judge_unseen_on_fresh(Procedure& p) {
  if (p.fresh.empty() || !p.fresh.front().failure.empty() || p.fresh.front().after.empty()) return;
  const size_t n = p.tab.cells.size();
  const double luck = p.verdict.seed_luck;
  std::vector<std::string> gone;  // tied ones a new first leaves clearly worse (swap_first)
  for (size_t i = 1; i < p.fresh.size(); ++i) {
    const FreshCheck f = p.fresh[i], chosen = p.fresh.front();
    if (!listed(p.unseen, f.effect) || !listed(p.verdict.tied, f.effect)) continue;
    std::vector<std::string>& tied = p.verdict.tied;
    const double a = chi2_of(chosen.gaps_after);
    if (!f.failure.empty() || f.after.empty()) {
      tied.erase(std::find(tied.begin(), tied.end(), f.effect));
      p.unseen_rejected.push_back(f.effect);
      p.notes.push_back(fmt::format(
          "shrink: the fresh runs of {} (unseen, tied held out) failed: {}; not named", f.effect, f.failure));
      continue;
    }
    const double b = chi2_of(f.gaps_after);
    Shift sh;
    double at = 0.0;
    if (fresh_shift_of(p, f.effect, &sh, &at) && shows(sh, n)) {
      see_on_fresh(p, i, sh, a, b, gone);
      continue;
    }
    switch (unseen_on_fresh(a, b, n, p.d.rule, luck)) {
      case FreshJudgement::kDrop:
        tied.erase(std::find(tied.begin(), tied.end(), f.effect));
        p.unseen_rejected.push_back(f.effect);
        p.notes.push_back(
            fmt::format("shrink: {} (unseen, tied held out) gives χ² {:.1f} on fresh runs at {:.3g} against "
                        "{:.1f} for {}: worse by more than the tie margin and the model's own seed luck "
                        "({:.1f}), so its held-out score followed its probes' noise; not named",
                        f.effect, b, f.strength, a, chosen.effect, luck));
        break;
      case FreshJudgement::kKeep:
        if (unseen_on_fresh(a, b, n, p.d.rule) != FreshJudgement::kKeep) hold_by_luck(p.verdict, f.effect);
        p.notes.push_back(fmt::format(
            "shrink: {} (unseen, tied held out) gives χ² {:.1f} on fresh runs at {:.3g} against "
            "{:.1f} for {}: within the tie margin or the model's own seed luck ({:.1f}), still tied",
            f.effect, b, f.strength, a, chosen.effect, luck));
        break;
      case FreshJudgement::kSwap:
        // The fresh runs, which carry no probe's noise, favour it: it is named first, the other stays tied
        // only where it is not clearly worse on the same fresh runs.
        p.notes.push_back(fmt::format(
            "shrink: {} (unseen, tied held out) gives χ² {:.1f} on fresh runs at {:.3g} against "
            "{:.1f} for {}: better by more than the tie margin and the model's own seed luck ({:.1f}), "
            "so it is named first",
            f.effect, b, f.strength, a, chosen.effect, luck));
        swap_first(p, i, gone);
        break;
    }
  }
  // Fresh checks of the candidates no longer named leave the list (the chosen one first, then the tied).
  p.fresh.erase(std::remove_if(p.fresh.begin() + 1, p.fresh.end(),
                               [&](const FreshCheck& f) {
                                 return listed(p.unseen_rejected, f.effect) || listed(gone, f.effect);
                               }),
                p.fresh.end());
}

// An unseen candidate that alone passes the held-out rule: name_only_seen left the verdict unexplained, since
// no candidate the table can see passes beside it. Its probes (P seeds, one run each side per knot) cannot
// show it, but its fresh runs at the fitted strength (R seeds at every condition, against the control on the
// same seeds) carry no probe's seed noise and no emulator. When they show it (shows(fresh_shift), the rule
// see_on_fresh applies to an unseen tie) and lower χ² below the control's by min_drop and the model's own
// seed luck (fresh_confirms, the rule every named effect meets), the table sees it after all: it leaves
// p.unseen and the verdict is decided again, naming it as it would any seen candidate, and the shrink goes on
// from its fresh check. Otherwise the verdict stays unexplained, with the fresh runs kept for the report
// (what they showed), and a note. A null's lead fails one of the two on its own runs: the fit followed its
// probes' noise.
void try_unseen_lead(Procedure& p) {
  const Verdict& v = p.verdict;
  if (v.kind != "unexplained" || v.fresh_rejected || v.ranking.empty()) return;
  const Candidate c = v.ranking.front();
  if (!passes_margin(c.loco, v, p.d.rule) || !listed(p.unseen, c.effect) ||
      listed(p.unseen_rejected, c.effect))
    return;
  FreshCheck f = want_fresh(p, c);
  want_control(p, c.refit);
  p.run();
  collect_fresh(p, f);
  if (p.null_fresh.after.empty()) collect_fresh(p, p.null_fresh);
  p.fresh = {f};
  if (!f.failure.empty() || f.after.empty() || p.null_fresh.after.empty()) {
    p.notes.push_back(
        fmt::format("shrink: the fresh runs of {} (unseen, the only candidate passing the held-out "
                    "rule) or of the model without it failed: {}; unexplained",
                    c.effect, f.failure.empty() ? p.null_fresh.failure : f.failure));
    return;
  }
  const double luck = seed_luck(p), before = chi2_of(p.null_fresh.gaps_after), after = chi2_of(f.gaps_after);
  p.verdict.seed_luck = luck;
  Shift sh;
  double at = 0.0;
  const size_t n = p.tab.cells.size();
  const bool ran = fresh_shift_of(p, c.effect, &sh, &at);
  const std::string moved = fmt::format(
      "at {:.3g} they move {} at {} by {:.1f} σ and the table's χ² by {:.1f} against the model without it on "
      "the same seeds (visible from {} σ or {:.1f}), and give χ² {:.1f} against its {:.1f} (a drop of "
      "min_drop = {:g} or the model's own seed luck {:.1f} confirms)",
      f.strength, p.tab.cells[sh.cell].observable, p.tab.conditions[p.tab.cell_condition[sh.cell]].label,
      sh.max_z, sh.chi2_excess, kVisibleZ, visible_chi2_excess(n), after, before, p.d.rule.min_drop, luck);
  if (!ran || !names_unseen_lead(sh, n, before, after, p.d.rule, luck)) {
    p.notes.push_back(fmt::format(
        "shrink: {} passes the held-out rule alone but its probes cannot show it; its "
        "fresh runs {}: {}, so it is not named and the verdict stays unexplained",
        c.effect, moved,
        !ran || !shows(sh, n) ? "they do not show it either" : "they show it but do not confirm the fit"));
    return;
  }
  p.unseen.erase(std::find(p.unseen.begin(), p.unseen.end(), c.effect));
  p.seen_on_fresh.push_back(c.effect);
  p.notes.push_back(
      fmt::format("shrink: {} passes the held-out rule alone and is seen on its fresh runs: {}; "
                  "its probes alone could not show it, so it is named as any seen candidate is",
                  c.effect, moved));
  p.verdict = redecide(p);
}

// The chosen effect's fresh runs do not confirm it against the control (fresh_confirms). A candidate the
// held-out score did not separate from it (tied, or a near tie: fresh_all ran both) and the table can see,
// whose own fresh runs on the same seeds do confirm it, is the answer the least approximate evidence
// supports: the fresh runs carry no probe's seed noise and no emulator. The one of least fresh χ² is named
// first, and the unconfirmed one is not named beside it. (absorption-strong: `scale` fitted best held
// out, 21.3, and `absorption` at the slow rate tied, 21.3; scale's fresh runs gave 70.2 against the
// control's 71.5, absorption's 47.4.) Nothing changes when none qualifies.
void promote_confirmed(Procedure& p, double before) {
  const double luck = p.verdict.seed_luck;
  std::vector<double> x;
  std::vector<bool> eligible;
  for (size_t i = 0; i < p.fresh.size(); ++i) {
    const FreshCheck& f = p.fresh[i];
    x.push_back(fresh_chi2(f));
    eligible.push_back(i > 0 && std::isfinite(x.back()) && !listed(p.unseen, f.effect) &&
                       ranked(p, f.effect) != nullptr);
  }
  const size_t best = confirmed_instead(before, x, eligible, p.d.rule, luck);
  if (best == kNone) return;
  const FreshCheck old = p.fresh.front(), f = p.fresh[best];
  std::vector<std::string>& tied = p.verdict.tied;
  if (!listed(tied, f.effect)) tied.push_back(f.effect);  // a near tie held out
  p.notes.push_back(fmt::format(
      "shrink: the fresh runs of {} at {:.3g} give χ² {:.1f} against {:.1f} for the model without it (the "
      "same fresh seeds), not lower by min_drop = {:g} or the model's own seed luck {:.1f}; those of {} at "
      "{:.3g}, which the held-out score did not separate from it, give {:.1f}: {} is named first, and {} is "
      "not named",
      old.effect, old.strength, chi2_of(old.gaps_after), before, p.d.rule.min_drop, luck, f.effect,
      f.strength, chi2_of(f.gaps_after), f.effect, old.effect));
  if (const Candidate* c = ranked(p, old.effect))
    p.verdict.passed_over = {old.effect, old.strength, c->loco, chi2_of(old.gaps_after), before};
  std::vector<std::string> gone = {old.effect};
  swap_first(p, best, gone);
  tied.erase(std::remove(tied.begin(), tied.end(), old.effect), tied.end());
  std::vector<std::string>& h = p.verdict.held_by_luck;
  h.erase(std::remove(h.begin(), h.end(), old.effect), h.end());
  p.fresh.erase(std::remove_if(p.fresh.begin() + 1, p.fresh.end(),
                               [&](const FreshCheck& c) { return listed(gone, c.effect); }),
                p.fresh.end());
}

// A tie whose runner-up is confirmed on its fresh runs (an unseen one too: its probes' noise is then not
// all its held-out score holds; viscous-strong on the flowing drum, 6 Dec 2026): neither is clearly worse,
// but the held-out score and the fresh runs may lean opposite ways, and the held-out order alone named the
// first. Each lean is measured in its own noise and the two added (tie_order_evidence, verdict.h); where the
// sum favours a tied candidate it is named first, and the former first stays tied (swap_first). The verdict's
// kind follows the new first's fresh runs. `before`: the control's χ² on the same fresh seeds.
void order_tie_by_evidence(Procedure& p, double before) {
  Verdict& v = p.verdict;
  const double luck = v.seed_luck;
  if ((v.kind != "effect" && v.kind != "partial") || p.fresh.size() < 2 || !(luck > 0)) return;
  const FreshCheck first = p.fresh.front();
  const Candidate* a = ranked(p, first.effect);
  const double fa = fresh_chi2(first);
  if (!a || !std::isfinite(fa)) return;
  size_t best = 0;
  const Candidate* winner = nullptr;
  double most = 0.0, held_z = 0.0, fresh_z = 0.0;
  for (size_t i = 1; i < p.fresh.size(); ++i) {
    const FreshCheck& f = p.fresh[i];
    const Candidate* b = ranked(p, f.effect);
    const double fb = fresh_chi2(f);
    // An unseen tie takes part once its fresh runs confirm it against the control, the rule every named
    // effect meets: those runs carry no probe's noise, so its held-out score is not that noise alone, and
    // the held-out lean is weighed in its own noise (held_out_noise) as any other's.
    if (!b || !std::isfinite(fb) || !listed(v.tied, f.effect) || !fresh_confirms(before, fb, p.d.rule, luck))
      continue;
    double hz = 0.0, fz = 0.0;
    const double e = tie_order_evidence(a->loco, b->loco, held_out_noise(*a, *b), fa, fb, luck, &hz, &fz);
    if (e > most) best = i, winner = b, most = e, held_z = hz, fresh_z = fz;
  }
  if (best == 0) return;
  const FreshCheck f = p.fresh[best];
  p.notes.push_back(fmt::format(
      "shrink: {} and {} are tied; held out their χ² are {:.1f} and {:.1f} ({:+.2f} σ of that difference's "
      "noise for {}), on fresh runs {:.1f} and {:.1f} ({:+.2f} σ of the model's own seed luck for {}): the "
      "evidence weighed by its noise favours {}, which is named first",
      first.effect, f.effect, a->loco, winner->loco, held_z, first.effect, fa, fresh_chi2(f), fresh_z,
      f.effect, f.effect));
  v.reordered = {first.effect, held_z, fresh_z};
  if (listed(p.unseen, f.effect)) {
    // Named first on its fresh runs' confirmation: no longer among what the table cannot see.
    p.unseen.erase(std::find(p.unseen.begin(), p.unseen.end(), f.effect));
    p.confirmed_on_fresh.push_back(f.effect);
    p.notes.push_back(fmt::format(
        "shrink: {}'s probes move no cell by 3 σ, but its fresh runs at {:.3g} give χ² {:.1f} against "
        "{:.1f} for the model without it on the same seeds, lower by more than min_drop = {:g} and the "
        "model's own seed luck ({:.1f}): its held-out score is not its probes' noise alone, and it takes "
        "part in the order of the tie",
        f.effect, f.strength, fresh_chi2(f), before, p.d.rule.min_drop, luck));
  }
  std::vector<std::string> gone;
  swap_first(p, best, gone);
  p.fresh.erase(std::remove_if(p.fresh.begin() + 1, p.fresh.end(),
                               [&](const FreshCheck& c) { return listed(gone, c.effect); }),
                p.fresh.end());
  std::vector<std::string>& h = v.held_by_luck;
  h.erase(std::remove(h.begin(), h.end(), f.effect), h.end());
  if (listed(v.tied, first.effect) &&
      !fresh_tie(fresh_chi2(f), fresh_chi2(first), p.tab.cells.size(), p.d.rule))
    hold_by_luck(v, first.effect);
  v.kind = "effect";
  settle_verdict(v, p.fresh.front().gaps_after, p.d.rule);
}

}  // namespace wetdem::diagnose::shrink_steps
