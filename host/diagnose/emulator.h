// A candidate's response over its strength, from a few runs: what step 4 of the diagnosis fits
// (diagnosis.md §4). Pure statistics on predictions the runs produced; nothing here runs a model.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "diagnose/cells.h"

namespace wetdem::diagnose {

// A candidate's predictions at a few strengths of its key (in the key's SI units), one vector per strength,
// all at one shape (second parameter, effects.h) and one refit setting (refit.h).
struct Response {
  std::string effect;
  std::vector<double> strengths;              // > 0, ascending
  std::vector<std::vector<Prediction>> pred;  // [strength][cell]
};

// The response of every cell over u = log10(strength): a piecewise cubic through the baseline (placed at
// u_lo = log10 of a tenth of the weakest strength probed, where the effect is taken as absent) and the
// probes, with each knot's slope that of the parabola through it and its neighbours, limited where the knots
// are monotone (emulator.cpp); the SE of the interpolated mean from the knots' SEs. Interpolation, not a
// smoothing fit: with three or four points per cell a polynomial overshoots steep responses (f_wet against a
// wetted fraction), and an emulator that misplaces the response misplaces the fitted strength; straight lines
// between the knots misplace a response that bends between them. Outside [u_lo, u_hi] the end values hold (no
// extrapolation).
class Emulator {
 public:
  Emulator(const std::vector<Prediction>& baseline, const Response& r);
  Prediction at(size_t cell, double u) const;
  std::vector<Prediction> at(double u) const;
  double u_lo() const { return u_.front(); }                        // the anchor of the baseline
  double u_hi() const { return u_.back(); }                         // the strongest strength probed
  double u_first() const { return u_.size() > 1 ? u_[1] : u_[0]; }  // the weakest strength probed
  size_t cells() const { return mean_.size(); }
  // The same emulator with every knot's mean (the baseline's included) redrawn from a normal distribution
  // with its own SE: one draw of a parametric bootstrap over the runs behind it (fit.h,
  // widen_by_emulator_noise).
  Emulator redrawn(std::mt19937_64& rng) const;
  // As above, but the baseline's knot moves by anchor_z[cell] of its SE instead of a fresh draw (where
  // given): emulators of several candidates built on one baseline share its noise in a paired bootstrap
  // (loco_draws, fit.h). Empty: the draw above, the same numbers from the same rng.
  Emulator redrawn(std::mt19937_64& rng, const std::vector<double>& anchor_z) const;

 private:
  // A knot's slope as weights over three neighbouring knots a, a+1, a+2 (emulator.cpp, set_slopes).
  struct Slope {
    size_t a = 0;
    double w[3] = {0, 0, 0};
  };
  void set_slopes();  // from the means: the parabola's, limited where the knots are monotone
  Prediction at(size_t cell, size_t i, double t) const;  // in interval i (knots i, i+1), at t in [0, 1]

  std::vector<double> u_;                       // knots: anchor, then log10 of every probe
  std::vector<std::vector<double>> mean_, se_;  // per cell, per knot
  std::vector<std::vector<Slope>> slope_;       // per cell, per knot (three knots or more)
};

// Inserts a run's predictions at `strength` into the response (kept ascending).
void add_knot(Response& r, double strength, std::vector<Prediction> pred);
// Removes the knot at `strength` (a run that failed) when present.
void drop_knot(Response& r, double strength);

}  // namespace wetdem::diagnose
