#include "diagnose/twin.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "app/case/case.h"
#include "app/output/summary.h"
#include "diagnose/observables.h"
#include "diagnose/runbook.h"
#include "diagnose/table.h"

namespace fs = std::filesystem;

namespace wetdem::diagnose {

double noisy_measurement(const std::string& observable, double mean, double sd, std::mt19937_64& rng) {
  const ObservableSpec* o = find_observable(observable);
  const double lo = o ? o->lo : -1e300, hi = o ? o->hi : 1e300;
  const bool has_lo = lo > -1e299, has_hi = hi < 1e299;
  const double m = std::clamp(mean, lo, hi);
  if (!(sd > 0)) return m;
  const double below = has_lo ? (m - lo) / sd : 1e300, above = has_hi ? (hi - m) / sd : 1e300;
  if (std::min(below, above) >= 6) {
    // Far from every bound (a draw outside has p < 1e-9): plain Gaussian, redrawn in the impossible case.
    std::normal_distribution<double> unit(0.0, 1.0);
    for (int i = 0; i < 100; ++i) {
      const double y = m + sd * unit(rng);
      if (y >= lo && y <= hi) return y;
    }
    return m;
  }
  // Near a bound a Gaussian truncated there has a mean above the truth (the half-normal's 0.8 sd at the
  // bound) and would show every dry cell a gap the model does not have. A distribution on the possible range
  // with the truth's mean and the given sd has no such bias: a gamma on one side of one bound, a beta between
  // two. A mean on a bound is the bound itself (a dry bed's f_wet is 0, a camera with no clumps sees size 1).
  if (below == 0 || above == 0) return m;
  const auto gamma = [&](double d) {  // mean d, sd sd: shape (d/sd)^2, scale sd^2/d
    std::gamma_distribution<double> g((d / sd) * (d / sd), sd * sd / d);
    return g(rng);
  };
  if (has_lo && !has_hi) return lo + gamma(m - lo);
  if (has_hi && !has_lo) return hi - gamma(hi - m);
  const double w = hi - lo, mu = (m - lo) / w;
  // The largest variance a distribution on [0, 1] with mean mu can have is mu (1 - mu); a sd beyond it (a
  // fraction near 0 with noise 0.5) is capped just below, so the draw stays a proper beta.
  const double v = std::min((sd / w) * (sd / w), 0.9 * mu * (1 - mu));
  const double c = mu * (1 - mu) / v - 1;
  std::gamma_distribution<double> ga(mu * c, 1.0), gb((1 - mu) * c, 1.0);
  const double a = ga(rng), b = gb(rng);
  return a + b > 0 ? lo + w * a / (a + b) : m;
}

nlohmann::json run_twin(const TwinSpec& t, const DiagnoseOptions& o) {
  const std::string store = o.store.empty() ? (fs::path(o.out) / "store").string() : o.store;
  study::ExecOptions exec;
  exec.jobs = o.jobs;
  exec.batch = o.batch;
  exec.device = o.device;
  exec.exe = o.exe;
  exec.quiet = o.quiet;
  RunBook book(store, t.path, t.name, t.case_path, t.set, exec);
  Variant truth;
  truth.effect = "truth";
  truth.overrides = t.truth;
  // The conditions: the explicit [[points]], or the Cartesian product of [conditions] (last key fastest).
  std::vector<Condition> conds;
  const auto add = [&](const std::vector<std::pair<std::string, std::string>>& kv) {
    Condition c;
    for (const auto& [key, tv] : kv) {
      std::string written = tv;
      if (written.size() >= 2 && written.front() == '"') written = written.substr(1, written.size() - 2);
      c.values.push_back({key, written, tv, std::nan("")});
    }
    std::sort(c.values.begin(), c.values.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
    c.label = condition_label(c.values);
    conds.push_back(c);
  };
  if (!t.points.empty()) {
    for (const auto& p : t.points) add(p);
  } else {
    std::vector<size_t> idx(t.condition_keys.size(), 0);
    for (;;) {
      std::vector<std::pair<std::string, std::string>> kv;
      for (size_t k = 0; k < idx.size(); ++k)
        kv.emplace_back(t.condition_keys[k], t.condition_toml[k][idx[k]]);
      add(kv);
      size_t k = idx.size();
      while (k > 0 && ++idx[k - 1] == t.condition_toml[k - 1].size()) idx[--k] = 0;
      if (k == 0) break;
    }
  }
  for (const auto& [obs, sd] : t.noise) {
    (void)sd;
    if (!find_observable(obs))
      throw DiagnoseError(
          fmt::format("{}: [noise] {}: unknown observable (known: {})", t.path, obs, observable_names()));
  }
  {  // The model must be able to produce every observable asked for (an end-plate angle needs plates).
    const app::Case c = app::parse_case_file(t.case_path, t.set);
    for (const auto& [obs, sd] : t.noise) {
      (void)sd;
      if (find_observable(obs)->needs_plates && c.drum.periodic_slice)
        throw DiagnoseError(fmt::format(
            "{}: [noise] {}: the model cannot produce it: it is a periodic slice, which has no end plates",
            t.path, obs));
    }
  }
  for (Condition& c : conds) {
    try {
      if (o.check)
        book.resolve(c, truth, t.seeds);  // validated as want does; the store is not touched
      else
        book.want(c, truth, t.seeds);
    } catch (const study::StudyError& e) {  // named as the user wrote it, not as the study's point number
      throw DiagnoseError(
          fmt::format("{}: the condition {} (the truth's run there): {}", t.path, c.label, e.reason()));
    }
  }
  // A condition listed twice (or written two ways that are equal in SI, "5 %" and 0.05) would give the
  // table two independent noisy values of the same cell.
  if (const auto same = same_condition_in_si(conds))
    throw DiagnoseError(fmt::format("{}: the conditions {} and {} are the same condition: list each once",
                                    t.path, conds[same->first].label, conds[same->second].label));
  if (o.check)
    return {{"checked", true}, {"conditions", conds.size()}, {"runs", conds.size() * t.seeds.size()}};
  book.run();
  if (const std::string why = book.failure(conds, truth, t.seeds); !why.empty())
    throw std::runtime_error("a truth run failed: " + why);
  fs::create_directories(o.out);
  std::mt19937_64 rng(t.noise_seed);
  std::string csv;
  for (const auto& v : conds.front().values) csv += v.key + ",";
  csv += "observable,value,sigma,n,note\n";
  nlohmann::json truth_json;
  truth_json["name"] = t.name;
  truth_json["truth"] = t.truth;
  truth_json["seeds"] = t.seeds;
  truth_json["noise"] = t.noise;
  truth_json["noise_seed"] = t.noise_seed;
  truth_json["noise_rule"] =
      "Gaussian with the given sd; within 6 sd of a bound of the observable's possible range a gamma (one "
      "bound) or beta (two) with the same mean and sd, so the noise never leaves the range nor biases the "
      "mean";
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
      const double y = noisy_measurement(obs, p.mean, sd, rng);
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
