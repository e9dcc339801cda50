#include "study/collect.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "app/output/summary.h"

#ifndef WETDEM_SOURCE_DIR
#define WETDEM_SOURCE_DIR "."
#endif

namespace wetdem::study {

namespace fs = std::filesystem;

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string num(double x) {
  return std::isfinite(x) ? fmt::format("{:.9g}", x) : std::string();
}

std::string scalar_text(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return v.dump();
  if (v.is_number()) return num(v.get<double>());
  if (v.is_string()) return csv_field(v.get<std::string>());
  return "";
}

bool is_scalar(const nlohmann::json& v) {
  return v.is_null() || v.is_boolean() || v.is_number() || v.is_string();
}

}  // namespace

Stats stats_of(const std::vector<double>& v) {
  Stats s;
  s.n = v.size();
  s.mean = s.sd = s.se = std::nan("");
  if (v.empty()) return s;
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / double(v.size());
  if (v.size() < 2) return s;
  double ss = 0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.sd = std::sqrt(ss / double(v.size() - 1));
  s.se = s.sd / std::sqrt(double(v.size()));
  return s;
}

std::string plot_script() {
  if (const char* e = std::getenv("WETDEM_PLOT_SCRIPT")) return e;
  return std::string(WETDEM_SOURCE_DIR) + "/scripts/plot_study.py";
}

Collected gather(const std::string& dir) {
  Collected c;
  c.index = read_index(dir);
  std::set<std::string> keys;
  for (const IndexEntry& e : c.index.runs) {
    const fs::path rd = fs::path(dir) / e.run_dir;
    c.states.push_back(state_name(run_state(rd.string())));
    nlohmann::json j;
    if (c.states.back() == std::string("complete")) {
      std::ifstream f(rd / "summary.json");
      try {
        j = nlohmann::json::parse(f);
      } catch (const std::exception& ex) {
        throw StudyError((rd / "summary.json").string() + ": " + ex.what());
      }
      for (auto it = j.begin(); it != j.end(); ++it)
        if (it->is_number() && !it->is_boolean()) keys.insert(it.key());
    }
    c.summaries.push_back(j);
  }
  c.numeric_keys.assign(keys.begin(), keys.end());
  c.points.resize(c.index.points);
  for (size_t p = 0; p < c.points.size(); ++p) c.points[p].point = p;
  std::map<size_t, std::map<std::string, std::vector<double>>> vals;
  for (size_t i = 0; i < c.index.runs.size(); ++i) {
    const IndexEntry& e = c.index.runs[i];
    PointResult& pr = c.points.at(e.point);
    pr.values = e.values;
    ++pr.runs;
    if (c.summaries[i].is_null()) continue;
    ++pr.complete;
    pr.run_dirs.push_back(e.run_dir);
    for (const std::string& k : c.numeric_keys) {
      const auto it = c.summaries[i].find(k);
      if (it != c.summaries[i].end() && it->is_number()) vals[e.point][k].push_back(it->get<double>());
    }
  }
  for (PointResult& pr : c.points)
    for (const std::string& k : c.numeric_keys) pr.stats[k] = stats_of(vals[pr.point][k]);
  return c;
}

Collected collect(const std::string& dir, const CollectOptions& opt) {
  Collected c = gather(dir);
  const fs::path d(dir);
  const auto& keys = c.index.axis_keys;

  // runs.csv: one row per run, every scalar of its summary.json.
  std::vector<std::string> scalar_keys;
  {
    std::set<std::string> seen;
    for (const auto& s : c.summaries)
      for (auto it = s.begin(); s.is_object() && it != s.end(); ++it)
        if (is_scalar(*it) && seen.insert(it.key()).second) scalar_keys.push_back(it.key());
    std::sort(scalar_keys.begin(), scalar_keys.end());
  }
  std::ostringstream rc;
  rc << "index,point,seed,hash,status,run_dir";
  for (const std::string& k : keys) rc << ',' << csv_field(k) << ',' << csv_field(k + " [SI]");
  for (const std::string& k : scalar_keys) rc << ',' << k;
  rc << '\n';
  for (size_t i = 0; i < c.index.runs.size(); ++i) {
    const IndexEntry& e = c.index.runs[i];
    rc << e.index << ',' << e.point << ',' << e.seed << ',' << e.hash << ',' << c.states[i] << ','
       << e.run_dir;
    for (const std::string& k : keys) {
      const AxisValue* a = nullptr;
      for (const AxisValue& v : e.values)
        if (v.key == k) a = &v;
      rc << ',' << (a ? csv_field(a->written) : "") << ',' << (a ? num(a->si) : "");
    }
    for (const std::string& k : scalar_keys)
      rc << ','
         << (c.summaries[i].is_object() && c.summaries[i].contains(k) ? scalar_text(c.summaries[i][k]) : "");
    rc << '\n';
  }
  app::write_file_atomic((d / "runs.csv").string(), rc.str());

  // points.csv: one row per point, mean / sd / se over its complete replicates.
  std::ostringstream pc;
  pc << "point";
  for (const std::string& k : keys) pc << ',' << csv_field(k) << ',' << csv_field(k + " [SI]");
  pc << ",runs,n";
  for (const std::string& k : c.numeric_keys)
    pc << ',' << k << "_mean," << k << "_sd," << k << "_se," << k << "_n";
  pc << '\n';
  for (const PointResult& p : c.points) {
    pc << p.point;
    for (const std::string& k : keys) {
      const AxisValue* a = nullptr;
      for (const AxisValue& v : p.values)
        if (v.key == k) a = &v;
      pc << ',' << (a ? csv_field(a->written) : "") << ',' << (a ? num(a->si) : "");
    }
    pc << ',' << p.runs << ',' << p.complete;
    for (const std::string& k : c.numeric_keys) {
      const Stats& s = p.stats.at(k);
      pc << ',' << num(s.mean) << ',' << num(s.sd) << ',' << num(s.se) << ',' << s.n;
    }
    pc << '\n';
  }
  app::write_file_atomic((d / "points.csv").string(), pc.str());

  // Figures.
  std::vector<std::string> figures;
  std::string fig_note;
  if (opt.figures) {
    fs::create_directories(d / "figures");
    const std::string script = plot_script();
    const std::string cmd = fmt::format("'{}' '{}' '{}' > '{}' 2>&1", opt.python, script, dir,
                                        (d / "figures" / "plot.log").string());
    const int rcode = std::system(cmd.c_str());
    if (rcode != 0)
      fig_note = fmt::format("figures: `{} {}` failed (see figures/plot.log)", opt.python, script);
    for (const auto& f : fs::directory_iterator(d / "figures"))
      if (f.path().extension() == ".png") figures.push_back("figures/" + f.path().filename().string());
    std::sort(figures.begin(), figures.end());
  }

  // report.md
  size_t complete = 0, failed = 0;
  for (const std::string& s : c.states) complete += s == "complete", failed += s == "failed";
  std::ostringstream md;
  md << "# Study " << c.index.name << "\n\n";
  md << fmt::format("Study file `{}`, base case `{}`, code {}.\n\n", c.index.study_file, c.index.base,
                    c.index.code_version);
  md << fmt::format("{} runs ({} points): {} complete, {} failed, {} not complete.\n\n", c.index.runs.size(),
                    c.points.size(), complete, failed, c.index.runs.size() - complete - failed);
  md << "## Points (mean ± standard error over replicates)\n\n|";
  for (const std::string& k : keys) md << ' ' << k << " |";
  md << " n | AoR (deg) | f_wet | bridges | contacts |\n|";
  for (size_t i = 0; i < keys.size() + 5; ++i) md << "---|";
  md << '\n';
  auto pm = [&](const PointResult& p, const std::string& k, int prec) {
    const auto it = p.stats.find(k);
    if (it == p.stats.end() || it->second.n == 0) return std::string("–");
    const Stats& s = it->second;
    return std::isfinite(s.se) ? fmt::format("{:.{}f} ± {:.{}f}", s.mean, prec, s.se, prec)
                               : fmt::format("{:.{}f}", s.mean, prec);
  };
  for (const PointResult& p : c.points) {
    md << '|';
    for (const std::string& k : keys) {
      std::string w = "–";
      for (const AxisValue& v : p.values)
        if (v.key == k) w = v.written;
      md << ' ' << w << " |";
    }
    md << ' ' << p.complete << " | " << pm(p, "aor_deg_mean", 2) << " | " << pm(p, "f_wet_mean", 3) << " | "
       << pm(p, "bridges_mean", 1) << " | " << pm(p, "contacts_mean", 1) << " |\n";
  }
  std::vector<std::string> problems;
  for (size_t i = 0; i < c.index.runs.size(); ++i)
    if (c.states[i] != "complete") {
      std::string why;
      run_state((d / c.index.runs[i].run_dir).string(), &why);
      problems.push_back(fmt::format("- run {} ({}): {}{}", i, c.index.runs[i].hash, c.states[i],
                                     why.empty() ? "" : ": " + why));
    }
  if (!problems.empty()) {
    md << "\n## Runs not complete\n\n";
    for (const std::string& s : problems) md << s << '\n';
  }
  md << "\n## Figures\n\n";
  if (!fig_note.empty()) md << fig_note << "\n\n";
  for (const std::string& f : figures) md << "![" << fs::path(f).stem().string() << "](" << f << ")\n\n";
  md << "Tables: [runs.csv](runs.csv) (one row per run), [points.csv](points.csv) (mean, sd, se, n per "
        "point).\n";
  app::write_file_atomic((d / "report.md").string(), md.str());
  return c;
}

}  // namespace wetdem::study
