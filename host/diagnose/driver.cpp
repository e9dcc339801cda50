#include "diagnose/driver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "diagnose/baseline.h"
#include "diagnose/fit_stage.h"
#include "diagnose/limits.h"
#include "diagnose/more_seeds.h"
#include "diagnose/next_bound.h"
#include "diagnose/next_experiment.h"
#include "diagnose/power.h"
#include "diagnose/procedure.h"
#include "diagnose/report.h"
#include "diagnose/screen.h"
#include "diagnose/second_effect.h"
#include "diagnose/shrink.h"
#include "diagnose/where.h"

namespace wetdem::diagnose {

namespace {

// Where a diagnosis spends its time: each stage's wall time and the runs it computed (the store's runs that
// other diagnoses already made cost nothing). The matrix and the cost notes in docs/diagnosis.md read it.
// Unless quiet, each stage's end is also a progress line: a diagnosis on lavapipe is tens of minutes of runs,
// and the runs' own progress lines count the book's runs, not the procedure's stages.
class StageClock {
 public:
  StageClock(const Procedure& p, std::string name, bool quiet)
      : p_(p), name_(std::move(name)), quiet_(quiet), t0_(std::chrono::steady_clock::now()), last_(t0_) {}
  void done(const char* stage, const std::string& what = "") {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    const size_t n = p_.book.computed() - runs_;
    stages_.push_back({stage, s, n});
    last_ = now, runs_ = p_.book.computed();
    if (!quiet_)
      fmt::print("diagnose {}: {} done in {} ({} runs computed; {} in all, {} elapsed){}{}\n", name_, stage,
                 clock_text(s), n, runs_, clock_text(std::chrono::duration<double>(now - t0_).count()),
                 what.empty() ? "" : ": ", what);
  }
  std::vector<StageCost> stages() const { return stages_; }

 private:
  static std::string clock_text(double s) {
    const long t = std::lround(s);
    return t >= 3600 ? fmt::format("{}h{:02}m{:02}s", t / 3600, t / 60 % 60, t % 60)
                     : fmt::format("{}m{:02}s", t / 60, t % 60);
  }
  const Procedure& p_;
  std::string name_;
  bool quiet_ = false;
  std::chrono::steady_clock::time_point t0_, last_;
  size_t runs_ = 0;
  std::vector<StageCost> stages_;
};

// The progress line after the screen: the significant cells and the candidates best first.
std::string screen_line(const Procedure& p, bool any_gap) {
  std::string s = fmt::format("{} of {} cells significant", significant(p.gaps), p.gaps.size());
  if (!any_gap) return s + ", the table within its noise: no gap";
  s += "; screen";
  for (size_t i = 0; i < p.screened.size() && i < 4; ++i)
    s += fmt::format("{} {} {:.1f}", i ? "," : "", p.screened[i].effect, p.screened[i].score);
  return p.screened.size() > 4 ? s + ", ..." : s;
}

// The widened fit (fit_stage.h, widened_candidates): a gap none of the screen's top candidates explains is
// not called unexplained before the next candidates that move the model towards it have been fitted too.
void widen_fit(Procedure& p) {
  if (p.verdict.kind != "unexplained") return;
  std::vector<std::string> fitted;
  for (const CandidateRuns& c : p.fitted) fitted.push_back(c.effect);
  const std::vector<Screened> add = widened_candidates(p.screened, fitted, p.d.screen_top);
  if (add.empty()) return;
  std::string added;
  for (const Screened& s : add)
    added += fmt::format("{}`{}` ({:.2f})", added.empty() ? "" : ", ", s.effect, s.score);
  p.notes.push_back(fmt::format(
      "fit: none of the screen's top {} explains the gap (verdict unexplained, best {}); the next with a "
      "positive screen score, {}, fitted as well",
      fitted.size(),
      p.verdict.ranking.empty() ? std::string("none") : "`" + p.verdict.ranking.front().effect + "`", added));
  run_fit(p, fitted.size() + add.size());
  for (CandidateRuns& c : p.fitted)
    if (std::find(fitted.begin(), fitted.end(), c.effect) == fitted.end())
      c.notes.push_back(
          fmt::format("widened fit: the screen's top {} left the gap unexplained", fitted.size()));
  mark_unseen(p);
  p.verdict = decide_seen(p);
}

// Stages 1-6b: baseline to the verdict, its fresh checks and a second effect.
void run_to_verdict(Procedure& p, StageClock& clock) {
  want_screen(p);   // the screen's probes run together with the baseline
  run_baseline(p);  // 1. baseline
  clock.done("baseline and screen probes");
  p.gaps = where(p.tab.cells, p.baselines[0], p.d.rule.q);     // 2. where
  const bool any_gap = has_gap(p.gaps, p.d.rule.table_level);  // a cell, or the table as a whole
  run_screen(p);                                               // 3. screen
  clock.done("where and screen", screen_line(p, any_gap));
  if (!any_gap) {
    p.verdict.kind = "no_gap";
    p.verdict.null_loco = loco_null(p.tab.cells, p.baselines);
    return;
  }
  run_fit(p);                  // 4. fit
  mark_unseen(p);              // 5. only what the table can see is named first
  p.verdict = decide_seen(p);  // 5. verdict
  widen_fit(p);                // 4-5 again with the next candidates, when none explains the gap
  clock.done("fit and verdict", verdict_line(p.verdict));
  run_shrink(p);  // 6. shrink (and the verdict settled)
  clock.done("shrink", verdict_line(p.verdict));
  run_second_effect(p);  // 6b. a second effect, when partial
  clock.done("second effect");
}

// Stage 6c (more_seeds.h): whether more seeds could decide an undecided verdict, at the escalation's seeds
// or, without one, at twice the seeds (what the report tells the user to try).
void run_more_seeds(Procedure& p, StageClock& clock, int to) {
  if (!undecided(p)) return;
  p.more_seeds = more_seeds_outlook(p, to > int(p.d.replicates) ? to : 2 * int(p.d.replicates));
  clock.done("more seeds");
}

// Stages 7-8: the experiment that would separate a tie, the one that would close an open interval, and
// what the table can see of each candidate.
void run_after_verdict(Procedure& p, StageClock& clock) {
  if (p.verdict.kind != "no_gap") {
    run_next_experiment(p);  // 7. next experiment (ties)
    clock.done("next experiment");
    run_bound_experiment(p);  // 7b. the experiment that would close an open interval
    clock.done("bound experiment");
  }
  run_reach(p);  // 8. what the table can see of each candidate (its strongest probe if none shows it)
  clock.done("reach");
  if (p.verdict.kind == "no_gap") {
    run_limits(p);  // 8b. what a table without a gap rules out
    clock.done("limits");
  }
}

}  // namespace

nlohmann::json run_diagnosis(const DiagnosisSpec& d, const DiagnoseOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  Procedure p(d, o);  // reads and checks the table and every run it may need; wants the baseline
  if (o.check)
    return {{"checked", true},
            {"conditions", p.tab.conditions.size()},
            {"cells", p.tab.cells.size()},
            {"candidates", p.effects}};
  StageClock clock(p, d.name, o.quiet);
  run_to_verdict(p, clock);
  // Sequential replication: when the first pass leaves its verdict undecided (a tie kept on fresh runs, or a
  // comparison only the model's seed luck decided), more seeds per condition lower the luck and the models'
  // errors (docs/validation.md: the luck 49.1 -> 18.0 from R = 2 to 4 on cohesion-weak, and its tie went) and
  // may decide it. Only then are they paid for, and only when they could (more_seeds.h): a tie whose two
  // fitted models the table cannot separate even when both are known exactly stays a tie at any number of
  // seeds (absorption-weak: escalated, the tie stayed and its order flipped). The first pass's runs stay in
  // the store, and the second reuses those it needs (the baseline's seeds 1..R and fresh seeds R+1..2R become
  // seeds 1..2R; probes and fits).
  run_more_seeds(p, clock, d.escalate_replicates);
  if (d.escalate_replicates <= d.replicates || !undecided(p) ||
      (d.escalate_only_decidable && !p.more_seeds.worth())) {
    run_after_verdict(p, clock);
    return write_report(o.out, make_report(p, wall(), clock.stages()), o.figures);
  }
  Escalation e;
  e.from = d.replicates;
  e.to = d.escalate_replicates;
  e.held_by_luck = p.verdict.held_by_luck;
  e.tied = p.verdict.tied;
  e.seed_luck = p.verdict.seed_luck;
  e.baseline_only = gap_on_baseline_seeds_only(p.verdict.fresh_rejected, p.null_fresh, d.rule.table_level);
  e.outlook = p.more_seeds;
  const Report first = make_report(p, 0.0);
  e.verdict = verdict_line(p.verdict, first.second_named() ? first.second_named()->effect : "");
  e.runs_computed = p.book.computed();
  if (!o.quiet)
    fmt::print("diagnose: at {} seeds per condition the verdict is {}, not decided; running again at {}\n",
               e.from, e.verdict, e.to);
  DiagnosisSpec more = d;
  more.replicates = d.escalate_replicates;
  Procedure q(more, o);
  q.escalation = e;
  StageClock clock2(q, d.name, o.quiet);
  run_to_verdict(q, clock2);
  run_more_seeds(q, clock2, 0);
  run_after_verdict(q, clock2);
  std::vector<StageCost> stages;
  for (StageCost c : clock.stages()) {
    c.stage = fmt::format("R = {}: {}", e.from, c.stage);
    stages.push_back(c);
  }
  for (const StageCost& c : clock2.stages()) stages.push_back(c);
  Report r = make_report(q, wall(), stages);
  r.computed += e.runs_computed;
  return write_report(o.out, r, o.figures);
}

}  // namespace wetdem::diagnose
