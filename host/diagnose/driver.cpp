#include "diagnose/driver.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>

#include "app/output/summary.h"
#include "diagnose/effects.h"
#include "diagnose/report.h"
#include "diagnose/runbook.h"
#include "diagnose/where.h"
#include "study/observations.h"

namespace fs = std::filesystem;

namespace wetdem::diagnose {

const std::vector<std::string>& known_observables() {
  static const std::vector<std::string> k = {"aor_deg_mean",
                                             "aor_deg_std",
                                             "f_wet_mean",
                                             "bridges_mean",
                                             "contacts_mean",
                                             "aor_surface_deg",
                                             "aor_plate_deg",
                                             "aor_centre_deg",
                                             "aor_drift_deg_per_rev",
                                             "surface_velocity_mps",
                                             "flowing_layer_depth_m",
                                             "agglomerate_size_mean",
                                             "drum_to_agglomerate_ratio",
                                             "liquid_free_fraction"};
  return k;
}

namespace {

std::string label_of(const std::vector<study::AxisValue>& v) {
  std::string s;
  for (const auto& a : v) s += (s.empty() ? "" : ", ") + a.key + "=" + a.written;
  return s;
}

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

// The calibrated case with [set] and a refit setting's overrides, as the effects' overrides need it.
ModelFacts model_facts(const DiagnosisSpec& d, const RefitSetting& r) {
  std::vector<std::string> set = d.set;
  set.insert(set.end(), r.overrides.begin(), r.overrides.end());
  const app::Case base = app::parse_case_file(d.case_path, set);
  ModelFacts model;
  model.theta_rad = base.liquid.theta;
  model.scaling = base.scaling;
  model.has_plates = !base.drum.periodic_slice;
  model.plates_mu_s = base.plates.mu_s;
  model.plates_mu_r = base.plates.mu_r;
  return model;
}

// The effect (none: "") at a strength, at refit setting j (setting 0: as calibrated, no override).
struct Variants {
  std::vector<RefitSetting> settings;
  std::vector<ModelFacts> models;  // per setting
  Variant operator()(const std::string& effect, double strength, size_t j = 0) const {
    Variant v;
    if (j > 0) v.refit = settings[j].label, v.overrides = settings[j].overrides;
    if (effect.empty()) return v;
    v.effect = effect;
    v.strength = strength;
    for (const std::string& o : effect_spec(effect).overrides(strength, models[j])) v.overrides.push_back(o);
    return v;
  }
};

// The observation rows as conditions and cells; errors name the row.
struct Table {
  std::vector<Condition> conditions;
  std::vector<size_t> cell_condition;
  std::vector<Cell> cells;
};

Table read_table(const std::string& path) {
  std::vector<study::Observation> rows;
  try {
    rows = study::read_observations(path);
  } catch (const std::exception& e) {
    throw DiagnoseError(e.what());
  }
  Table t;
  for (const study::Observation& r : rows) {
    const auto& known = known_observables();
    if (std::find(known.begin(), known.end(), r.observable) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw DiagnoseError(
          fmt::format("{}: line {}: unknown observable '{}' (known: {})", path, r.line, r.observable, list));
    }
    std::vector<study::AxisValue> v;
    for (const auto& [k, w] : r.conditions) v.push_back({k, w, toml_text_of_written(w), std::nan("")});
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
    const std::string label = label_of(v);
    size_t ci = 0;
    while (ci < t.conditions.size() && t.conditions[ci].label != label) ++ci;
    if (ci == t.conditions.size()) t.conditions.push_back({v, label, {}});
    t.cell_condition.push_back(ci);
    Cell c;
    c.observable = r.observable;
    c.y = r.value;
    c.sigma = r.sigma;
    t.cells.push_back(c);
  }
  if (t.conditions.size() < 2)
    throw DiagnoseError(
        fmt::format("{}: {} condition(s): a diagnosis needs at least two (no held-out check "
                    "is possible with one)",
                    path, t.conditions.size()));
  return t;
}

}  // namespace

nlohmann::json run_diagnosis(const DiagnosisSpec& d, const DiagnoseOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (d.observations.empty())
    throw DiagnoseError(d.path +
                        ": observations: no table (give `observations` in the file or --observations)");
  Table tab = read_table(d.observations);
  const std::string store = o.store.empty() ? (fs::path(o.out) / "store").string() : o.store;
  RunBook book(store, d.path, d.name, d.case_path, d.set, exec_of(o));
  const std::vector<uint64_t> base_seeds = seed_range(1, d.replicates);
  const std::vector<uint64_t> fresh_seeds = seed_range(uint64_t(d.replicates) + 1, d.replicates);
  const std::vector<uint64_t> probe_seed = {1};  // common random numbers with baseline replicate 1

  // Validate every run the procedure may need before any runs (bad keys, conditions no case can express).
  // The calibrated case and every refit setting (refit.h), as the effects' overrides need them.
  Variants variant;
  variant.settings = refit_settings(d.refit);
  for (const RefitSetting& r : variant.settings) variant.models.push_back(model_facts(d, r));
  const size_t n_refit = variant.settings.size();
  const ModelFacts& model = variant.models.front();
  for (const std::string& e : d.effects)
    if (const std::string why = effect_spec(e).not_applicable(model); !why.empty() && d.effects_given)
      throw DiagnoseError(fmt::format("{}: effects: '{}' cannot act here: {}", d.path, e, why));
  for (const RefitKey& k : d.refit)
    for (const Condition& c : tab.conditions)
      for (const auto& v : c.values)
        if (v.key == k.key)
          throw DiagnoseError(
              fmt::format("{}: refit: \"{}\" is a condition of the observation table {}: it is "
                          "measured, not fitted",
                          d.path, k.key, d.observations));
  std::vector<std::string> effects;  // the catalogue by default, less what cannot act in this model
  for (const std::string& e : d.effects)
    if (effect_spec(e).not_applicable(model).empty()) effects.push_back(e);
  try {
    for (Condition& c : tab.conditions) {
      book.want(c, variant("", 0), base_seeds);
      for (const std::string& e : effects) {
        const std::vector<double>& p = d.probes.at(e);
        book.want(c, variant(e, p[p.size() / 2]), probe_seed);
        for (size_t j = 1; j < n_refit; ++j)
          for (double s : p) book.check(c, variant(e, s, j));
      }
      for (size_t j = 1; j < n_refit; ++j) book.check(c, variant("", 0, j));
    }
  } catch (const study::StudyError& e) {
    throw DiagnoseError(e.what());
  }
  for (size_t k = 0; k < tab.cells.size(); ++k)
    tab.cells[k].condition = tab.conditions[tab.cell_condition[k]].si;

  auto predictions = [&](const Variant& v, const std::vector<uint64_t>& seeds) {
    std::vector<Prediction> p;
    for (size_t k = 0; k < tab.cells.size(); ++k)
      p.push_back(book.predict(tab.conditions[tab.cell_condition[k]], v, seeds, tab.cells[k].observable));
    return p;
  };

  // 1. Baseline and 3. screen probes (run together: both are needed whatever the verdict).
  book.run();
  const Variant base = variant("", 0);
  const std::vector<Prediction> baseline = predictions(base, base_seeds);
  const std::vector<Prediction> base_seed1 = predictions(base, probe_seed);
  // 2. Where.
  const std::vector<CellGap> gaps = where(tab.cells, baseline, d.rule.q);
  const bool any_gap = std::any_of(gaps.begin(), gaps.end(), [](const CellGap& g) { return g.significant; });

  // 3. Screen: the probe's change against baseline replicate 1 (same seed), projected on the z-vector.
  std::vector<std::pair<double, std::string>> screened;
  for (const std::string& e : effects) {
    const std::vector<double>& p = d.probes.at(e);
    std::vector<Prediction> probe = predictions(variant(e, p[p.size() / 2]), probe_seed);
    for (size_t k = 0; k < probe.size(); ++k)
      probe[k].mean = baseline[k].mean + (probe[k].mean - base_seed1[k].mean);
    screened.push_back({screen_score(tab.cells, baseline, probe), e});
  }
  std::stable_sort(screened.begin(), screened.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });

  Report rep;
  rep.spec = &d;
  rep.cells = tab.cells;
  for (size_t k = 0; k < tab.cells.size(); ++k)
    rep.cell_condition.push_back(tab.conditions[tab.cell_condition[k]].label);
  rep.baseline = baseline;
  rep.gaps = gaps;
  rep.where = describe_where(tab.cells, gaps);
  rep.screened = screened;
  rep.settings = variant.settings;

  if (!any_gap) {
    rep.verdict.kind = "no_gap";
    rep.verdict.null_loco = loco_null(tab.cells, baseline);
  } else {
    // 4. Fit and select: the top candidates at every probe strength (seed 1), and with refit (refit.h) the
    // baseline and the top candidates at every refit setting.
    std::vector<std::string> top;
    for (size_t i = 0; i < screened.size() && i < d.screen_top; ++i) top.push_back(screened[i].second);
    for (Condition& c : tab.conditions) {
      for (size_t j = 1; j < n_refit; ++j) book.want(c, variant("", 0, j), base_seeds);
      for (const std::string& e : top)
        for (double s : d.probes.at(e))
          for (size_t j = 0; j < n_refit; ++j) book.want(c, variant(e, s, j), probe_seed);
    }
    book.run();
    std::vector<std::vector<Prediction>> baselines{baseline}, seed1{base_seed1};  // per refit setting
    for (size_t j = 1; j < n_refit; ++j) {
      baselines.push_back(predictions(variant("", 0, j), base_seeds));
      seed1.push_back(predictions(variant("", 0, j), probe_seed));
    }
    // Common random numbers: the effect's change against replicate 1 at the same refit setting, on top of
    // that setting's replicate mean.
    auto probe_at = [&](const std::string& e, double s, size_t j) {
      std::vector<Prediction> p = predictions(variant(e, s, j), probe_seed);
      for (size_t k = 0; k < p.size(); ++k) p[k].mean = baselines[j][k].mean + (p[k].mean - seed1[j][k].mean);
      return p;
    };
    std::vector<std::vector<Response>> responses;  // [candidate][refit setting]
    std::vector<double> scores;
    for (const std::string& e : top) {
      std::vector<Response> rs(n_refit);
      for (size_t j = 0; j < n_refit; ++j) {
        rs[j].effect = e;
        rs[j].strengths = d.probes.at(e);
        for (double s : rs[j].strengths) rs[j].pred.push_back(probe_at(e, s, j));
      }
      // Refinement (candidates.h, next_knot): runs at the fitted strength and refit setting, seed 1 (so the
      // knot carries no seed noise against the baseline), added as knots.
      for (int round = 0; round < d.refine; ++round) {
        const auto [j, s] = next_refit_knot(tab.cells, baselines, rs);
        if (s == 0.0) break;
        for (Condition& c : tab.conditions) book.want(c, variant(e, s, j), probe_seed);
        book.run();
        add_knot(rs[j], s, probe_at(e, s, j));
      }
      responses.push_back(rs);
      for (const auto& [sc, name] : screened)
        if (name == e) scores.push_back(sc);
    }
    rep.verdict = decide(tab.cells, baselines, responses, scores, d.rule);
    for (size_t i = 0; i < top.size(); ++i)  // each at the refit setting fitted with it
      for (const Candidate& c : rep.verdict.ranking)
        if (top[i] == c.effect) rep.responses.push_back(responses[i][c.refit]);
    if (n_refit > 1) {
      rep.null_refit_pred = baselines[rep.verdict.null_refit];
      rep.null_refit_gaps = where(tab.cells, rep.null_refit_pred, d.rule.q);
    }
    // 5. Shrink: the chosen effect at its fitted strength (3 significant digits) and refit setting, fresh
    // seeds.
    if (rep.verdict.kind == "effect") {
      const Candidate& best = rep.verdict.ranking.front();
      const double s = std::stod(fmt::format("{:.3g}", best.fit.strength));
      rep.chosen_strength = s;
      const Variant chosen = variant(rep.verdict.effect, s, best.refit);
      for (Condition& c : tab.conditions) book.want(c, chosen, fresh_seeds);
      book.run();
      rep.after = predictions(chosen, fresh_seeds);
      rep.gaps_after = where(tab.cells, rep.after, d.rule.q);
    }
  }
  rep.runs = book.runs();
  rep.computed = book.computed();
  rep.device = book.device();
  rep.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rep.store = store;
  return write_report(o.out, rep, o.figures);
}

nlohmann::json run_twin(const TwinSpec& t, const DiagnoseOptions& o) {
  const std::string store = o.store.empty() ? (fs::path(o.out) / "store").string() : o.store;
  std::vector<std::string> set = t.set;
  RunBook book(store, t.path, t.name, t.case_path, set, exec_of(o));
  Variant truth;
  truth.effect = "truth";
  truth.overrides = t.truth;
  // The Cartesian product of the conditions, in file order (last key fastest).
  std::vector<Condition> conds;
  std::vector<size_t> idx(t.condition_keys.size(), 0);
  for (;;) {
    Condition c;
    for (size_t k = 0; k < idx.size(); ++k) {
      const std::string& tv = t.condition_toml[k][idx[k]];
      std::string written = tv;
      if (written.size() >= 2 && written.front() == '"') written = written.substr(1, written.size() - 2);
      c.values.push_back({t.condition_keys[k], written, tv, std::nan("")});
    }
    std::sort(c.values.begin(), c.values.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
    c.label = label_of(c.values);
    conds.push_back(c);
    size_t k = idx.size();
    while (k > 0 && ++idx[k - 1] == t.condition_toml[k - 1].size()) idx[--k] = 0;
    if (k == 0) break;
  }
  try {
    for (Condition& c : conds) book.want(c, truth, t.seeds);
  } catch (const study::StudyError& e) {
    throw DiagnoseError(e.what());
  }
  for (const auto& [obs, sd] : t.noise) {
    const auto& known = known_observables();
    if (std::find(known.begin(), known.end(), obs) == known.end())
      throw DiagnoseError(fmt::format("{}: [noise] {}: unknown observable", t.path, obs));
    (void)sd;
  }
  book.run();
  fs::create_directories(o.out);
  std::mt19937_64 rng(t.noise_seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::string csv;
  for (const auto& v : conds.front().values) csv += v.key + ",";
  csv += "observable,value,sigma,n,note\n";
  nlohmann::json truth_json;
  truth_json["name"] = t.name;
  truth_json["truth"] = t.truth;
  truth_json["seeds"] = t.seeds;
  truth_json["noise"] = t.noise;
  truth_json["noise_seed"] = t.noise_seed;
  for (const Condition& c : conds) {
    for (const auto& [obs, sd] : t.noise) {
      // A quantity the truth does not have at this condition (liquid_free_fraction of a dry bed) is no
      // measurement: no row, and truth.json says so.
      if (!book.reports(c, truth, t.seeds, obs)) {
        truth_json["not_reported"].push_back({{"condition", c.label}, {"observable", obs}});
        continue;
      }
      const Prediction p = book.predict(c, truth, t.seeds, obs);
      const double sigma = std::sqrt(sd * sd + p.se * p.se);
      const double y = p.mean + sd * unit(rng);
      std::string row;
      for (const auto& v : c.values) row += "\"" + v.written + "\",";
      csv += row + fmt::format("{},{:.9g},{:.6g},{},twin\n", obs, y, sigma, t.seeds.size());
      truth_json["noiseless"].push_back(
          {{"condition", c.label}, {"observable", obs}, {"mean", p.mean}, {"se", p.se}});
    }
  }
  app::write_file_atomic((fs::path(o.out) / "observations.csv").string(), csv);
  truth_json["device"] = book.device();
  app::write_file_atomic((fs::path(o.out) / "truth.json").string(), truth_json.dump(2) + "\n");
  return truth_json;
}

}  // namespace wetdem::diagnose
