#include "diagnose/driver.h"

#include <chrono>

#include "diagnose/baseline.h"
#include "diagnose/fit_stage.h"
#include "diagnose/next_experiment.h"
#include "diagnose/power.h"
#include "diagnose/procedure.h"
#include "diagnose/report.h"
#include "diagnose/screen.h"
#include "diagnose/second_effect.h"
#include "diagnose/shrink.h"

namespace wetdem::diagnose {

namespace {

// Where a diagnosis spends its time: each stage's wall time and the runs it computed (the store's runs that
// other diagnoses already made cost nothing). The matrix and the cost notes in docs/diagnosis.md read it.
class StageClock {
 public:
  explicit StageClock(const Procedure& p) : p_(p), last_(std::chrono::steady_clock::now()) {}
  void done(const char* stage) {
    const auto now = std::chrono::steady_clock::now();
    stages_.push_back(
        {stage, std::chrono::duration<double>(now - last_).count(), p_.book.computed() - runs_});
    last_ = now, runs_ = p_.book.computed();
  }
  std::vector<StageCost> stages() const { return stages_; }

 private:
  const Procedure& p_;
  std::chrono::steady_clock::time_point last_;
  size_t runs_ = 0;
  std::vector<StageCost> stages_;
};

}  // namespace

nlohmann::json run_diagnosis(const DiagnosisSpec& d, const DiagnoseOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  Procedure p(d, o);  // reads and checks the table and every run it may need; wants the baseline
  StageClock clock(p);
  want_screen(p);   // the screen's probes run together with the baseline
  run_baseline(p);  // 1. baseline
  clock.done("baseline and screen probes");
  p.gaps = where(p.tab.cells, p.baselines[0], d.rule.q);  // 2. where
  const bool any_gap =
      std::any_of(p.gaps.begin(), p.gaps.end(), [](const CellGap& g) { return g.significant; });
  run_screen(p);  // 3. screen
  clock.done("where and screen");
  if (!any_gap) {
    p.verdict.kind = "no_gap";
    p.verdict.null_loco = loco_null(p.tab.cells, p.baselines);
  } else {
    run_fit(p);                  // 4. fit
    mark_unseen(p);              // 5. only what the table can see is named first
    p.verdict = decide_seen(p);  // 5. verdict
    clock.done("fit and verdict");
    run_shrink(p);  // 6. shrink (and the verdict settled)
    clock.done("shrink");
    run_second_effect(p);  // 6b. a second effect, when partial
    clock.done("second effect");
    run_next_experiment(p);  // 7. next experiment (ties)
    clock.done("next experiment");
  }
  run_reach(p);  // 8. what the table can see of each candidate (its strongest probe if none shows it)
  clock.done("reach");
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return write_report(o.out, make_report(p, wall_s, clock.stages()), o.figures);
}

}  // namespace wetdem::diagnose
