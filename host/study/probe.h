// `wetdem study plan --probe` (issue 19): a short measurement of this device on the study's own first batch,
// and the estimate of the whole study from it. The runs of the first batch are prepared (filled) and stepped
// together as one ensemble (README "Ensembles") for a few hundred steps of their settling phase, and sampled
// a few times as a run samples. A freshly filled bed is not a turning one (its contacts and rebuild rate
// differ), so the estimate is a guide: docs/paper.md compares it with the stages it estimated.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "study/study_file.h"

namespace wetdem::study {

struct ProbeResult {
  size_t runs = 0, particles = 0;
  uint64_t steps = 0;               // timed steps
  double setup_s_per_run = 0;       // prepare_run (PSD, fill, films) per run, wall seconds
  double step_s = 0;                // wall seconds per step of the whole batch
  double sample_s = 0;              // wall seconds per sample of the whole batch (device reductions + host)
  double particle_steps_per_s = 0;  // aggregate: particles x steps / (steps x step_s)
  std::string device;
};

// Measures on the first `batch` runs of `runs` (they must be able to share an ensemble). Throws on failure.
ProbeResult probe(const std::vector<PlannedRun>& runs, size_t batch, uint64_t steps,
                  const std::string& device);

struct Estimate {
  size_t batches = 0, runs = 0;
  double particle_steps = 0;
  double setup_s = 0, step_s = 0, sample_s = 0;
  std::vector<double> batch_s;  // each batch's set-up + steps + samples, in order
  double total_s() const { return setup_s + step_s + sample_s; }
};

// The time of running `runs` (those still to compute) `batch` at a time at the probed rates: per batch,
// set-up of its runs, its steps at the probed time per particle-step (the batch's particles over the
// probe's), its samples likewise. A batch smaller than the probe's is estimated at the probe's rate per
// particle, which flatters it (fixed per-step costs do not shrink with the batch).
Estimate estimate(const std::vector<PlannedRun>& runs, size_t batch, const ProbeResult& p);

// What the runs already complete on this device measured: a probe steps a freshly filled bed, which has fewer
// contacts and bridges than a turning one, and on a GPU it erred short by 2.3-3.2x (docs/paper.md). Each
// complete run's summary gives its batch's stepping time per particle-step: wall_split_s.stepping over (runs
// in its ensemble x its particles x the steps of this segment, steps - resumed_from_step); sampling and
// set-up are left to the probe. The rate is 1 / the mean of those times over the runs on `device`
// (every device when it is empty).
struct MeasuredRate {
  size_t runs = 0;                  // complete runs on the device that carry a stepping time
  double particle_steps_per_s = 0;  // 0 when none
  size_t batch_min = 0, batch_max = 0;
};
MeasuredRate measured_rate(const std::vector<nlohmann::json>& summaries, const std::string& device);

// The probe with its stepping time replaced by the measured rate (sample and set-up times kept).
ProbeResult at_rate(ProbeResult p, double particle_steps_per_s);

nlohmann::json to_json(const ProbeResult& p);
nlohmann::json to_json(const Estimate& e);
nlohmann::json to_json(const MeasuredRate& m);

}  // namespace wetdem::study
