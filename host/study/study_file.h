// A study file (TOML, ../shared spec "studies.md", docs/studies.md): a base case, overrides
// for every run ([set]), a Cartesian grid ([axes]) and/or explicit [[points]], replicates or seeds, and
// optional [observations]. Expanded into runs, each identified by the hash of its resolved case + seed + code
// version.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "app/case/case.h"

namespace wetdem::study {

// Bad study input. what() is "FILE: KEY: reason".
class StudyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  StudyError(const std::string& what, std::string cause)
      : std::runtime_error(what), cause_(std::move(cause)) {}
  // The reason alone, without the file and point it was found at, for a caller that names the place in its
  // own terms (a diagnosis names the observation table's lines); the whole message when it has no location.
  std::string reason() const { return cause_.empty() ? std::string(what()) : cause_; }

 private:
  std::string cause_;
};

// One axis or point value as written in the study file ("5 %", 0.3, true) and as a --set override.
struct AxisValue {
  std::string key;      // dotted case key, e.g. "liquid.content"
  std::string written;  // the value as text, as in the file ("5 %", "0.3")
  std::string toml;     // the value as TOML, for the override ("\"5 %\"", "0.3")
  double si = 0;        // the resolved value in SI (NaN when the key has no numeric SI value)
};

struct ObservationSpec {
  std::string file;              // absolute path of the CSV table ("" when the study has none)
  std::vector<std::string> fit;  // the axes being calibrated; the other axes are conditions
};

struct StudySpec {
  std::string path;  // the study file, absolute
  std::string name;
  std::string base;                            // the base case file, absolute
  std::vector<std::string> set;                // "key=toml" overrides for every run, in file order
  std::vector<std::string> axis_keys;          // [axes] in file order
  std::vector<std::vector<AxisValue>> points;  // every point's values (grid first, then [[points]])
  std::vector<uint64_t> seeds;                 // one run per point and seed
  ObservationSpec observations;
};

// One run of the study.
struct PlannedRun {
  size_t index = 0;  // 0-based, the Slurm array task id
  size_t point = 0;  // index into StudySpec::points
  uint64_t seed = 0;
  std::vector<AxisValue> values;       // the point's values
  std::vector<std::string> overrides;  // [set], then the point's values, then run.seed
  std::string hash;                    // run identity (hex)
  app::Case resolved;
};

// Reads and validates a study file: every override of every point is applied to the base case and validated
// (errors name the study file, the point and the key) before anything runs. Throws StudyError.
StudySpec parse_study_file(const std::string& path);

// The runs of a study in order (points x seeds), each resolved and hashed. Throws StudyError.
std::vector<PlannedRun> expand(const StudySpec& s);

// The version that enters every hash: wetdem::run_version(), WETDEM_VERSION + a content hash of the sources
// that decide what a run computes, as tokens (cmake/git_describe.cmake). A change to study, diagnosis or CLI
// code, or to comments and layout anywhere, keeps the stored runs; a changed token in a shader, the GPU
// system or the run driver makes new ones.
std::string code_version();
// Run identity: 64-bit FNV-1a (hex) of the resolved case's canonical JSON (keys sorted, SI), the seed and the
// code version. Axis order and unit spelling ("5 %" vs 0.05) do not change it; any resolved value does.
std::string run_hash(const app::Case& c, uint64_t seed, const std::string& version = code_version());

// The SI value of a dotted case key in a resolved case's JSON (case_to_json), following its unit-suffixed
// spelling (drum.diameter -> drum.diameter_m, drum.rpm -> drum.rotation_rad_per_s). NaN when not numeric.
double si_of_key(const nlohmann::json& case_json, const std::string& key);

// "key=value" as a TOML override, value rendered from a toml node's text.
std::string override_of(const AxisValue& v);

}  // namespace wetdem::study
