#include "study/study_file.h"

#include "app/run/resources.h"
#include "wetdem/version.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#ifndef WETDEM_VERSION
#define WETDEM_VERSION "unknown"
#endif

namespace wetdem::study {

namespace fs = std::filesystem;

namespace {

// A scalar as written and as TOML text. Tables and arrays are not axis values.
bool scalar_text(const toml::node& n, std::string* written, std::string* toml_text) {
  if (const auto* s = n.as_string()) {
    *written = s->get();
    std::ostringstream os;
    os << *s;  // quoted and escaped
    *toml_text = os.str();
    return true;
  }
  if (const auto* i = n.as_integer()) return *written = *toml_text = std::to_string(i->get()), true;
  if (const auto* f = n.as_floating_point()) {
    std::string t = fmt::format("{}", f->get());
    if (t.find_first_of(".eEn") == std::string::npos) t += ".0";
    return *written = *toml_text = t, true;
  }
  if (const auto* b = n.as_boolean()) return *written = *toml_text = b->get() ? "true" : "false", true;
  return false;
}

// Position in the file, so that [axes] keep the order they were written in (toml::table is sorted).
std::pair<uint32_t, uint32_t> pos(const toml::node& n) {
  return {n.source().begin.line, n.source().begin.column};
}

// Flattens a table of overrides ("run.duration" = ..., or [set.run] duration = ...) into AxisValues in file
// order.
void flatten(const toml::table& t, const std::string& prefix, const std::string& where,
             const std::string& file, std::vector<std::pair<std::pair<uint32_t, uint32_t>, AxisValue>>* out) {
  for (auto&& [k, v] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = v.as_table()) {
      flatten(*sub, key, where, file, out);
      continue;
    }
    AxisValue a;
    a.key = key;
    if (!scalar_text(v, &a.written, &a.toml))
      throw StudyError(fmt::format("{}: {}: {}: expected a number, string or boolean", file, where, key));
    out->push_back({pos(v), a});
  }
}

std::vector<AxisValue> flat_in_order(const toml::table& t, const std::string& where,
                                     const std::string& file) {
  std::vector<std::pair<std::pair<uint32_t, uint32_t>, AxisValue>> v;
  flatten(t, "", where, file, &v);
  std::stable_sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<AxisValue> r;
  for (auto& e : v) r.push_back(e.second);
  return r;
}

std::string describe(const std::vector<AxisValue>& p) {
  std::string s;
  for (const AxisValue& a : p) s += (s.empty() ? "" : ", ") + a.key + " = " + a.written;
  return s.empty() ? "the base case" : s;
}

}  // namespace

std::string override_of(const AxisValue& v) {
  return v.key + "=" + v.toml;
}

std::string code_version() {
  return wetdem::run_version();
}

std::string run_hash(const app::Case& c, uint64_t seed, const std::string& version) {
  // nlohmann::json objects are std::map: dump() writes keys sorted, doubles in round-trip form.
  const std::string text =
      app::case_to_json(c).dump() + "\nseed=" + std::to_string(seed) + "\ncode=" + version;
  uint64_t h = 1469598103934665603ull;
  for (unsigned char b : text) h = (h ^ b) * 1099511628211ull;
  return fmt::format("{:016x}", h);
}

double si_of_key(const nlohmann::json& cj, const std::string& key) {
  const size_t dot = key.rfind('.');
  const nlohmann::json* sec = &cj;
  if (dot != std::string::npos) {
    std::stringstream ss(key.substr(0, dot));
    for (std::string p; std::getline(ss, p, '.');) {
      if (!sec->is_object() || !sec->contains(p)) return std::nan("");
      sec = &(*sec)[p];
    }
  }
  std::string leaf = dot == std::string::npos ? key : key.substr(dot + 1);
  if (leaf == "rpm" || leaf.rfind("rotation", 0) == 0) leaf = "rotation";
  if (!sec->is_object()) return std::nan("");
  // The key itself, or, dropping unit suffixes one at a time (content_pct -> content), its SI spelling.
  for (std::string b = leaf; !b.empty();) {
    for (auto it = sec->begin(); it != sec->end(); ++it)
      if ((it.key() == b || it.key().rfind(b + "_", 0) == 0) && it->is_number()) return it->get<double>();
    const size_t u = b.rfind('_');
    if (u == std::string::npos) break;
    b = b.substr(0, u);
  }
  return std::nan("");
}

StudySpec parse_study_file(const std::string& path) {
  StudySpec s;
  s.path = fs::absolute(path).lexically_normal().string();
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw StudyError(fmt::format("{}:{}: {}", path, e.source().begin.line, e.description()));
  } catch (const std::exception& e) {
    throw StudyError(fmt::format("{}: {}", path, e.what()));
  }
  const auto err = [&](const std::string& key, const std::string& why) {
    return StudyError(fmt::format("{}: {}: {}", path, key, why));
  };
  static const std::set<std::string> known = {"name", "description", "base",   "replicates",  "seeds",
                                              "set",  "axes",        "points", "observations"};
  for (auto&& [k, v] : root)
    if (!known.count(std::string(k.str())))
      throw err(std::string(k.str()),
                "unknown key (expected one of name, description, base, replicates, "
                "seeds, set, axes, points, observations)");
  const fs::path dir = fs::path(s.path).parent_path();
  s.name = root["name"].value_or(fs::path(path).stem().string());
  const auto base = root["base"].value<std::string>();
  if (!base) throw err("base", "required: the case file every run starts from (relative to the study file)");
  s.base = (dir / *base).lexically_normal().string();
  if (!fs::exists(s.base)) throw err("base", "no such file: " + s.base);

  if (root.contains("seeds") && root.contains("replicates"))
    throw err("seeds", "give either replicates or seeds, not both");
  if (const auto* a = root["seeds"].as_array()) {
    for (const toml::node& n : *a) {
      const auto v = n.value<int64_t>();
      if (!v || *v < 0) throw err("seeds", "expected non-negative integers");
      s.seeds.push_back(uint64_t(*v));
    }
    if (s.seeds.empty()) throw err("seeds", "empty");
    if (std::set<uint64_t>(s.seeds.begin(), s.seeds.end()).size() != s.seeds.size())
      throw err("seeds", "repeated seed");
  } else if (root.contains("seeds")) {
    throw err("seeds", "expected an array of integers");
  } else if (root.contains("replicates")) {
    const auto r = root["replicates"].value<int64_t>();
    if (!r || *r < 1 || *r > 10000) throw err("replicates", "expected an integer in [1, 10000]");
    for (int64_t i = 1; i <= *r; ++i) s.seeds.push_back(uint64_t(i));
  }

  if (root.contains("set")) {
    const auto* t = root["set"].as_table();
    if (!t) throw err("set", "expected a table of case keys");
    for (const AxisValue& a : flat_in_order(*t, "set", path)) s.set.push_back(override_of(a));
  }
  // The base case with [set] alone, so that a bad [set] key is reported as such.
  app::Case base_case;
  try {
    base_case = app::parse_case_file(s.base, s.set);
  } catch (const app::CaseError& e) {
    throw StudyError(fmt::format("{}: [set] on {}: {}", path, s.base, e.what()));
  }
  if (s.seeds.empty()) s.seeds.push_back(base_case.run.seed);

  if (root.contains("axes")) {
    const auto* t = root["axes"].as_table();
    if (!t) throw err("axes", "expected a table: case key = [values]");
    std::vector<std::pair<std::pair<uint32_t, uint32_t>, std::string>> order;
    for (auto&& [k, v] : *t) order.push_back({pos(v), std::string(k.str())});
    std::sort(order.begin(), order.end());
    std::vector<std::vector<AxisValue>> values;
    for (const auto& [p, key] : order) {
      const auto* arr = (*t)[key].as_array();
      if (!arr || arr->empty()) throw err("axes." + key, "expected a non-empty array of values");
      std::vector<AxisValue> vs;
      for (const toml::node& n : *arr) {
        AxisValue a;
        a.key = key;
        if (!scalar_text(n, &a.written, &a.toml)) throw err("axes." + key, "values must be scalars");
        vs.push_back(a);
      }
      s.axis_keys.push_back(key);
      values.push_back(vs);
    }
    // Cartesian product, the first axis slowest.
    std::vector<size_t> ix(values.size(), 0);
    while (true) {
      std::vector<AxisValue> p;
      for (size_t a = 0; a < values.size(); ++a) p.push_back(values[a][ix[a]]);
      s.points.push_back(p);
      size_t a = values.size();
      while (a > 0 && ++ix[a - 1] == values[a - 1].size()) ix[--a] = 0;
      if (a == 0) break;
    }
  }
  if (root.contains("points")) {
    const auto* arr = root["points"].as_array();
    if (!arr) throw err("points", "expected [[points]] tables");
    size_t i = 0;
    for (const toml::node& n : *arr) {
      const auto* t = n.as_table();
      if (!t) throw err(fmt::format("points[{}]", i), "expected a table");
      s.points.push_back(flat_in_order(*t, fmt::format("points[{}]", i), path));
      ++i;
    }
  }
  if (s.points.empty()) s.points.push_back({});

  if (root.contains("observations")) {
    const auto* t = root["observations"].as_table();
    if (!t) throw err("observations", "expected a table with file and fit");
    const auto f = (*t)["file"].value<std::string>();
    if (!f) throw err("observations.file", "required: the observation table (CSV)");
    s.observations.file = (dir / *f).lexically_normal().string();
    if (!fs::exists(s.observations.file))
      throw err("observations.file", "no such file: " + s.observations.file);
    if (const auto* fa = (*t)["fit"].as_array())
      for (const toml::node& n : *fa) {
        const auto k = n.value<std::string>();
        if (!k) throw err("observations.fit", "expected case keys (strings)");
        bool varied = false;
        for (const auto& p : s.points)
          for (const AxisValue& a : p) varied |= a.key == *k;
        if (!varied) throw err("observations.fit", "\"" + *k + "\" is not an axis or point key of the study");
        s.observations.fit.push_back(*k);
      }
    if (s.observations.fit.empty()) throw err("observations.fit", "required: the axes being calibrated");
  }
  return s;
}

std::vector<PlannedRun> expand(const StudySpec& s) {
  std::vector<PlannedRun> runs;
  std::set<std::string> seen;
  for (size_t p = 0; p < s.points.size(); ++p)
    for (uint64_t seed : s.seeds) {
      PlannedRun r;
      r.index = runs.size();
      r.point = p;
      r.seed = seed;
      r.values = s.points[p];
      r.overrides = s.set;
      for (const AxisValue& a : r.values) r.overrides.push_back(override_of(a));
      r.overrides.push_back("run.seed=" + std::to_string(seed));
      try {
        r.resolved = app::parse_case_file(s.base, r.overrides);
        app::check_reach(r.resolved);
      } catch (const app::CaseError& e) {
        throw StudyError(fmt::format("{}: point {} ({}): {}", s.path, p, describe(r.values), e.what()),
                         e.what());
      }
      const nlohmann::json cj = app::case_to_json(r.resolved);
      for (AxisValue& a : r.values) a.si = si_of_key(cj, a.key);
      r.hash = run_hash(r.resolved, seed);
      if (!seen.insert(r.hash).second)
        throw StudyError(fmt::format("{}: point {} ({}), seed {}: the same resolved case as an earlier run",
                                     s.path, p, describe(r.values), seed));
      runs.push_back(std::move(r));
    }
  return runs;
}

}  // namespace wetdem::study
