// The candidate effects the diagnosis can switch on (diagnosis.md §3), each as one positive "strength" on a
// log axis whose limit 0 is the model without the effect, and the case overrides that realise a strength.
// An effect whose second parameter changes its fingerprint (absorption: the rate at which pores fill) also
// has "shapes": values of that parameter the fit profiles over. The case keys and laws are the model's own
// (docs/model.md, "Candidate effects"); this table only maps strengths and shapes to keys.
#pragma once

#include <string>
#include <vector>

namespace wetdem::diagnose {

// What an effect's overrides depend on in the calibrated case.
struct ModelFacts {
  double theta_rad = 0.0;    // static contact angle (hysteresis is relative to it)
  double scaling = 1.0;      // particle scaling l (scale coarsens it further)
  bool has_plates = false;   // closed drum (plates needs end plates)
  double plates_mu_s = 0.0;  // the plates' sliding friction in the model (plates adds to it)
  double plates_mu_r = 0.0;
  double rpm = 0.0;         // drum speed (the next experiment proposes others)
  double duration_s = 0.0;  // rotation time of a run (and longer runs)
  // The drum's inner radius: the Froude number ω²R/g of a speed the next experiment proposes.
  double drum_radius_m = 0.0;
};

struct EffectSpec {
  std::string name;            // "viscous", "absorption", ...
  std::string strength;        // what the strength is, with its unit ("eta (Pa s)", "1/tau (1/s)", ...)
  std::vector<double> probes;  // default strengths probed (ascending, > 0, inside the physical range)
  std::string fingerprint;     // what it leaves in the observables (for the report)
  double phys_lo = 0.0, phys_hi = 0.0;  // the physical range searched (diagnosis.md §3), in strength units
  // The second parameter, when it changes the fingerprint: its meaning ("" = none), the default values the
  // fit profiles over (the middle one is the screen's), and its physical range.
  std::string shape;
  std::vector<double> shapes;
  double shape_lo = 0.0, shape_hi = 0.0;

  // The --set overrides ("key=toml") that switch the effect on at strength s (and shape value, for an effect
  // with a second parameter; ignored otherwise) in the model m.
  std::vector<std::string> overrides(double s, double shape_value, const ModelFacts& m) const;
  // The effect's overrides at its default (middle) shape.
  std::vector<std::string> overrides(double s, const ModelFacts& m) const;
  double default_shape() const { return shapes.empty() ? 0.0 : shapes[shapes.size() / 2]; }
  // The strongest strength the model m can realise inside the physical range: phys_hi, except where the
  // override saturates before it (hysteresis: θ_r is floored at 0, so θ - θ_r stops at the model's θ).
  double realisable_hi(const ModelFacts& m) const;
  // Why the effect cannot act in the model m ("" when it can): plates in a periodic slice.
  std::string not_applicable(const ModelFacts& m) const;
  // The physical range of the strength and of the shape, for messages: "1e-4-1".
  std::string range_text() const;
  std::string shape_range_text() const;
};

// Every effect the diagnosis knows, in a fixed order.
const std::vector<EffectSpec>& effect_catalogue();
// The spec of one effect; throws std::invalid_argument naming the known ones when the name is unknown.
const EffectSpec& effect_spec(const std::string& name);

}  // namespace wetdem::diagnose
