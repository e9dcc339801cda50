// The report's section and diagnosis.json's "limits": what a table without a gap rules out (limits.h).
#include <fmt/format.h>

#include <string>

#include "diagnose/report.h"

namespace wetdem::diagnose {

namespace {

std::string runs_text(const Limit& l) {
  std::string s;
  for (const LimitRun& x : l.runs)
    s += fmt::format("{}{:.3g} ({:+.1f} ± {:.1f}{})", s.empty() ? "" : ", ", x.strength, x.delta, x.noise_sd,
                     ruled_out(x, l.threshold) ? ", out" : "");
  return s;
}

std::string strength_or_dash(double s) {
  return s > 0 ? fmt::format("{:.3g}", s) : std::string("-");
}

// "rate k (1/s) = 3" for an effect with a second parameter, "-" without.
std::string shape_text(const Limit& l) {
  const EffectSpec& e = effect_spec(l.effect);
  return e.shape.empty() ? std::string("-") : fmt::format("{} = {:g}", e.shape, l.shape);
}

}  // namespace

std::string limits_markdown(const Report& r) {
  if (r.limits.empty()) return "";
  std::string md = fmt::format(
      "## What this table rules out\n\nThe model needs no effect here; this is how strong each candidate "
      "could be and still not show. Each candidate's runs at every condition of the table (the strengths the "
      "stages ran; other shapes as below) are set against the observations: Δχ² = Σ [(y − run)² − (y − "
      "model)² − {:.2f} se_run²] / (σ² + se_run²) over the cells the run moves (the last term the run's own "
      "seed noise, (2/P − 2/R) / (2/P + 1/R) of its knot's se²), whose mean, were the model right, is the "
      "run's shift Σ z² (the table above); with one run a probe, it scatters about that by the seeds' noise "
      "too. A strength is ruled out (`out`) where Δχ² ≥ {:.1f} ({:g}² × the table's scatter factor {:.2f}, "
      "max(1, χ²/(n − 1))): a {:g} σ shift of one cell the observations do not show; and ≥ {:g} × its "
      "scatter for a run that shifts nothing (± below), so that seed noise alone rarely rules a run out. The "
      "limit lies between "
      "the strongest run allowed and the weakest from which every stronger run is ruled out (about: "
      "√Δχ² interpolated in log strength); strengths weaker than those run are not tested. An effect with a "
      "second parameter has a row per value run (the default first; the others from where the default is "
      "ruled out), and its limit with that parameter free is where every value rules it out.\n\n"
      "| effect | strength | at | runs: strength (Δχ² ± scatter) | ruled out from | allowed up to | limit "
      "about |\n"
      "|---|---|---|---|---|---|---|\n",
      limit_noise_share(size_t(r.spec->probe_seeds), size_t(r.spec->replicates)), r.limits.front().threshold,
      kVisibleZ, r.limits.front().threshold / kRuleOutDelta, kVisibleZ, kRuleOutNoiseZ);
  for (const Limit& l : r.limits)
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", l.effect, effect_spec(l.effect).strength,
                      shape_text(l), runs_text(l), strength_or_dash(l.ruled_out_from),
                      strength_or_dash(l.allowed_to), strength_or_dash(l.about));
  md += "\n";
  for (const FreeShapeLimit& f : free_shape_limits(r.limits))
    md += fmt::format("`{}`: {}{}; values of the {} outside those run are not tested.\n\n", f.effect,
                      f.ruled_out_from > 0 ? "ruled out " : "", free_shape_text(f),
                      effect_spec(f.effect).shape);
  return md;
}

std::string free_shape_text(const FreeShapeLimit& f) {
  const EffectSpec& e = effect_spec(f.effect);
  const std::string free =
      fmt::format("with the {} free ({:g}–{:g} run", e.shape, f.shapes.front(), f.shapes.back());
  if (f.ruled_out_from > 0)
    return fmt::format("from {} = {:.3g} {}; set by {} = {:g})", e.strength, f.ruled_out_from, free, e.shape,
                       f.binding);
  const auto [shape, strongest] = f.open.front();
  return fmt::format("not ruled out {}): at {} = {:g} no run up to {} = {:.3g}{} is", free, e.shape, shape,
                     e.strength, strongest, strongest >= e.phys_hi ? ", the end of its physical range," : "");
}

nlohmann::json limits_json(const Report& r) {
  nlohmann::json out = nlohmann::json::array();
  for (const Limit& l : r.limits) {
    nlohmann::json runs = nlohmann::json::array();
    for (const LimitRun& x : l.runs)
      runs.push_back({{"strength", x.strength},
                      {"delta_chi2", x.delta},
                      {"noise_sd", x.noise_sd},
                      {"rule_out_at", rule_out_at(x, l.threshold)},
                      {"ruled_out", ruled_out(x, l.threshold)}});
    out.push_back({{"effect", l.effect},
                   {"shape", l.shape > 0 ? nlohmann::json(l.shape) : nlohmann::json()},
                   {"runs", runs},
                   {"threshold", l.threshold},
                   {"ruled_out_from", l.ruled_out_from},
                   {"allowed_to", l.allowed_to},
                   {"about", l.about}});
  }
  return out;
}

nlohmann::json free_shape_limits_json(const Report& r) {
  nlohmann::json out = nlohmann::json::array();
  for (const FreeShapeLimit& f : free_shape_limits(r.limits)) {
    nlohmann::json open = nlohmann::json::array();
    for (const auto& [sh, s] : f.open) open.push_back({{"shape", sh}, {"strongest_run", s}});
    out.push_back({{"effect", f.effect},
                   {"shape_name", effect_spec(f.effect).shape},
                   {"shapes", f.shapes},
                   {"ruled_out_from", f.ruled_out_from},
                   {"binding_shape", f.binding},
                   {"open", open}});
  }
  return out;
}

}  // namespace wetdem::diagnose
