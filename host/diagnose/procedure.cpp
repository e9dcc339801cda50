#include "diagnose/procedure.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "app/case/case.h"
#include "diagnose/observables.h"

namespace fs = std::filesystem;

namespace wetdem::diagnose {

namespace {

study::ExecOptions exec_of(const DiagnoseOptions& o) {
  study::ExecOptions e;
  e.jobs = o.jobs;
  e.batch = o.batch;
  e.device = o.device;
  e.exe = o.exe;
  e.quiet = o.quiet;
  return e;
}

std::vector<uint64_t> seed_range(uint64_t first, int n) {
  std::vector<uint64_t> s;
  for (int i = 0; i < n; ++i) s.push_back(first + uint64_t(i));
  return s;
}

std::string store_of(const DiagnoseOptions& o) {
  return o.store.empty() ? (fs::path(o.out) / "store").string() : o.store;
}

// The calibrated case with [set] and a refit setting's overrides, as the effects' overrides need it.
ModelFacts model_facts(const DiagnosisSpec& d, const RefitSetting& r) {
  std::vector<std::string> set = d.set;
  set.insert(set.end(), r.overrides.begin(), r.overrides.end());
  const app::Case base = app::parse_case_file(d.case_path, set);
  ModelFacts m;
  m.theta_rad = base.liquid.theta;
  m.scaling = base.scaling;
  m.has_plates = !base.drum.periodic_slice;
  m.plates_mu_s = base.plates.mu_s;
  m.plates_mu_r = base.plates.mu_r;
  m.rpm = base.drum.omega * 60.0 / (2.0 * 3.14159265358979323846);
  m.duration_s = base.run.duration;
  m.drum_radius_m = 0.5 * base.drum.diameter;
  return m;
}

}  // namespace

Response& CandidateRuns::member(size_t j, size_t m) {
  for (size_t i = 0; i < members.size(); ++i)
    if (refit_of[i] == j && shape_of[i] == m) return members[i];
  members.push_back(Response{effect, {}, {}});
  refit_of.push_back(j);
  shape_of.push_back(m);
  return members.back();
}

Family CandidateRuns::family(const std::vector<std::vector<Prediction>>& baselines) const {
  Family f;
  f.effect = effect;
  f.screen = screen;
  for (size_t i = 0; i < members.size(); ++i) {
    if (members[i].strengths.empty()) continue;  // every run of this member failed
    f.ems.emplace_back(baselines.at(refit_of[i]), members[i]);
    f.refit_of.push_back(refit_of[i]);
    f.shape_of.push_back(shape_of[i]);
  }
  return f;
}

Procedure::Procedure(const DiagnosisSpec& d_, const DiagnoseOptions& o_)
    : spec_(d_),
      d(spec_),
      o(o_),
      tab(d_.observations.empty()
              ? throw DiagnoseError(d_.path + ": observations: no table (give `observations` in the file or "
                                              "--observations)")
              : read_table(d_.observations)),
      book(store_of(o_), d_.path, d_.name, d_.case_path, d_.set, exec_of(o_)),
      store(store_of(o_)) {
  base_seeds = seed_range(1, d.replicates);
  fresh_seeds = seed_range(uint64_t(d.replicates) + 1, d.replicates);
  if (d.probe_seeds < 1 || d.probe_seeds > d.replicates)
    throw DiagnoseError(
        fmt::format("{}: probe_seeds: {} is not in [1, replicates = {}] (the probes share the "
                    "baseline's first seeds; --probe-seeds or --replicates)",
                    d.path, d.probe_seeds, d.replicates));
  probe_seeds = seed_range(1, d.probe_seeds);  // common random numbers with the baseline's first seeds
  settings = refit_settings(d.refit);
  for (const RefitSetting& r : settings) models.push_back(model_facts(d, r));
  const ModelFacts& model = models.front();
  check_producible(tab, !model.has_plates);
  // An assay the table measures now (a report asked for it, and the laboratory added its rows: the file is
  // run again as it was) is one of the table's observables: its rows are observations with their own σ, and a
  // new measurement of it carries the table's σ (measurement_noise.h), not the file's.
  for (auto it = spec_.assays.begin(); it != spec_.assays.end();) {
    const std::string& obs = it->first;
    if (std::none_of(tab.cells.begin(), tab.cells.end(),
                     [&](const Cell& c) { return c.observable == obs; })) {
      ++it;
      continue;
    }
    assays_in_table.push_back(obs);
    it = spec_.assays.erase(it);
  }
  for (const auto& [obs, sd] : d.assays) {
    if (find_observable(obs)->needs_plates && !model.has_plates)
      throw DiagnoseError(fmt::format(
          "{}: [assays] {}: the model cannot produce it: it is a periodic slice, which has no end plates",
          d.path, obs));
  }
  for (const std::string& e : d.effects)
    if (const std::string why = effect_spec(e).not_applicable(model); !why.empty() && d.effects_given)
      throw DiagnoseError(fmt::format("{}: effects: '{}' cannot act here: {}", d.path, e, why));
  // [set] applies to every run before the table's condition does, so a condition key there would be silently
  // replaced at every condition.
  std::vector<std::string> varied;
  for (const auto& v : tab.conditions.front().values) varied.push_back(v.key);
  if (const std::string key = sets_varied_key(d.set, varied); !key.empty())
    throw DiagnoseError(fmt::format(
        "{}: [set] {}: a condition of the observation table {}: the table sets it at each condition, so the "
        "file may not",
        d.path, key, d.observations));
  for (const RefitKey& k : d.refit)
    for (const Condition& c : tab.conditions)
      for (const auto& v : c.values)
        if (v.key == k.key)
          throw DiagnoseError(
              fmt::format("{}: refit: \"{}\" is a condition of the observation table {}: it is "
                          "measured, not fitted",
                          d.path, k.key, d.observations));
  for (const std::string& e : d.effects)
    if (effect_spec(e).not_applicable(model).empty()) effects.push_back(e);
  // Validate every run the procedure may need before any runs (bad keys, conditions no case can express,
  // a slice too thin for the neighbour reach at some condition); the baseline is wanted now. An error names
  // the table's rows at the condition (where a user wrote it) and, for a candidate's run, the candidate.
  for (size_t ci = 0; ci < tab.conditions.size(); ++ci) {
    Condition& c = tab.conditions[ci];
    // `run` names the run only when a check fails: a diagnosis checks hundreds of runs, and most pass.
    const auto checked = [&](auto&& plan, auto&& run) {
      try {
        plan();
      } catch (const study::StudyError& e) {
        throw DiagnoseError(
            fmt::format("{}: {} ({}){}: {}", tab.path, condition_lines(tab, ci), c.label, run(), e.reason()));
      }
    };
    checked(
        [&] {
          if (o.check)
            book.resolve(c, variant("", 0), base_seeds);  // diagnose --check: the store is not touched
          else
            book.want(c, variant("", 0), base_seeds);
        },
        [] { return std::string(); });
    for (size_t j = 1; j < settings.size(); ++j)
      checked(
          [&] { book.check(c, variant("", 0, j)); },
          [&] { return fmt::format(", the model re-fitted at {} ({}: refit)", settings[j].label, d.path); });
    for (const std::string& e : effects) {
      const EffectSpec& spec = effect_spec(e);
      const std::vector<double>& p = d.probes.at(e);
      const std::vector<double> shapes = d.shapes.count(e) ? d.shapes.at(e) : std::vector<double>{NAN};
      for (size_t j = 0; j < settings.size(); ++j)
        for (double sh : shapes)
          for (double s : {p.front(), p.back(), spec.phys_hi})
            checked([&] { book.check(c, variant(e, s, j, sh)); },
                    [&] {
                      return fmt::format(
                          ", the candidate '{}' at {:g} ({}: probes, or the end of its physical range)", e, s,
                          d.path);
                    });
    }
  }
  // Conditions written differently but equal in SI ("5 %" and 0.05) are one condition listed twice.
  if (const auto same = same_condition_in_si(tab.conditions)) {
    const auto [a, b] = *same;
    throw DiagnoseError(fmt::format(
        "{}: {} ({}) and {} ({}) are the same condition in SI units: write each condition one way", tab.path,
        condition_lines(tab, a), tab.conditions[a].label, condition_lines(tab, b), tab.conditions[b].label));
  }
  for (size_t k = 0; k < tab.cells.size(); ++k)
    tab.cells[k].condition = tab.conditions[tab.cell_condition[k]].si;
  for (const Condition& c : tab.conditions) base_steps.push_back(book.particle_steps(c, variant("", 0)));
}

Variant Procedure::variant(const std::string& effect, double s, size_t j, double shape) const {
  Variant v;
  if (j > 0) v.refit = settings.at(j).label, v.overrides = settings.at(j).overrides;
  if (effect.empty()) return v;
  const EffectSpec& spec = effect_spec(effect);
  v.effect = effect;
  v.strength = s;
  if (!spec.shapes.empty()) v.shape = std::isnan(shape) ? spec.default_shape() : shape;
  for (const std::string& x : spec.overrides(s, v.shape, models.at(j))) v.overrides.push_back(x);
  return v;
}

double Procedure::cost(const Variant& v) const {
  double worst = 0;
  for (size_t i = 0; i < tab.conditions.size() && i < base_steps.size(); ++i)
    if (base_steps[i] > 0) worst = std::max(worst, book.particle_steps(tab.conditions[i], v) / base_steps[i]);
  return worst;
}

std::string Procedure::want(const Variant& v, const std::vector<uint64_t>& seeds) {
  // The cost guard: a variant whose time step is far below the baseline's (the lubrication damper's limit at
  // a high viscosity) or whose particles are many more (a finer scale) is not run; the stage cuts the
  // candidate's range there.
  if (const double x = cost(v); x > d.max_cost)
    return fmt::format(
        "not run: {:.3g}x the particle-steps of a baseline run (max_cost = {:g}; its time step is "
        "limited by the lubrication damper, or a finer scaling has more particles)",
        x, d.max_cost);
  try {
    for (Condition& c : tab.conditions) book.want(c, v, seeds);
  } catch (const study::StudyError& e) {
    return std::string("not run: ") + e.what();
  }
  return "";
}

std::vector<Prediction> Procedure::predict(const Variant& v, const std::vector<uint64_t>& seeds) const {
  std::vector<Prediction> p;
  for (size_t k = 0; k < tab.cells.size(); ++k) {
    const Condition& c = tab.conditions[tab.cell_condition[k]];
    // A run may not report an observable (the AoR drift of a window that cannot carry it): NaN.
    if (!book.reports(c, v, seeds, tab.cells[k].observable))
      p.push_back({std::nan(""), std::nan("")});
    else
      p.push_back(book.predict(c, v, seeds, tab.cells[k].observable));
  }
  return p;
}

std::vector<Family> Procedure::families() const {
  std::vector<Family> fams;
  for (const CandidateRuns& c : fitted)
    if (Family f = c.family(baselines); !f.ems.empty()) fams.push_back(f);
  return fams;
}

bool gap_on_baseline_seeds_only(bool fresh_rejected, const FreshCheck& null_fresh, double table_level) {
  return fresh_rejected && !null_fresh.after.empty() && !has_gap(null_fresh.gaps_after, table_level);
}

double knot_se(double spread, double probe_se, size_t probe_seeds, size_t replicates) {
  const double np = double(std::max<size_t>(1, probe_seeds)), r = double(std::max<size_t>(1, replicates));
  const double s = std::max(spread, std::isfinite(probe_se) ? probe_se * std::sqrt(np) : 0.0);
  return s * std::sqrt(2.0 / np + 1.0 / r);
}

std::vector<Prediction> Procedure::probe(const Variant& v, size_t j) const {
  std::vector<Prediction> p = predict(v, probe_seeds);
  for (size_t k = 0; k < p.size(); ++k) {
    const double se = knot_se(spread[k], p[k].se, probe_seeds.size(), base_seeds.size());
    if (std::isnan(p[k].mean) || std::isnan(seed1[j][k].mean)) {
      // The probe (or the baseline's probe seeds) does not report this cell: no measured change, and a knot
      // that carries almost no weight there.
      p[k] = {baselines[j][k].mean, 3.0 * se};
      continue;
    }
    p[k].mean = baselines[j][k].mean + (p[k].mean - seed1[j][k].mean);
    p[k].se = se;
  }
  return p;
}

}  // namespace wetdem::diagnose
