// The diagnosis file (D.toml) and the twin file (T.toml): docs/diagnosis.md. Both are validated
// whole before anything runs; errors name the file and the key.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "diagnose/refit.h"
#include "diagnose/verdict.h"

namespace wetdem::diagnose {

class DiagnoseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DiagnosisSpec {
  std::string path, name;
  std::string case_path;             // the calibrated model (absolute)
  std::string observations;          // the observation table (absolute)
  std::vector<std::string> set;      // "key=toml" for every run
  std::vector<std::string> effects;  // candidates (default: the whole catalogue)
  bool effects_given = false;  // named in the file (else the catalogue: those that cannot act are dropped)
  std::map<std::string, std::vector<double>>
      probes;  // per effect: strengths probed (default: the catalogue's), inside the physical range
  // Per effect with a second parameter (absorption: its rate k, 1/s): the values the fit profiles over
  // (default: the catalogue's), inside its physical range.
  std::map<std::string, std::vector<double>> shapes;
  // Per fitted candidate: runs that extend the probed range past an edge of the best shape's fit (0-6), and
  // as many again for its other shapes' own fits (fit_stage.h).
  int extend = 3;
  int confirm = 1;       // re-fits of the chosen effect with its fresh runs as a knot (0-3, shrink.h)
  double max_cost = 10;  // a run needing more than this many times a baseline run's particle-steps is not run
  size_t next_conditions = 8;  // conditions the next-experiment stage may propose and run (0: none)
  // The fastest drum a proposal beyond the table may ask for, as a Froude number ω²R/g (next_experiment.h,
  // max_drum_omega): at 1 the bed centrifuges; past ~0.1 it cataracts (Mellmann, Powder Technol. 118 (2001)
  // 251), and from half the critical speed's Froude number on, the surface a camera fits and the AoR it
  // gives lose their meaning. The 60 mm flowing drum: 122 rpm.
  double max_froude = 0.5;
  // Of them, the best conditions at which both tied models also run at every strength they were probed at,
  // so that each can re-fit to the other's value there (next_experiment.h, refit_rise; 0: none).
  size_t next_refit = 3;
  // [assays]: observables the laboratory could add to the table (a washing assay of the free liquid), each
  // with the sd of one measurement. The next-experiment stage may propose them; nothing else reads them.
  std::map<std::string, double> assays;
  // Conditions beyond the table where a candidate it cannot see is run (power.h): 5 reaches two steps past
  // the largest content and speed of a two-key table, where an effect that grows with them (lubrication with
  // speed, hysteresis with the liquid) may first show.
  size_t reach_conditions = 5;
  // Steps past the file's strongest probe for a candidate that does not show even there (power.h,
  // extend_reach): each one run per condition at the probes' step (x3), up to the physical range and
  // max_cost, until it shows. "Unseen up to 0.03 Pa s" says little when the range goes to 1.
  int reach_steps = 2;
  // Rounds of runs that bracket what a no_gap table rules out (limits.h, run_limits): one strength more per
  // candidate a round (one run per condition), under its weakest run when every run is ruled out, else the
  // middle of a wide bracket. 0: the limits come from the runs the other stages made. Two close every limit
  // of the flowing viscous-weak twin's table (one left absorption unbracketed; docs/validation.md).
  int limit_steps = 2;
  int replicates = 2;  // baseline and shrink seeds
  // Seeds per probe knot (1..replicates): the baseline's first seeds, as common random numbers. One seed is
  // enough where an effect shifts a mean; an effect that widens the run-to-run scatter (lubrication on the
  // flowing drum: sd 0.036 m/s against the model's 0.017) can land its one seed anywhere in it, so the knot
  // says little (docs/validation.md, "Lubrication on a faster drum").
  int probe_seeds = 1;
  // When the verdict at `replicates` seeds is not decided (a tie, or a comparison the seed luck decided), the
  // diagnosis runs again at this many, reusing every run of the first pass the second needs (driver.cpp).
  // 0: never.
  int escalate_replicates = 0;
  // `escalate_when = "decidable"`: only when more seeds could decide it by the outlook (more_seeds.h: some
  // tie the table would separate at that many, as fitted now, or something no outlook covers); false (the
  // default, "undecided"): whenever the verdict is not decided. Not the default: more seeds also re-fit the
  // tied models, which the outlook cannot foresee (docs/validation.md, "Would more seeds decide?").
  bool escalate_only_decidable = false;
  size_t screen_top = 3;      // candidates fitted after the screen
  bool second_effect = true;  // a partial verdict fits a second candidate on top (second_effect.h)
  int refine = 2;             // per fitted candidate: runs added at its fitted strength, then refitted (0-5)
  VerdictRule rule;
  std::vector<RefitKey> refit;  // `refit` + [refit_values] (refit.h); empty: nothing re-fitted
};
// `observations`: the table given on the command line (--observations), used instead of the file's key.
DiagnosisSpec parse_diagnosis_file(const std::string& path, const std::string& observations = "");

struct TwinSpec {
  std::string path, name;
  std::string case_path;
  std::vector<std::string> set;  // "key=toml" for every run (the common model)
  // The conditions: [conditions] (keys with value lists, their Cartesian product in file order), or
  // [[points]] (explicit conditions, each a table of key = value, all with the same keys): a laboratory's
  // table is rarely a full product (speeds measured at some liquid contents only).
  std::vector<std::string> condition_keys;               // [conditions], Cartesian product in file order
  std::vector<std::vector<std::string>> condition_toml;  // per key: values as TOML
  std::vector<std::vector<std::pair<std::string, std::string>>> points;  // [[points]]: (key, TOML) each
  std::vector<std::string> truth;       // "key=toml": what the real system has and the model lacks
  std::vector<uint64_t> seeds;          // truth seeds (distinct from the diagnosis's 1..2R)
  std::map<std::string, double> noise;  // observable -> measurement sd (also the table's sigma)
  uint64_t noise_seed = 1;
};
TwinSpec parse_twin_file(const std::string& path);

// A TOML value (string, number, boolean) as the text of a --set override; throws DiagnoseError otherwise.
std::string value_toml(const toml::node& n);

// A TOML value as it would be written in a case file after `key=`.
std::string toml_text_of_written(const std::string& written);

}  // namespace wetdem::diagnose
