#include "diagnose/runbook.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "app/run/resources.h"
#include "study/store.h"

namespace fs = std::filesystem;

namespace wetdem::diagnose {

std::string condition_label(const std::vector<study::AxisValue>& values) {
  std::string s;
  for (const auto& a : values) s += (s.empty() ? "" : ", ") + a.key + "=" + a.written;
  return s;
}

std::optional<std::pair<size_t, size_t>> same_condition_in_si(const std::vector<Condition>& conditions) {
  for (size_t a = 0; a < conditions.size(); ++a)
    for (size_t b = a + 1; b < conditions.size(); ++b)
      if (conditions[a].si == conditions[b].si) return std::pair{a, b};
  return std::nullopt;
}

std::string sets_varied_key(const std::vector<std::string>& settings,
                            const std::vector<std::string>& varied) {
  for (const std::string& kv : settings) {
    const std::string key = kv.substr(0, kv.find('='));
    if (std::find(varied.begin(), varied.end(), key) != varied.end()) return key;
  }
  return "";
}

std::string Variant::label() const {
  std::string l = effect.empty() ? "baseline" : fmt::format("{}@{:.6g}", effect, strength);
  if (!std::isnan(shape)) l += fmt::format("~{:.6g}", shape);
  return refit.empty() ? l : l + " [" + refit + "]";
}

RunBook::RunBook(std::string store_dir, std::string spec_path, std::string name, std::string case_path,
                 std::vector<std::string> set, study::ExecOptions exec)
    : dir_(std::move(store_dir)),
      spec_path_(std::move(spec_path)),
      name_(std::move(name)),
      case_path_(std::move(case_path)),
      set_(std::move(set)),
      exec_(std::move(exec)) {}

study::StudySpec RunBook::spec() const {
  study::StudySpec s;
  s.path = spec_path_;
  s.name = name_;
  s.base = case_path_;
  s.set = set_;
  return s;
}

study::StudySpec RunBook::spec_of(const Condition& c, const Variant& v,
                                  const std::vector<uint64_t>& seeds) const {
  study::StudySpec s = spec();
  s.seeds = seeds;
  std::vector<study::AxisValue> values = c.values;
  for (const std::string& o : v.overrides) {
    const size_t eq = o.find('=');
    values.push_back({o.substr(0, eq), o.substr(eq + 1), o.substr(eq + 1), std::nan("")});
  }
  s.points = {values};
  return s;
}

void RunBook::check(const Condition& c, const Variant& v) const {
  study::expand(spec_of(c, v, {1}));
}

namespace {

// A condition's SI values from one of its planned runs, once (want and resolve).
void fill_si(Condition& c, const study::PlannedRun& r) {
  if (!c.si.empty()) return;
  for (size_t i = 0; i < c.values.size(); ++i) {
    c.values[i].si = r.values[i].si;
    c.si[c.values[i].key] = r.values[i].si;
  }
}

}  // namespace

void RunBook::resolve(Condition& c, const Variant& v, const std::vector<uint64_t>& seeds) const {
  const std::vector<study::PlannedRun> planned = study::expand(spec_of(c, v, seeds));
  if (!planned.empty()) fill_si(c, planned.front());
}

std::string RunBook::same_physics(const study::PlannedRun& r) {
  const std::string phys = study::run_hash(app::physics_identity(r.resolved), r.seed);
  if (const auto it = phys_to_hash_.find(phys); it != phys_to_hash_.end()) return it->second;
  // Across the books sharing the store (a twin's and a diagnosis's): physics/<identity> names the first run
  // planned with it; that run is used once it is complete.
  const fs::path alias = fs::path(dir_) / "physics" / phys;
  std::string first;
  if (std::ifstream in(alias); in) in >> first;
  if (!first.empty() && first != r.hash &&
      study::run_state((fs::path(dir_) / "runs" / first).string()) == study::RunState::Complete) {
    phys_to_hash_[phys] = first;
    return first;
  }
  phys_to_hash_[phys] = r.hash;
  if (first.empty()) {  // the first planned keeps the name (a later book uses it once it completes)
    fs::create_directories(alias.parent_path());
    std::ofstream(alias) << r.hash << "\n";
  }
  return "";
}

void RunBook::want(Condition& c, const Variant& v, const std::vector<uint64_t>& seeds) {
  std::vector<study::PlannedRun> planned = study::expand(spec_of(c, v, seeds));
  for (study::PlannedRun& r : planned) {
    fill_si(c, r);
    const std::string key = c.label + "|" + v.label() + "|" + std::to_string(r.seed);
    if (key_to_hash_.count(key)) continue;
    // A run whose physics is an earlier one's (the same hash, or a liquid-only effect at a dry condition:
    // app::physics_identity) is that run: the same bits, computed once.
    if (const std::string same = same_physics(r); !same.empty()) {
      key_to_hash_[key] = same;
      continue;
    }
    key_to_hash_[key] = r.hash;
    r.point = points_.size();
    points_.push_back(r.values);
    r.index = runs_.size();
    runs_.push_back(std::move(r));
  }
}

size_t RunBook::run() {
  study::StudySpec s = spec();
  s.points = points_;
  const study::StoreLock lock(dir_);  // the plan is this book's until its runs are done
  study::write_plan(dir_, s, runs_);
  const study::ExecReport rep = study::run_study(dir_, exec_);
  wall_s_ += rep.wall_s;
  computed_ += rep.completed;
  if (rep.interrupted) throw std::runtime_error("interrupted; run the same command again to continue");
  for (const study::PlannedRun& r : runs_) {
    std::string why;
    const fs::path dir = fs::path(dir_) / "runs" / r.hash;
    const study::RunState st = study::run_state(dir.string(), &why);
    if (st == study::RunState::Complete) continue;
    if (st == study::RunState::Failed)
      failed_[r.hash] = why.empty() ? "failed" : why;
    else
      failed_[r.hash] = std::string("did not complete (") + study::state_name(st) + ")";
  }
  return failed_.size();
}

std::string RunBook::failure(const Condition& c, const Variant& v, uint64_t seed) const {
  const auto it = key_to_hash_.find(c.label + "|" + v.label() + "|" + std::to_string(seed));
  if (it == key_to_hash_.end()) return "";
  const auto f = failed_.find(it->second);
  return f == failed_.end() ? "" : f->second;
}

std::string RunBook::failure(const std::vector<Condition>& cs, const Variant& v,
                             const std::vector<uint64_t>& seeds) const {
  for (const Condition& c : cs)
    for (uint64_t seed : seeds)
      if (std::string why = failure(c, v, seed); !why.empty())
        return fmt::format("{} at {} (seed {}): {}", v.label(), c.label, seed, why);
  return "";
}

bool RunBook::has_summaries(const std::vector<Condition>& cs, const Variant& v,
                            const std::vector<uint64_t>& seeds) const {
  for (const Condition& c : cs)
    for (uint64_t seed : seeds) {
      const auto it = key_to_hash_.find(c.label + "|" + v.label() + "|" + std::to_string(seed));
      if (it == key_to_hash_.end()) return false;
      if (summaries_.count(it->second)) continue;
      if (!fs::exists(fs::path(dir_) / "runs" / it->second / "summary.json")) return false;
    }
  return true;
}

double RunBook::steps(const Condition& c, const Variant& v) const {
  const std::vector<study::PlannedRun> r = study::expand(spec_of(c, v, {1}));
  return app::estimate_resources(r.front().resolved).steps;
}

double RunBook::particle_steps(const Condition& c, const Variant& v) const {
  const std::vector<study::PlannedRun> r = study::expand(spec_of(c, v, {1}));
  return app::estimate_resources(r.front().resolved).particle_steps;
}

const nlohmann::json& RunBook::summary(const std::string& hash) const {
  auto it = summaries_.find(hash);
  if (it != summaries_.end()) return it->second;
  const fs::path p = fs::path(dir_) / "runs" / hash / "summary.json";
  std::ifstream f(p);
  if (!f) throw std::runtime_error("run " + hash + " has no summary.json (" + p.string() + ")");
  return summaries_[hash] = nlohmann::json::parse(f);
}

std::string RunBook::device() const {
  for (const auto& [h, j] : summaries_)
    if (j.contains("device") && j["device"].is_string()) return j["device"].get<std::string>();
  return "";
}

std::string sem_key(const std::string& observable, const nlohmann::json& s) {
  std::vector<std::string> cands = {observable + "_sem"};
  if (observable == "aor_deg_mean") cands.insert(cands.begin(), "aor_sem_block");
  const std::string suffix = "_mean";
  if (observable.size() > suffix.size() &&
      observable.compare(observable.size() - suffix.size(), suffix.size(), suffix) == 0)
    cands.push_back(observable.substr(0, observable.size() - suffix.size()) + "_sem");
  for (const std::string& k : cands)
    if (s.contains(k) && s[k].is_number()) return k;
  return "";
}

const nlohmann::json& RunBook::summary_of(const Condition& c, const Variant& v, uint64_t seed) const {
  const std::string key = c.label + "|" + v.label() + "|" + std::to_string(seed);
  auto it = key_to_hash_.find(key);
  if (it == key_to_hash_.end()) throw std::logic_error("RunBook: run not wanted: " + key);
  return summary(it->second);
}

bool RunBook::reports(const Condition& c, const Variant& v, const std::vector<uint64_t>& seeds,
                      const std::string& observable) const {
  for (uint64_t seed : seeds) {
    const nlohmann::json& s = summary_of(c, v, seed);
    if (s.contains(observable) && s[observable].is_number()) return true;
  }
  return false;
}

Prediction RunBook::predict(const Condition& c, const Variant& v, const std::vector<uint64_t>& seeds,
                            const std::string& observable, double f) const {
  std::vector<double> x;
  double own2 = 0.0;  // Σ of the runs' own window SE², over the runs that report one
  size_t owned = 0;
  for (uint64_t seed : seeds) {
    const nlohmann::json& s = summary_of(c, v, seed);
    if (!s.contains(observable) || !s[observable].is_number()) continue;  // flagged or absent in this run
    x.push_back(s[observable].get<double>());
    const std::string k = sem_key(observable, s);
    if (!k.empty()) own2 += s[k].get<double>() * s[k].get<double>(), ++owned;
  }
  if (x.empty())
    throw std::runtime_error(fmt::format("no run of {} at {} reports '{}'", v.label(), c.label, observable));
  Prediction p;
  for (double a : x) p.mean += a;
  p.mean /= double(x.size());
  // Two estimates of the error of the mean: the spread between the seeds (sd/√n, one degree of freedom with
  // two seeds, so often far too small by chance) and the runs' own window errors (from the autocorrelation of
  // each window, √(mean SE²/n)). The larger is kept: a cell is never called significant because two seeds
  // happened to agree.
  const double within = owned ? f * std::sqrt(own2 / double(owned) / double(x.size())) : 0.0;
  double between = 0.0;
  if (x.size() >= 2) {
    double ss = 0;
    for (double a : x) ss += (a - p.mean) * (a - p.mean);
    between = std::sqrt(ss / double(x.size() - 1) / double(x.size()));
  }
  p.se = std::max(between, within);
  return p;
}

}  // namespace wetdem::diagnose
