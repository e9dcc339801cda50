#include "diagnose/refit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "app/case/case.h"
#include "diagnose/files.h"
#include "study/study_file.h"

namespace wetdem::diagnose {

namespace {

// The resolved case's SI value of `key` (NaN when the key has no numeric value).
double resolved_si(const std::string& case_path, std::vector<std::string> set, const std::string& over,
                   const std::string& key) {
  if (!over.empty()) set.push_back(over);
  return study::si_of_key(app::case_to_json(app::parse_case_file(case_path, set)), key);
}

bool same_value(double a, double b) {
  return std::fabs(a - b) <= 1e-12 * std::max(std::fabs(a), std::fabs(b));
}

}  // namespace

std::vector<RefitKey> parse_refit(const toml::table& root, const std::string& path,
                                  const std::string& case_path, const std::vector<std::string>& set,
                                  const std::map<std::string, std::string>& effect_keys) {
  const auto* names = root["refit"].as_array();
  if (!names || names->empty())
    throw DiagnoseError(fmt::format(
        "{}: refit: an array of case keys is required with [refit_values] (e.g. refit = [\"liquid.v_max\"])",
        path));
  const auto* table = root["refit_values"].as_table();
  if (!table)
    throw DiagnoseError(fmt::format(
        "{}: [refit_values]: the values to try for each refit key are required (e.g. \"liquid.v_max\" = "
        "[\"0.5 %\", \"2 %\"])",
        path));
  std::vector<RefitKey> keys;
  for (const auto& n : *names) {
    if (!n.is_string()) throw DiagnoseError(fmt::format("{}: refit: keys must be strings", path));
    RefitKey k;
    k.key = n.as_string()->get();
    for (const RefitKey& q : keys)
      if (q.key == k.key) throw DiagnoseError(fmt::format("{}: refit: \"{}\" named twice", path, k.key));
    if (k.key == "run.seed" || k.key == "seed")
      throw DiagnoseError(fmt::format("{}: refit: \"{}\": the seed is not a model parameter", path, k.key));
    if (auto e = effect_keys.find(k.key); e != effect_keys.end())
      throw DiagnoseError(fmt::format(
          "{}: refit: \"{}\" is the key of the candidate effect '{}' (the fit could not tell them "
          "apart); drop one of them",
          path, k.key, e->second));
    const auto* vals = (*table)[k.key].as_array();
    if (!vals || vals->empty())
      throw DiagnoseError(
          fmt::format("{}: [refit_values] \"{}\": a non-empty array of values is required", path, k.key));
    for (const auto& v : *vals) {
      RefitValue x;
      try {
        x.toml = value_toml(v);
      } catch (const DiagnoseError& e) {
        throw DiagnoseError(fmt::format("{}: [refit_values] \"{}\": {}", path, k.key, e.what()));
      }
      x.written = v.is_string()           ? v.as_string()->get()
                  : v.is_floating_point() ? fmt::format("{}", v.as_floating_point()->get())  // shortest
                                          : x.toml;
      try {
        x.si = resolved_si(case_path, set, k.key + "=" + x.toml, k.key);
      } catch (const app::CaseError& e) {
        throw DiagnoseError(fmt::format("{}: [refit_values] \"{}\" = {}: {}", path, k.key, x.toml, e.what()));
      }
      if (std::isnan(x.si))
        throw DiagnoseError(fmt::format(
            "{}: refit: \"{}\": not a numeric case key (only numbers can be re-fitted)", path, k.key));
      for (const RefitValue& q : k.values)
        if (same_value(q.si, x.si))
          throw DiagnoseError(fmt::format("{}: [refit_values] \"{}\": {} and {} are the same value", path,
                                          k.key, q.written, x.written));
      k.values.push_back(x);
    }
    try {
      k.calibrated_si = resolved_si(case_path, set, "", k.key);
    } catch (const app::CaseError& e) {
      throw DiagnoseError(fmt::format("{}: case {}: {}", path, case_path, e.what()));
    }
    // The calibrated value is always setting 0; listing it again adds nothing.
    k.values.erase(std::remove_if(k.values.begin(), k.values.end(),
                                  [&](const RefitValue& x) { return same_value(x.si, k.calibrated_si); }),
                   k.values.end());
    if (k.values.empty())
      throw DiagnoseError(
          fmt::format("{}: [refit_values] \"{}\": no value other than the calibrated one ({:.6g} SI)", path,
                      k.key, k.calibrated_si));
    keys.push_back(k);
  }
  for (const auto& [name, v] : *table) {
    (void)v;
    if (std::none_of(keys.begin(), keys.end(), [&](const RefitKey& k) { return k.key == name.str(); }))
      throw DiagnoseError(fmt::format("{}: [refit_values] \"{}\": not named in refit", path, name.str()));
  }
  size_t n = 1;
  for (const RefitKey& k : keys) n *= k.values.size() + 1;
  if (n > kMaxRefitSettings)
    throw DiagnoseError(
        fmt::format("{}: refit: {} settings (the product of the value counts, each plus the calibrated "
                    "value); at most {}",
                    path, n, kMaxRefitSettings));
  return keys;
}

std::vector<RefitSetting> refit_settings(const std::vector<RefitKey>& keys) {
  std::vector<RefitSetting> out;
  std::vector<size_t> ix(keys.size(), 0);  // 0: the calibrated value, i > 0: values[i - 1]
  for (;;) {
    RefitSetting s;
    for (size_t k = 0; k < keys.size(); ++k) {
      if (ix[k] == 0) {
        s.si[keys[k].key] = keys[k].calibrated_si;
        continue;
      }
      const RefitValue& v = keys[k].values[ix[k] - 1];
      s.overrides.push_back(keys[k].key + "=" + v.toml);
      s.si[keys[k].key] = v.si;
      s.label += (s.label.empty() ? "" : ", ") + keys[k].key + "=" + v.written;
    }
    if (s.label.empty()) s.label = "calibrated";
    out.push_back(s);
    size_t k = ix.size();
    while (k > 0 && ++ix[k - 1] == keys[k - 1].values.size() + 1) ix[--k] = 0;
    if (k == 0) break;
  }
  return out;
}

}  // namespace wetdem::diagnose
