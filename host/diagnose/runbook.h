// The diagnosis's simulations, kept in a study run store (host/study): every run is a normal run of the case
// with the condition's and the variant's overrides and a seed, identified by its hash, so a run is never
// computed twice, not across stages and not across diagnoses that share the store (--store). A run whose
// physics is another's (app::physics_identity: a liquid-only effect at a dry condition) is that run.
#pragma once

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "diagnose/cells.h"
#include "study/executor.h"
#include "study/study_file.h"

namespace wetdem::diagnose {

struct Condition {
  std::vector<study::AxisValue> values;  // the condition keys as written (si filled once expanded)
  std::string label;                     // "liquid.content=5 %"
  std::map<std::string, double> si;      // key -> SI value
};

// A condition's label from its keys as written: "liquid.content=5 %, drum.omega=3 rad/s".
std::string condition_label(const std::vector<study::AxisValue>& values);

// The first two conditions (by index) equal in SI: one condition written two ways ("5 %" and 0.05) or listed
// twice, which would make two independent noisy values of one cell. Empty when all differ.
std::optional<std::pair<size_t, size_t>> same_condition_in_si(const std::vector<Condition>& conditions);

// The key of the first "key=value" setting that sets one of `varied` (a key the conditions vary: set for
// every run, it would be replaced at each condition, or replace every condition's value); "" when none does.
std::string sets_varied_key(const std::vector<std::string>& settings, const std::vector<std::string>& varied);

// A model variant: the baseline (no effect) or one effect at one strength (and, for an effect with a second
// parameter, one shape: effects.h), at a refit setting (refit.h).
struct Variant {
  std::string effect;  // "" = baseline
  double strength = 0.0;
  double shape = std::nan("");         // the second parameter's value; NaN: the effect has none
  std::string refit;                   // the refit setting's label; "" = as calibrated
  std::vector<std::string> overrides;  // "key=toml": the refit setting's, then the effect's
  std::string label() const;
};

class RunBook {
 public:
  RunBook(std::string store_dir, std::string spec_path, std::string name, std::string case_path,
          std::vector<std::string> set, study::ExecOptions exec);
  // Resolves and validates the runs (nothing runs); throws study::StudyError naming the point and key.
  void want(Condition& c, const Variant& v, const std::vector<uint64_t>& seeds);
  // Resolves and validates the run of v at c as want does, without wanting it.
  void check(const Condition& c, const Variant& v) const;
  // As check, and fills c's SI values as want does; writes nothing to the store (twin --check).
  void resolve(Condition& c, const Variant& v, const std::vector<uint64_t>& seeds) const;
  // Runs every wanted run that is not complete. A run that fails (a probe whose bed blows up) does not stop
  // the others nor the diagnosis: it is recorded (failure()) and the stages decide what it means (a cut
  // range). A run that failed in an earlier diagnosis sharing the store is not run again and reads the same.
  // Throws std::runtime_error only when interrupted. Returns the number of runs that failed so far.
  size_t run();
  // Why the run of v at c with this seed failed ("" when it completed or has not been asked for).
  std::string failure(const Condition& c, const Variant& v, uint64_t seed) const;
  // The first failure among the runs of v at these conditions and seeds ("" when all completed).
  std::string failure(const std::vector<Condition>& cs, const Variant& v,
                      const std::vector<uint64_t>& seeds) const;
  // Whether every run of v at these conditions and seeds has its summary.json.
  bool has_summaries(const std::vector<Condition>& cs, const Variant& v,
                     const std::vector<uint64_t>& seeds) const;
  // Steps the run of v at c would take (settle + duration over its dt), from the case alone.
  double steps(const Condition& c, const Variant& v) const;
  // Its particle-steps: the particles the case expects times those steps (app::estimate_resources).
  double particle_steps(const Condition& c, const Variant& v) const;
  // Replicate mean and SE of `observable` (a summary.json key) over the seeds: SE = max(sd/√n, f √(mean own
  // SE²/n)), the runs' own window errors a floor under the spread of few seeds. f (>= 1) scales the own
  // errors up where they are known to understate the seed-to-seed spread (Procedure::within_inflation).
  // Throws when a run is missing or never reports it.
  Prediction predict(const Condition& c, const Variant& v, const std::vector<uint64_t>& seeds,
                     const std::string& observable, double f = 1.0) const;
  // Whether any of these runs reports `observable` as a number (e.g. liquid_free_fraction is null in a dry
  // run).
  bool reports(const Condition& c, const Variant& v, const std::vector<uint64_t>& seeds,
               const std::string& observable) const;
  size_t runs() const { return runs_.size(); }
  size_t computed() const { return computed_; }
  double wall_s() const { return wall_s_; }
  std::string device() const;

 private:
  const nlohmann::json& summary(const std::string& hash) const;
  // The summary of the run of v at c with this seed (wanted before; throws std::logic_error otherwise).
  const nlohmann::json& summary_of(const Condition& c, const Variant& v, uint64_t seed) const;
  study::StudySpec spec() const;  // the store's study: this book's file, name, case and [set]
  // The study of the runs of v at c with these seeds (one point: the condition, then v's overrides).
  study::StudySpec spec_of(const Condition& c, const Variant& v, const std::vector<uint64_t>& seeds) const;
  // The hash of a run already wanted (or complete in the store) with r's physics (app::physics_identity),
  // else "" after recording r as the first with it.
  std::string same_physics(const study::PlannedRun& r);
  std::string dir_, spec_path_, name_, case_path_;
  std::vector<std::string> set_;
  study::ExecOptions exec_;
  std::vector<study::PlannedRun> runs_;
  std::vector<std::vector<study::AxisValue>> points_;
  std::map<std::string, std::string> key_to_hash_;   // condition|variant|seed -> hash
  std::map<std::string, std::string> phys_to_hash_;  // physics identity -> the run that has it
  mutable std::map<std::string, nlohmann::json> summaries_;
  std::map<std::string, std::string> failed_;  // hash -> reason
  size_t computed_ = 0;
  double wall_s_ = 0.0;
};

// The summary.json key holding a run's own standard error of `observable`, or "" when none.
std::string sem_key(const std::string& observable, const nlohmann::json& summary);

}  // namespace wetdem::diagnose
