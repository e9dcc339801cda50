#include "diagnose/files.h"

#include <fmt/format.h>

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "diagnose/effects.h"
#include "diagnose/observables.h"
#include "diagnose/runbook.h"

namespace fs = std::filesystem;

namespace wetdem::diagnose {

std::string value_toml(const toml::node& n) {
  if (const auto* s = n.as_string()) return toml_text_of_written(s->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* f = n.as_floating_point()) {
    // The shortest text that reads back as the same double (0.05, not 0.050000000000000003: it labels
    // conditions), kept a TOML float.
    std::string t = fmt::format("{}", f->get());
    if (t.find_first_of(".eEni") == std::string::npos) t += ".0";
    return t;
  }
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  throw DiagnoseError("a value must be a string, a number or a boolean");
}

namespace {

std::string rel_path(const std::string& file, const std::string& p) {
  const fs::path q(p);
  return (q.is_absolute() ? q : fs::absolute(fs::path(file).parent_path() / q)).lexically_normal().string();
}

toml::table load(const std::string& path) {
  if (!fs::exists(path)) throw DiagnoseError(path + ": no such file");
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw DiagnoseError(fmt::format("{}: line {}: {}", path, e.source().begin.line, e.description()));
  }
}

std::string need_string(const toml::table& t, const std::string& file, const char* key) {
  const auto* v = t.get(key);
  if (!v || !v->is_string()) throw DiagnoseError(fmt::format("{}: {}: a string is required", file, key));
  return v->as_string()->get();
}

std::vector<std::string> overrides_of(const toml::table& t, const std::string& file,
                                      const std::string& section) {
  std::vector<std::string> out;
  for (const auto& [k, v] : t) {
    try {
      out.push_back(std::string(k.str()) + "=" + value_toml(v));
    } catch (const DiagnoseError& e) {
      throw DiagnoseError(fmt::format("{}: [{}] {}: {}", file, section, k.str(), e.what()));
    }
  }
  return out;
}

void reject_unknown(const toml::table& t, const std::string& file, const std::vector<std::string>& known) {
  for (const auto& [k, v] : t)
    if (std::find(known.begin(), known.end(), std::string(k.str())) == known.end())
      throw DiagnoseError(fmt::format("{}: {}: unknown key", file, k.str()));
}

}  // namespace

std::string toml_text_of_written(const std::string& w) {
  if (w == "true" || w == "false") return w;
  char* end = nullptr;
  std::strtod(w.c_str(), &end);
  if (!w.empty() && end && *end == '\0') return w;
  std::string q = "\"";
  for (char ch : w) q += (ch == '"' || ch == '\\') ? std::string("\\") + ch : std::string(1, ch);
  return q + "\"";
}

DiagnosisSpec parse_diagnosis_file(const std::string& path_in, const std::string& observations) {
  const std::string path = fs::absolute(path_in).lexically_normal().string();
  const toml::table root = load(path);
  reject_unknown(root, path,
                 {"name",
                  "case",
                  "observations",
                  "effects",
                  "replicates",
                  "escalate_replicates",
                  "escalate_when",
                  "probe_seeds",
                  "screen_top",
                  "refine",
                  "extend",
                  "confirm",
                  "max_cost",
                  "next_conditions",
                  "next_refit",
                  "assays",
                  "reach_conditions",
                  "reach_steps",
                  "limit_steps",
                  "second_effect",
                  "set",
                  "probes",
                  "shapes",
                  "verdict",
                  "refit",
                  "refit_values",
                  "max_froude"});
  DiagnosisSpec d;
  d.path = path;
  d.name = root["name"].value_or(fs::path(path).stem().string());
  d.case_path = rel_path(path, need_string(root, path, "case"));
  // The table may come with --observations only (a shipped example whose table a GPU run makes). Given
  // there, it replaces the file's, which then need not exist (a diagnosis file copied elsewhere).
  if (!observations.empty()) {
    if (!fs::exists(observations)) throw DiagnoseError("--observations: no such file " + observations);
    d.observations = fs::absolute(observations).lexically_normal().string();
  } else if (root.contains("observations")) {
    d.observations = rel_path(path, need_string(root, path, "observations"));
    if (!fs::exists(d.observations))
      throw DiagnoseError(fmt::format("{}: observations: no such file {}", path, d.observations));
  }
  if (!fs::exists(d.case_path))
    throw DiagnoseError(fmt::format("{}: case: no such file {}", path, d.case_path));
  if (const auto* e = root["effects"].as_array()) {
    for (const auto& x : *e) {
      if (!x.is_string()) throw DiagnoseError(fmt::format("{}: effects: names must be strings", path));
      std::string name;
      try {
        name = effect_spec(x.as_string()->get()).name;
      } catch (const std::invalid_argument& ex) {
        throw DiagnoseError(fmt::format("{}: effects: {}", path, ex.what()));
      }
      if (std::find(d.effects.begin(), d.effects.end(), name) != d.effects.end())
        throw DiagnoseError(fmt::format("{}: effects: {} is listed twice", path, name));
      d.effects.push_back(name);
    }
    if (d.effects.empty()) throw DiagnoseError(fmt::format("{}: effects: name at least one effect", path));
    d.effects_given = true;
  } else if (root.contains("effects")) {
    throw DiagnoseError(fmt::format("{}: effects: an array of effect names is required", path));
  } else {
    for (const EffectSpec& spec : effect_catalogue()) d.effects.push_back(spec.name);
  }
  if (root.contains("replicates")) {
    const auto r = root["replicates"].value<int64_t>();
    if (!r || *r < 1 || *r > 100)
      throw DiagnoseError(fmt::format("{}: replicates: an integer in [1, 100]", path));
    d.replicates = int(*r);
  }
  if (root.contains("escalate_replicates")) {
    const auto r = root["escalate_replicates"].value<int64_t>();
    if (!r || *r < 0 || *r > 100)
      throw DiagnoseError(fmt::format("{}: escalate_replicates: an integer in [0, 100] (0: never)", path));
    if (*r != 0 && *r <= d.replicates)
      throw DiagnoseError(
          fmt::format("{}: escalate_replicates: {} is not more than replicates ({}); 0 turns "
                      "it off",
                      path, *r, d.replicates));
    d.escalate_replicates = int(*r);
  }
  if (root.contains("escalate_when")) {
    const auto w = root["escalate_when"].value<std::string>();
    if (!w || (*w != "decidable" && *w != "undecided"))
      throw DiagnoseError(fmt::format(
          "{}: escalate_when: \"undecided\" (the default: run again whenever the verdict is not decided) or "
          "\"decidable\" (only when more seeds could decide it, by the outlook of the fitted models)",
          path));
    d.escalate_only_decidable = *w == "decidable";
  }
  if (root.contains("probe_seeds")) {
    const auto r = root["probe_seeds"].value<int64_t>();
    if (!r || *r < 1 || *r > d.replicates)
      throw DiagnoseError(
          fmt::format("{}: probe_seeds: an integer in [1, replicates = {}] (the probes share the "
                      "baseline's first seeds)",
                      path, d.replicates));
    d.probe_seeds = int(*r);
  }
  if (root.contains("screen_top")) {
    const auto r = root["screen_top"].value<int64_t>();
    if (!r || *r < 1) throw DiagnoseError(fmt::format("{}: screen_top: an integer >= 1", path));
    d.screen_top = size_t(*r);
  }
  if (root.contains("refine")) {
    const auto r = root["refine"].value<int64_t>();
    if (!r || *r < 0 || *r > 5) throw DiagnoseError(fmt::format("{}: refine: an integer in [0, 5]", path));
    d.refine = int(*r);
  }
  if (root.contains("extend")) {
    const auto r = root["extend"].value<int64_t>();
    if (!r || *r < 0 || *r > 6) throw DiagnoseError(fmt::format("{}: extend: an integer in [0, 6]", path));
    d.extend = int(*r);
  }
  if (root.contains("confirm")) {
    const auto r = root["confirm"].value<int64_t>();
    if (!r || *r < 0 || *r > 3) throw DiagnoseError(fmt::format("{}: confirm: an integer in [0, 3]", path));
    d.confirm = int(*r);
  }
  if (root.contains("second_effect")) {
    // as_boolean, not value<bool>: toml++ would read 1 as true, and a number here is a mistake.
    const auto* r = root["second_effect"].as_boolean();
    if (!r) throw DiagnoseError(fmt::format("{}: second_effect: true or false", path));
    d.second_effect = r->get();
  }
  if (root.contains("max_cost")) {
    const auto r = root["max_cost"].value<double>();
    if (!r || !(*r >= 1)) throw DiagnoseError(fmt::format("{}: max_cost: a number >= 1", path));
    d.max_cost = *r;
  }
  if (root.contains("next_conditions")) {
    const auto r = root["next_conditions"].value<int64_t>();
    if (!r || *r < 0 || *r > 20)
      throw DiagnoseError(fmt::format("{}: next_conditions: an integer in [0, 20]", path));
    d.next_conditions = size_t(*r);
  }
  if (root.contains("max_froude")) {
    const auto r = root["max_froude"].value<double>();
    if (!r || !(*r > 0) || !(*r <= 1))
      throw DiagnoseError(fmt::format(
          "{}: max_froude: a number in (0, 1] (the drum's Froude number ω²R/g; at 1 the bed centrifuges)",
          path));
    d.max_froude = *r;
  }
  if (root.contains("next_refit")) {
    const auto r = root["next_refit"].value<int64_t>();
    if (!r || *r < 0 || *r > 10)
      throw DiagnoseError(fmt::format("{}: next_refit: an integer in [0, 10]", path));
    d.next_refit = size_t(*r);
  }
  if (const auto* t = root["assays"].as_table()) {
    for (const auto& [k, v] : *t) {
      const std::string obs(k.str());
      const ObservableSpec* o = find_observable(obs);
      if (!o)
        throw DiagnoseError(
            fmt::format("{}: [assays] {}: not an observable (one of {})", path, obs, observable_names()));
      if (o->routine.rfind("no", 0) == 0)
        throw DiagnoseError(fmt::format(
            "{}: [assays] {}: {} is a simulation quantity that no laboratory measures: it cannot be "
            "the next experiment",
            path, obs, obs));
      const auto sd = v.value<double>();
      if (!sd || !(*sd > 0) || !std::isfinite(*sd))
        throw DiagnoseError(fmt::format("{}: [assays] {}: the sd of one measurement, a positive number in {}",
                                        path, obs, o->unit));
      d.assays[obs] = *sd;
    }
  } else if (root.contains("assays")) {
    throw DiagnoseError(fmt::format("{}: [assays]: a table of observable = measurement sd", path));
  }
  if (root.contains("reach_conditions")) {
    const auto r = root["reach_conditions"].value<int64_t>();
    if (!r || *r < 0 || *r > 20)
      throw DiagnoseError(fmt::format("{}: reach_conditions: an integer in [0, 20]", path));
    d.reach_conditions = size_t(*r);
  }
  if (root.contains("reach_steps")) {
    const auto r = root["reach_steps"].value<int64_t>();
    if (!r || *r < 0 || *r > 10)
      throw DiagnoseError(fmt::format("{}: reach_steps: an integer in [0, 10]", path));
    d.reach_steps = int(*r);
  }
  if (root.contains("limit_steps")) {
    const auto r = root["limit_steps"].value<int64_t>();
    if (!r || *r < 0 || *r > 10)
      throw DiagnoseError(fmt::format("{}: limit_steps: an integer in [0, 10]", path));
    d.limit_steps = int(*r);
  }
  if (const auto* t = root["set"].as_table()) d.set = overrides_of(*t, path, "set");
  // [probes] (strengths) and [shapes] (second parameters): positive, ascending, inside the physical range
  // (diagnosis.md §3), so that no probe asks for a system that cannot exist.
  const auto read_list = [&](const char* table, bool shapes) {
    const auto* t = root[table].as_table();
    if (!t) {
      if (root.contains(table))
        throw DiagnoseError(fmt::format("{}: [{}]: a table of effect = [values]", path, table));
      return;
    }
    for (const auto& [k, v] : *t) {
      const std::string name(k.str());
      if (std::find(d.effects.begin(), d.effects.end(), name) == d.effects.end())
        throw DiagnoseError(fmt::format("{}: [{}] {}: not one of the effects diagnosed", path, table, name));
      const EffectSpec& spec = effect_spec(name);
      if (shapes && spec.shape.empty())
        throw DiagnoseError(fmt::format("{}: [shapes] {}: the effect has no second parameter", path, name));
      const auto* a = v.as_array();
      std::vector<double> s;
      if (a)
        for (const auto& x : *a)
          if (auto f = x.value<double>()) s.push_back(*f);
      if (!a || s.size() != a->size() || s.empty())
        throw DiagnoseError(fmt::format("{}: [{}] {}: an array of positive numbers", path, table, name));
      for (size_t i = 0; i < s.size(); ++i)
        if (!(s[i] > 0) || (i && !(s[i] > s[i - 1])))
          throw DiagnoseError(
              fmt::format("{}: [{}] {}: values must be positive and ascending", path, table, name));
      const double lo = shapes ? spec.shape_lo : spec.phys_lo, hi = shapes ? spec.shape_hi : spec.phys_hi;
      for (double x : s)
        if (x < lo * (1 - 1e-9) || x > hi * (1 + 1e-9))
          throw DiagnoseError(
              fmt::format("{}: [{}] {}: {:g} is outside the physical range {:g}-{:g} of {} (diagnosis.md §3)",
                          path, table, name, x, lo, hi, shapes ? spec.shape : spec.strength));
      (shapes ? d.shapes : d.probes)[name] = s;
    }
  };
  read_list("probes", false);
  read_list("shapes", true);
  for (const std::string& e : d.effects) {
    if (!d.probes.count(e)) d.probes[e] = effect_spec(e).probes;
    if (!d.shapes.count(e) && !effect_spec(e).shapes.empty()) d.shapes[e] = effect_spec(e).shapes;
  }
  if (const auto* t = root["verdict"].as_table()) {
    reject_unknown(
        *t, path + ": [verdict]",
        {"fdr", "table_level", "held_out", "ratio", "min_drop", "tie_delta", "tie_noise", "tie_draws"});
    d.rule.tie_delta = (*t)["tie_delta"].value_or(d.rule.tie_delta);
    if (!(d.rule.tie_delta >= 0))
      throw DiagnoseError(fmt::format("{}: verdict.tie_delta: a number >= 0", path));
    d.rule.tie_noise = (*t)["tie_noise"].value_or(d.rule.tie_noise);
    if (!(d.rule.tie_noise >= 0))
      throw DiagnoseError(fmt::format(
          "{}: verdict.tie_noise: a number >= 0 (standard deviations of the held-out difference; 0: off)",
          path));
    const int64_t draws = (*t)["tie_draws"].value_or(int64_t(d.rule.tie_draws));
    if (draws < 2 || draws > 1000)
      throw DiagnoseError(fmt::format("{}: verdict.tie_draws: an integer in 2-1000, not {}", path, draws));
    d.rule.tie_draws = int(draws);
    d.rule.q = (*t)["fdr"].value_or(d.rule.q);
    d.rule.ratio = (*t)["ratio"].value_or(d.rule.ratio);
    d.rule.min_drop = (*t)["min_drop"].value_or(d.rule.min_drop);
    if (!(d.rule.q > 0 && d.rule.q < 1)) throw DiagnoseError(fmt::format("{}: verdict.fdr: in (0, 1)", path));
    const std::string held_out = (*t)["held_out"].value_or(std::string("chi2"));
    if (held_out != "chi2" && held_out != "log_density")
      throw DiagnoseError(
          fmt::format("{}: verdict.held_out: \"chi2\" or \"log_density\", not \"{}\"", path, held_out));
    d.rule.held_out = held_out == "log_density" ? HeldOut::kLogDensity : HeldOut::kChi2;
    d.rule.table_level = (*t)["table_level"].value_or(d.rule.table_level);
    if (!(d.rule.table_level >= 0 && d.rule.table_level < 1))
      throw DiagnoseError(
          fmt::format("{}: verdict.table_level: in [0, 1) (0 turns the table's χ² test off)", path));
    if (!(d.rule.ratio > 0 && d.rule.ratio <= 1))
      throw DiagnoseError(fmt::format("{}: verdict.ratio: in (0, 1]", path));
  }
  if (root.contains("refit") || root.contains("refit_values")) {
    std::map<std::string, std::string> effect_keys;  // key -> the candidate that sets it
    for (const std::string& e : d.effects)
      for (const std::string& o : effect_spec(e).overrides(d.probes.at(e).front(), ModelFacts{}))
        effect_keys.emplace(o.substr(0, o.find('=')), e);
    d.refit = parse_refit(root, path, d.case_path, d.set, effect_keys);
  }
  return d;
}

TwinSpec parse_twin_file(const std::string& path_in) {
  const std::string path = fs::absolute(path_in).lexically_normal().string();
  const toml::table root = load(path);
  reject_unknown(root, path,
                 {"name", "case", "set", "conditions", "points", "truth", "seeds", "noise", "noise_seed"});
  TwinSpec t;
  t.path = path;
  t.name = root["name"].value_or(fs::path(path).stem().string());
  t.case_path = rel_path(path, need_string(root, path, "case"));
  if (!fs::exists(t.case_path))
    throw DiagnoseError(fmt::format("{}: case: no such file {}", path, t.case_path));
  if (const auto* s = root["set"].as_table()) t.set = overrides_of(*s, path, "set");
  if (const auto* s = root["truth"].as_table()) t.truth = overrides_of(*s, path, "truth");
  const auto* c = root["conditions"].as_table();
  const auto* pts = root["points"].as_array();
  if (c && pts) throw DiagnoseError(fmt::format("{}: [conditions] and [[points]]: give one of them", path));
  if (pts) {
    std::vector<std::string> keys;
    for (size_t i = 0; i < pts->size(); ++i) {
      const auto* p = (*pts)[i].as_table();
      if (!p || p->empty())
        throw DiagnoseError(fmt::format("{}: [[points]] #{}: a table of condition keys", path, i + 1));
      std::vector<std::pair<std::string, std::string>> point;
      std::vector<std::string> ks;
      for (const auto& [k, v] : *p) {
        try {
          point.emplace_back(std::string(k.str()), value_toml(v));
        } catch (const DiagnoseError& e) {
          throw DiagnoseError(fmt::format("{}: [[points]] #{} {}: {}", path, i + 1, k.str(), e.what()));
        }
        ks.emplace_back(k.str());
      }
      std::sort(ks.begin(), ks.end());
      if (i == 0) keys = ks;
      if (ks != keys)
        throw DiagnoseError(fmt::format(
            "{}: [[points]] #{}: every point needs the same condition keys as the first", path, i + 1));
      t.points.push_back(point);
    }
    if (t.points.size() < 2)
      throw DiagnoseError(
          fmt::format("{}: [[points]]: at least two conditions (a held-out check needs them)", path));
  } else {
    if (!c || c->empty())
      throw DiagnoseError(fmt::format("{}: [conditions]: at least one condition key (or [[points]])", path));
    size_t n = 1;
    for (const auto& [k, v] : *c) {
      const auto* a = v.as_array();
      if (!a || a->empty())
        throw DiagnoseError(fmt::format("{}: [conditions] {}: a non-empty array", path, k.str()));
      t.condition_keys.emplace_back(k.str());
      std::vector<std::string> vals;
      for (const auto& x : *a) {
        try {
          vals.push_back(value_toml(x));
        } catch (const DiagnoseError& e) {
          throw DiagnoseError(fmt::format("{}: [conditions] {}: {}", path, k.str(), e.what()));
        }
      }
      n *= vals.size();
      t.condition_toml.push_back(vals);
    }
    if (n < 2)
      throw DiagnoseError(
          fmt::format("{}: [conditions]: at least two conditions (a held-out check needs them)", path));
  }
  // The truth (and the common [set]) may not set a key the conditions vary: the truth's value would
  // replace every condition's (a table of one condition, told as several).
  std::vector<std::string> varied = t.condition_keys;
  for (const auto& [k, v] :
       t.points.empty() ? std::vector<std::pair<std::string, std::string>>{} : t.points[0])
    varied.push_back(k);
  for (const auto& [section, list] : {std::pair{"truth", &t.truth}, std::pair{"set", &t.set}})
    if (const std::string key = sets_varied_key(*list, varied); !key.empty())
      throw DiagnoseError(fmt::format(
          "{}: [{}] {}: the conditions vary this key; a twin's [{}] may not set it (its value would "
          "replace every condition's)",
          path, section, key, section));
  if (const auto* s = root["seeds"].as_array()) {
    for (const auto& x : *s) {
      const auto v = x.value<int64_t>();
      if (!v || *v < 1) throw DiagnoseError(fmt::format("{}: seeds: positive integers", path));
      t.seeds.push_back(uint64_t(*v));
    }
  }
  if (t.seeds.empty()) throw DiagnoseError(fmt::format("{}: seeds: at least one truth seed", path));
  const auto* nz = root["noise"].as_table();
  if (!nz || nz->empty())
    throw DiagnoseError(fmt::format("{}: [noise]: the measurement sd of at least one observable", path));
  for (const auto& [k, v] : *nz) {
    const auto s = v.value<double>();
    if (!s || !(*s > 0)) throw DiagnoseError(fmt::format("{}: [noise] {}: a positive number", path, k.str()));
    t.noise[std::string(k.str())] = *s;
  }
  if (root.contains("noise_seed")) {
    const auto s = root["noise_seed"].value<int64_t>();
    if (!s || *s < 0) throw DiagnoseError(fmt::format("{}: noise_seed: a non-negative integer", path));
    t.noise_seed = uint64_t(*s);
  }
  return t;
}

}  // namespace wetdem::diagnose
