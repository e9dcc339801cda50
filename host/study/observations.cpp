#include "study/observations.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <fstream>

#include "study/study_file.h"

namespace wetdem::study {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out(1);
  bool q = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (q) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"')
        out.back() += '"', ++i;
      else if (c == '"')
        q = false;
      else
        out.back() += c;
    } else if (c == '"') {
      q = true;
    } else if (c == ',') {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  for (std::string& s : out) {
    s.erase(0, s.find_first_not_of(" \t"));
    s.erase(s.find_last_not_of(" \t") + 1);
  }
  return out;
}

namespace {

bool parse_double(const std::string& s, double* v) {
  if (s.empty()) return false;
  size_t used = 0;
  try {
    *v = std::stod(s, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == s.size() && std::isfinite(*v);
}

}  // namespace

std::vector<Observation> read_observations(const std::string& path, bool allow_missing) {
  std::ifstream f(path);
  if (!f) throw StudyError(path + ": cannot read the observation table");
  std::string line;
  size_t ln = 0;
  std::vector<std::string> head;
  while (head.empty() && std::getline(f, line)) {
    ++ln;
    if (line.empty() || line[0] == '#') continue;
    head = split_csv(line);
  }
  const auto col = [&](const std::string& name) {
    for (size_t i = 0; i < head.size(); ++i)
      if (head[i] == name) return int(i);
    return -1;
  };
  const int c_obs = col("observable"), c_val = col("value"), c_sig = col("sigma"), c_n = col("n"),
            c_note = col("note");
  if (c_obs < 0 || c_val < 0 || c_sig < 0)
    throw StudyError(fmt::format("{}:{}: header: needs the columns observable, value and sigma", path, ln));
  for (int i = 0; i < c_obs; ++i)
    if (head[size_t(i)].find('.') == std::string::npos)
      throw StudyError(fmt::format("{}:{}: header: condition column \"{}\" is not a dotted case key", path,
                                   ln, head[size_t(i)]));
  for (size_t i = size_t(c_obs) + 1; i < head.size(); ++i)
    if (int(i) != c_val && int(i) != c_sig && int(i) != c_n && int(i) != c_note)
      throw StudyError(
          fmt::format("{}:{}: header: unknown column \"{}\" after observable (expected value, "
                      "sigma, n, note)",
                      path, ln, head[i]));
  std::vector<Observation> rows;
  while (std::getline(f, line)) {
    ++ln;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const std::vector<std::string> v = split_csv(line);
    const auto bad = [&](const std::string& why) {
      return StudyError(fmt::format("{}: row at line {}: {}", path, ln, why));
    };
    if (v.size() != head.size())
      throw bad(fmt::format("{} fields, the header has {}", v.size(), head.size()));
    Observation o;
    o.line = ln;
    for (int i = 0; i < c_obs; ++i) {
      if (v[size_t(i)].empty()) throw bad("empty condition " + head[size_t(i)]);
      o.conditions.push_back({head[size_t(i)], v[size_t(i)]});
    }
    o.observable = v[size_t(c_obs)];
    if (o.observable.empty()) throw bad("empty observable");
    const auto missing = [](std::string s) {
      for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
      return s.empty() || s == "na" || s == "nan" || s == "n/a";
    };
    const auto infinite = [](std::string s) {
      for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
      return s == "inf" || s == "+inf" || s == "infinity";
    };
    if (allow_missing && (missing(v[size_t(c_val)]) || infinite(v[size_t(c_sig)]))) {
      o.measured = false;
      o.value = o.sigma = std::nan("");
    } else {
      if (!parse_double(v[size_t(c_val)], &o.value))
        throw bad("value \"" + v[size_t(c_val)] + "\" is not a number");
      if (!parse_double(v[size_t(c_sig)], &o.sigma))
        throw bad("sigma \"" + v[size_t(c_sig)] + "\" is missing or not a number");
      if (!(o.sigma > 0)) throw bad(fmt::format("sigma must be positive, got {}", o.sigma));
    }
    if (c_n >= 0 && !v[size_t(c_n)].empty()) {
      double n = 0;
      if (!parse_double(v[size_t(c_n)], &n) || n < 1 || n != std::floor(n))
        throw bad("n \"" + v[size_t(c_n)] + "\" is not a positive integer");
      o.n = int(n);
    }
    if (c_note >= 0) o.note = v[size_t(c_note)];
    rows.push_back(o);
  }
  if (rows.empty()) throw StudyError(path + ": no observation rows");
  return rows;
}

}  // namespace wetdem::study
