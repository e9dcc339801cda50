#include "study/calibrate.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

#include "app/output/summary.h"

namespace wetdem::study {

namespace fs = std::filesystem;

namespace {

bool same(double a, double b) {
  return std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b)) + 1e-15;
}

// A Gaussian process with a squared-exponential kernel and a constant mean (the data mean): it passes
// within the noise of every fitted value and relaxes to the mean away from them.
class Gp {
 public:
  Gp(const std::vector<std::vector<double>>& x, const std::vector<double>& y,
     const std::vector<double>& noise, double length)
      : x_(x), length_(length) {
    const size_t n = y.size();
    double m = 0;
    for (double v : y) m += v;
    mean_ = m / double(n);
    double var = 0;
    for (double v : y) var += (v - mean_) * (v - mean_);
    amp_ = n > 1 ? var / double(n - 1) : 1.0;
    if (!(amp_ > 0)) amp_ = 1.0;
    Eigen::MatrixXd k(n, n);
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j) k(Eigen::Index(i), Eigen::Index(j)) = kern(x[i], x[j]);
    for (size_t i = 0; i < n; ++i) k(Eigen::Index(i), Eigen::Index(i)) += noise[i] + 1e-8 * amp_;
    Eigen::VectorXd r(n);
    for (size_t i = 0; i < n; ++i) r(Eigen::Index(i)) = y[i] - mean_;
    alpha_ = k.ldlt().solve(r);
  }
  double operator()(const std::vector<double>& x) const {
    double s = mean_;
    for (size_t i = 0; i < x_.size(); ++i) s += kern(x, x_[i]) * alpha_(Eigen::Index(i));
    return s;
  }

 private:
  double kern(const std::vector<double>& a, const std::vector<double>& b) const {
    double d2 = 0;
    for (size_t k = 0; k < a.size(); ++k) d2 += (a[k] - b[k]) * (a[k] - b[k]);
    return amp_ * std::exp(-0.5 * d2 / (length_ * length_));
  }
  std::vector<std::vector<double>> x_;
  double length_, mean_ = 0, amp_ = 1;
  Eigen::VectorXd alpha_;
};

std::string toml_value(const std::string& written) {
  size_t used = 0;
  try {
    (void)std::stod(written, &used);
    if (used == written.size()) return written;
  } catch (const std::exception&) {
  }
  std::string q = "\"";
  for (char c : written) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return q + "\"";
}

}  // namespace

Calibration calibrate(const std::string& dir, const CalibrateOptions& opt) {
  const Collected col = gather(dir);
  const StudyIndex& ix = col.index;
  Calibration cal;
  const std::string obs_file = opt.observations.empty() ? ix.observations : opt.observations;
  if (obs_file.empty())
    throw StudyError(dir + ": the study has no [observations] table (or give --observations FILE)");
  cal.fit = opt.fit.empty() ? ix.fit : opt.fit;
  if (cal.fit.empty()) throw StudyError(dir + ": no fitted axes ([observations].fit or --fit)");
  for (const std::string& k : cal.fit)
    if (std::find(ix.axis_keys.begin(), ix.axis_keys.end(), k) == ix.axis_keys.end())
      throw StudyError(fmt::format("{}: fitted axis \"{}\" is not an axis of the study", dir, k));
  cal.obs = read_observations(obs_file);

  // Each point's resolved case (JSON), for the SI values of condition keys.
  std::vector<nlohmann::json> point_case(col.points.size());
  for (const IndexEntry& e : ix.runs)
    if (point_case[e.point].is_null())
      point_case[e.point] = app::case_to_json(app::parse_case_file((fs::path(dir) / e.case_file).string()));
  const std::string ref_case = (fs::path(dir) / ix.runs.at(0).case_file).string();

  for (Observation& o : cal.obs) {
    const auto bad = [&](const std::string& why) {
      return StudyError(fmt::format("{}: row at line {}: {}", obs_file, o.line, why));
    };
    if (std::find(col.numeric_keys.begin(), col.numeric_keys.end(), o.observable) == col.numeric_keys.end())
      throw bad(fmt::format("unknown observable \"{}\" (not a numeric key of the runs' summary.json{})",
                            o.observable, col.numeric_keys.empty() ? ": no run is complete yet" : ""));
    for (const auto& [k, w] : o.conditions) {
      if (std::find(cal.fit.begin(), cal.fit.end(), k) != cal.fit.end())
        throw bad("condition " + k + " is a fitted axis");
      double si = std::nan("");
      try {
        si = si_of_key(app::case_to_json(app::parse_case_file(ref_case, {k + "=" + toml_value(w)})), k);
      } catch (const app::CaseError& e) {
        throw bad(fmt::format("condition {} = {}: {}", k, w, e.what()));
      }
      if (!std::isfinite(si)) throw bad("condition " + k + " has no numeric value");
      o.conditions_si.push_back(si);
    }
    bool covered = false;
    for (size_t p = 0; p < col.points.size() && !covered; ++p) {
      bool ok = !point_case[p].is_null();
      for (size_t c = 0; ok && c < o.conditions.size(); ++c)
        ok = same(si_of_key(point_case[p], o.conditions[c].first), o.conditions_si[c]);
      covered = ok;
    }
    if (!covered) {
      std::string cs;
      for (const auto& [k, w] : o.conditions) cs += (cs.empty() ? "" : ", ") + k + " = " + w;
      throw bad("no run of the study has the conditions " + cs);
    }
  }

  // Fit points: the distinct values of the fitted axes.
  const size_t nd = cal.fit.size(), no = cal.obs.size();
  std::map<std::vector<double>, size_t> fp_of;
  std::vector<size_t> point_fp(col.points.size());
  for (const PointResult& p : col.points) {
    std::vector<double> x;
    std::vector<std::string> w;
    for (const std::string& k : cal.fit) {
      double v = std::nan("");
      std::string wr;
      for (const AxisValue& a : p.values)
        if (a.key == k) v = a.si, wr = a.written;
      if (!std::isfinite(v)) v = si_of_key(point_case[p.point], k), wr = fmt::format("{}", v);
      x.push_back(v), w.push_back(wr);
    }
    auto it = fp_of.find(x);
    if (it == fp_of.end()) {
      it = fp_of.emplace(x, cal.points.size()).first;
      FitPoint f;
      f.x_si = x, f.written = w;
      f.y.assign(no, std::nan("")), f.se.assign(no, std::nan(""));
      cal.points.push_back(f);
    }
    point_fp[p.point] = it->second;
  }
  for (const PointResult& p : col.points) {
    FitPoint& f = cal.points[point_fp[p.point]];
    for (size_t o = 0; o < no; ++o) {
      bool ok = true;
      for (size_t c = 0; ok && c < cal.obs[o].conditions.size(); ++c)
        ok =
            same(si_of_key(point_case[p.point], cal.obs[o].conditions[c].first), cal.obs[o].conditions_si[c]);
      if (!ok) continue;
      const auto st = p.stats.find(cal.obs[o].observable);
      if (st == p.stats.end() || st->second.n == 0) continue;
      f.y[o] = st->second.mean;
      f.se[o] = std::isfinite(st->second.se) ? st->second.se : 0.0;
    }
  }
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < cal.points.size(); ++i) {
    FitPoint& f = cal.points[i];
    f.complete = true;
    f.chi2 = 0;
    for (size_t o = 0; o < no; ++o) {
      if (!std::isfinite(f.y[o])) {
        f.complete = false;
        continue;
      }
      const double r = cal.obs[o].value - f.y[o];
      f.chi2 += r * r / (cal.obs[o].sigma * cal.obs[o].sigma + f.se[o] * f.se[o]);
    }
    if (f.complete && f.chi2 < best) best = f.chi2, cal.best = int(i);
  }
  if (cal.best < 0) throw StudyError(dir + ": no fit point has a complete run for every observation");

  // Emulator coordinates: log10 for positive axes, scaled to [0, 1] over the sampled range.
  cal.lo.assign(nd, 0), cal.hi.assign(nd, 0), cal.log_axis.assign(nd, true);
  for (size_t k = 0; k < nd; ++k) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const FitPoint& f : cal.points) {
      lo = std::min(lo, f.x_si[k]), hi = std::max(hi, f.x_si[k]);
      cal.log_axis[k] = cal.log_axis[k] && f.x_si[k] > 0;
    }
    cal.lo[k] = lo, cal.hi[k] = hi;
  }
  const auto to_u = [&](size_t k, double x) {
    const double a = cal.log_axis[k] ? std::log10(cal.lo[k]) : cal.lo[k];
    const double b = cal.log_axis[k] ? std::log10(cal.hi[k]) : cal.hi[k];
    const double v = cal.log_axis[k] ? std::log10(x) : x;
    return b > a ? (v - a) / (b - a) : 0.0;
  };
  const auto from_u = [&](size_t k, double u) {
    const double a = cal.log_axis[k] ? std::log10(cal.lo[k]) : cal.lo[k];
    const double b = cal.log_axis[k] ? std::log10(cal.hi[k]) : cal.hi[k];
    const double v = a + u * (b - a);
    return cal.log_axis[k] ? std::pow(10.0, v) : v;
  };
  // Length scale: 1.5 grid spacings of the axis with the most values (a smooth interpolant through them).
  size_t most = 2;
  for (size_t k = 0; k < nd; ++k) {
    std::vector<double> v;
    for (const FitPoint& f : cal.points) v.push_back(f.x_si[k]);
    std::sort(v.begin(), v.end());
    most = std::max<size_t>(most, size_t(std::unique(v.begin(), v.end()) - v.begin()));
  }
  const double length = 1.5 / double(most - 1);
  std::vector<Gp> gps;
  std::vector<double> se2_mean(no, 0);
  for (size_t o = 0; o < no; ++o) {
    std::vector<std::vector<double>> xs;
    std::vector<double> ys, ns;
    for (const FitPoint& f : cal.points)
      if (std::isfinite(f.y[o])) {
        std::vector<double> u;
        for (size_t k = 0; k < nd; ++k) u.push_back(to_u(k, f.x_si[k]));
        xs.push_back(u), ys.push_back(f.y[o]), ns.push_back(f.se[o] * f.se[o]);
        se2_mean[o] += f.se[o] * f.se[o];
      }
    se2_mean[o] /= double(std::max<size_t>(1, ys.size()));
    gps.emplace_back(xs, ys, ns, length);
  }
  const auto chi2_at = [&](const std::vector<double>& u) {
    double s = 0;
    for (size_t o = 0; o < no; ++o) {
      const double r = cal.obs[o].value - gps[o](u);
      s += r * r / (cal.obs[o].sigma * cal.obs[o].sigma + se2_mean[o]);
    }
    return s;
  };
  const size_t g = nd == 1 ? 2001 : nd == 2 ? 121 : 15;
  size_t total = 1;
  for (size_t k = 0; k < nd; ++k) total *= g;
  std::vector<std::vector<double>> us;
  std::vector<double> chis;
  size_t arg = 0;
  for (size_t i = 0; i < total; ++i) {
    std::vector<double> u(nd);
    size_t r = i;
    for (size_t k = 0; k < nd; ++k) u[k] = double(r % g) / double(g - 1), r /= g;
    chis.push_back(chi2_at(u));
    us.push_back(u);
    if (chis.back() < chis[arg]) arg = i;
  }
  cal.chi2_optimum = chis[arg];
  for (size_t k = 0; k < nd; ++k) cal.optimum.push_back(from_u(k, us[arg][k]));
  for (size_t o = 0; o < no; ++o) cal.y_optimum.push_back(gps[o](us[arg]));
  cal.interval_lo.assign(nd, 0), cal.interval_hi.assign(nd, 0);
  cal.interval_open_lo.assign(nd, false), cal.interval_open_hi.assign(nd, false);
  for (size_t k = 0; k < nd; ++k) {
    // Profile: the connected run of grid values around the optimum with min over the other axes <= min + 1.
    std::vector<double> prof(g, std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < total; ++i) {
      const size_t gi = size_t(std::lround(us[i][k] * double(g - 1)));
      prof[gi] = std::min(prof[gi], chis[i]);
    }
    const size_t a0 = size_t(std::lround(us[arg][k] * double(g - 1)));
    size_t a = a0, b = a0;
    while (a > 0 && prof[a - 1] <= cal.chi2_optimum + 1) --a;
    while (b + 1 < g && prof[b + 1] <= cal.chi2_optimum + 1) ++b;
    cal.interval_lo[k] = from_u(k, double(a) / double(g - 1));
    cal.interval_hi[k] = from_u(k, double(b) / double(g - 1));
    cal.interval_open_lo[k] = a == 0;
    cal.interval_open_hi[k] = b + 1 == g;
  }
  // The emulator for the figures: every grid point in 1-D, every 2nd in 2-D.
  const size_t stride = nd == 1 ? 4 : 1;
  for (size_t i = 0; i < total; i += stride) {
    std::vector<double> x;
    for (size_t k = 0; k < nd; ++k) x.push_back(from_u(k, us[i][k]));
    cal.grid_x.push_back(x);
    cal.grid_chi2.push_back(chis[i]);
  }
  // Proposals: the lowest emulated chi2 at least 0.05 (scaled units) away from every sampled value and from
  // each other: refinement where the emulator expects the optimum, not where the grid already is.
  if (opt.propose > 0) {
    std::vector<size_t> order(total);
    for (size_t i = 0; i < total; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return chis[a] < chis[b]; });
    std::vector<std::vector<double>> taken;
    for (const FitPoint& f : cal.points) {
      std::vector<double> u;
      for (size_t k = 0; k < nd; ++k) u.push_back(to_u(k, f.x_si[k]));
      taken.push_back(u);
    }
    for (size_t i : order) {
      if (cal.proposals.size() >= opt.propose) break;
      bool far = true;
      for (const auto& t : taken) {
        double d2 = 0;
        for (size_t k = 0; k < nd; ++k) d2 += (t[k] - us[i][k]) * (t[k] - us[i][k]);
        far = far && d2 > 0.05 * 0.05;
      }
      if (!far) continue;
      taken.push_back(us[i]);
      std::vector<double> x;
      for (size_t k = 0; k < nd; ++k) x.push_back(from_u(k, us[i][k]));
      cal.proposals.push_back(x);
    }
  }
  return cal;
}

std::string write_calibration(const std::string& dir, const Calibration& c) {
  const fs::path d = fs::path(dir) / "calibration";
  fs::create_directories(d);
  const size_t nd = c.fit.size(), no = c.obs.size();
  const auto cond = [&](const Observation& o) {
    std::string s;
    for (const auto& [k, w] : o.conditions) s += (s.empty() ? "" : ", ") + k + " = " + w;
    return s.empty() ? std::string("–") : s;
  };
  std::ostringstream md;
  md << "# Calibration\n\n";
  md << fmt::format(
      "Fitted: {}. {} observations. chi2 = sum (y_obs - y_sim)^2 / (sigma_obs^2 + SE_sim^2).\n\n",
      fmt::join(c.fit, ", "), no);
  const FitPoint& b = c.points[size_t(c.best)];
  md << "**Best grid point**: ";
  for (size_t k = 0; k < nd; ++k) md << (k ? ", " : "") << c.fit[k] << " = " << b.written[k];
  md << fmt::format(", chi2 = {:.3g} ({} observations).\n\n", b.chi2, no);
  md << "**Emulator optimum** (Gaussian process per observation over ";
  for (size_t k = 0; k < nd; ++k) md << (k ? ", " : "") << (c.log_axis[k] ? "log10 " : "") << c.fit[k];
  md << fmt::format("): chi2 = {:.3g} at\n\n", c.chi2_optimum);
  for (size_t k = 0; k < nd; ++k)
    md << fmt::format(
        "- {} = {:.4g} (SI), Delta chi2 = 1 interval [{:.4g}, {:.4g}]{}{}\n", c.fit[k], c.optimum[k],
        c.interval_lo[k], c.interval_hi[k],
        c.interval_open_lo[k] ? " (reaches the lowest sampled value: extend the axis down)" : "",
        c.interval_open_hi[k] ? " (reaches the highest sampled value: extend the axis up)" : "");
  md << "\n## Simulated vs measured (the paper's table form)\n\n| condition | observable | measured |";
  for (size_t i = 0; i < c.points.size(); ++i) {
    std::string h;
    for (size_t k = 0; k < nd; ++k) h += (k ? ", " : "") + c.points[i].written[k];
    md << ' ' << h << (int(i) == c.best ? " (best)" : "") << " |";
  }
  md << " emulator optimum |\n|---|---|---|";
  for (size_t i = 0; i <= c.points.size(); ++i) md << "---|";
  md << '\n';
  for (size_t o = 0; o < no; ++o) {
    md << "| " << cond(c.obs[o]) << " | " << c.obs[o].observable << " | "
       << fmt::format("{:.3g} ± {:.2g}", c.obs[o].value, c.obs[o].sigma) << " |";
    for (const FitPoint& f : c.points)
      md << ' '
         << (std::isfinite(f.y[o]) ? fmt::format("{:.3g} ± {:.2g}", f.y[o], f.se[o]) : std::string("–"))
         << " |";
    md << fmt::format(" {:.3g} |\n", c.y_optimum[o]);
  }
  md << "| | chi2 | |";
  for (const FitPoint& f : c.points)
    md << ' ' << (f.complete ? fmt::format("{:.3g}", f.chi2) : "incomplete") << " |";
  md << fmt::format(" {:.3g} |\n", c.chi2_optimum);
  if (!c.proposals.empty()) {
    md << "\n## Proposed refinement points (lowest emulated chi2 away from the sampled values)\n\n";
    for (const auto& p : c.proposals) {
      md << "-";
      for (size_t k = 0; k < nd; ++k) md << ' ' << c.fit[k] << " = " << fmt::format("{:.4g}", p[k]);
      md << '\n';
    }
  }
  app::write_file_atomic((d / "calibration.md").string(), md.str());

  std::ostringstream cc;
  for (const std::string& k : c.fit) cc << k << ',';
  cc << "chi2,complete\n";
  for (const FitPoint& f : c.points) {
    for (double x : f.x_si) cc << fmt::format("{:.9g},", x);
    cc << fmt::format("{:.9g},{}\n", f.chi2, f.complete ? 1 : 0);
  }
  app::write_file_atomic((d / "chi2.csv").string(), cc.str());
  std::ostringstream ec;
  for (const std::string& k : c.fit) ec << k << ',';
  ec << "chi2\n";
  for (size_t i = 0; i < c.grid_x.size(); ++i) {
    for (double x : c.grid_x[i]) ec << fmt::format("{:.9g},", x);
    ec << fmt::format("{:.9g}\n", c.grid_chi2[i]);
  }
  app::write_file_atomic((d / "emulator.csv").string(), ec.str());
  nlohmann::json j;
  j["fit"] = c.fit;
  j["log_axis"] = c.log_axis;
  j["best"] = {{"values", b.x_si}, {"written", b.written}, {"chi2", b.chi2}};
  j["optimum"] = c.optimum;
  j["chi2_optimum"] = c.chi2_optimum;
  j["interval_lo"] = c.interval_lo;
  j["interval_hi"] = c.interval_hi;
  j["interval_open_lo"] = c.interval_open_lo;
  j["interval_open_hi"] = c.interval_open_hi;
  j["observations"] = no;
  j["proposals"] = c.proposals;
  app::write_file_atomic((d / "calibration.json").string(), j.dump(1) + "\n");
  return md.str();
}

}  // namespace wetdem::study
