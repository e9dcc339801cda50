#include "diagnose/where.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

#include <unsupported/Eigen/SpecialFunctions>

namespace wetdem::diagnose {

std::vector<bool> benjamini_hochberg(const std::vector<double>& p, double q) {
  const size_t m = p.size();
  std::vector<size_t> order(m);
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return p[a] < p[b]; });
  size_t k_max = 0;  // number declared significant
  for (size_t k = 1; k <= m; ++k)
    if (p[order[k - 1]] <= double(k) * q / double(m)) k_max = k;
  std::vector<bool> sig(m, false);
  for (size_t k = 0; k < k_max; ++k) sig[order[k]] = true;
  return sig;
}

std::vector<CellGap> where(const std::vector<Cell>& cells, const std::vector<Prediction>& pred, double q) {
  if (pred.size() != cells.size()) throw std::invalid_argument("where: one prediction per cell");
  std::vector<CellGap> g(cells.size());
  std::vector<double> p(cells.size());
  for (size_t k = 0; k < cells.size(); ++k) {
    g[k].gap = cells[k].y - pred[k].mean;
    g[k].z = z_score(cells[k], pred[k]);
    // A prediction the runs could not make (NaN: the model does not report the observable there) is no
    // evidence of a gap.
    g[k].p = p[k] = std::isfinite(g[k].z) ? std::erfc(std::fabs(g[k].z) / std::sqrt(2.0)) : 1.0;
  }
  const std::vector<bool> sig = benjamini_hochberg(p, q);
  for (size_t k = 0; k < cells.size(); ++k) g[k].significant = sig[k];
  return g;
}

namespace {

// The one condition key along which the given cells vary, if exactly one does.
std::string varying_key(const std::vector<const Cell*>& cs) {
  std::set<std::string> keys;
  for (const Cell* c : cs)
    for (const auto& kv : c->condition) keys.insert(kv.first);
  std::string found;
  for (const std::string& k : keys) {
    std::set<double> values;
    for (const Cell* c : cs) {
      auto it = c->condition.find(k);
      values.insert(it == c->condition.end() ? std::nan("") : it->second);
    }
    if (values.size() > 1) {
      if (!found.empty()) return "";
      found = k;
    }
  }
  return found;
}

}  // namespace

std::vector<std::string> describe_where(const std::vector<Cell>& cells, const std::vector<CellGap>& gaps,
                                        bool gaps_only) {
  std::vector<std::string> out;
  std::map<std::string, std::vector<size_t>> by_obs;
  for (size_t k = 0; k < cells.size(); ++k) by_obs[cells[k].observable].push_back(k);
  for (const auto& [obs, idx] : by_obs) {
    std::vector<size_t> sig;
    for (size_t k : idx)
      if (gaps[k].significant) sig.push_back(k);
    if (sig.empty()) {
      if (!gaps_only)
        out.push_back(fmt::format("{}: no significant gap at {} condition(s)", obs, idx.size()));
      continue;
    }
    int above = 0;
    for (size_t k : sig) above += gaps[k].gap > 0;
    const int below = int(sig.size()) - above;
    std::string dir = above && below ? "observation on both sides of the model"
                      : above        ? "observation above the model"
                                     : "observation below the model";
    std::string line = fmt::format("{}: {} at {} of {} condition(s)", obs, dir, sig.size(), idx.size());
    std::vector<const Cell*> cs;
    for (size_t k : idx) cs.push_back(&cells[k]);
    const std::string key = varying_key(cs);
    if (!key.empty()) {
      double lo = 1e300, hi = -1e300;
      for (size_t k : sig) {
        const double v = cells[k].condition.at(key);
        lo = std::min(lo, v), hi = std::max(hi, v);
      }
      line += fmt::format(" ({} {:.4g}-{:.4g})", key, lo, hi);
      // Trend of the gap along the key: sign of the least-squares slope over all cells of this observable,
      // stated only when the correlation is strong (|r| >= 0.7) and there are 3 or more conditions.
      if (idx.size() >= 3) {
        double mx = 0, my = 0;
        for (size_t k : idx) mx += cells[k].condition.at(key), my += gaps[k].gap;
        mx /= double(idx.size()), my /= double(idx.size());
        double sxy = 0, sxx = 0, syy = 0;
        for (size_t k : idx) {
          const double dx = cells[k].condition.at(key) - mx, dy = gaps[k].gap - my;
          sxy += dx * dy, sxx += dx * dx, syy += dy * dy;
        }
        const double r = sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0.0;
        if (std::fabs(r) >= 0.7) line += fmt::format(", gap {} with {}", r > 0 ? "growing" : "falling", key);
      }
    }
    out.push_back(line);
  }
  return out;
}

double chi2_of(const std::vector<CellGap>& g) {
  double s = 0;
  for (const CellGap& x : g)
    if (std::isfinite(x.z)) s += x.z * x.z;
  return s;
}

size_t significant(const std::vector<CellGap>& g) {
  size_t n = 0;
  for (const CellGap& x : g) n += x.significant;
  return n;
}

namespace {
// P(χ²_n >= x) = Q(n/2, x/2) (Abramowitz & Stegun 26.4.19).
double chi2_upper(size_t n, double x) {
  return Eigen::numext::igammac(0.5 * double(n), 0.5 * std::max(0.0, x));
}
}  // namespace

double chi2_upper_point(size_t n, double level) {
  if (n == 0 || !(level > 0 && level < 1)) return std::numeric_limits<double>::infinity();
  // Bisection on the monotone upper tail, from 0 to a bound past the point.
  double lo = 0.0, hi = double(n) + 10.0 * std::sqrt(2.0 * double(n)) + 50.0;
  while (chi2_upper(n, hi) > level) hi *= 2.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_upper(n, mid) > level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TableFit table_fit(const std::vector<CellGap>& g, double level) {
  TableFit t;
  t.level = level > 0 && level < 1 ? level : 0.0;
  for (const CellGap& x : g)
    if (std::isfinite(x.z)) t.chi2 += x.z * x.z, ++t.n;
  t.critical = std::numeric_limits<double>::infinity();
  if (t.n == 0) return t;
  t.p = chi2_upper(t.n, t.chi2);
  if (t.level == 0.0) return t;
  t.beyond = t.p < level;
  t.critical = chi2_upper_point(t.n, level);
  return t;
}

std::string table_text(const TableFit& t) {
  if (t.level == 0.0 || t.n == 0)
    return fmt::format("χ² {:.1f} over {} cells (the table test is off)", t.chi2, t.n);
  return fmt::format("χ² {:.1f} over {} cells, {} χ²_{}'s {:.3g} % point {:.1f} (p = {:.2g})", t.chi2, t.n,
                     t.beyond ? "beyond" : "within", t.n, 100 * t.level, t.critical, t.p);
}

bool has_gap(const std::vector<CellGap>& g, double level) {
  return significant(g) > 0 || table_fit(g, level).beyond;
}

}  // namespace wetdem::diagnose
