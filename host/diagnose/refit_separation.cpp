#include "diagnose/refit_separation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "diagnose/fit.h"
#include "diagnose/verdict.h"

namespace wetdem::diagnose {

namespace {

// The rival's least χ² over the table with the extra measurements appended (its strength re-fitted to all).
double chi2_with(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
                 const Response& rival, const std::vector<ExtraMeasurement>& extra) {
  std::vector<Cell> all = cells;
  std::vector<Prediction> base = baseline;
  Response r = rival;
  for (const ExtraMeasurement& e : extra) {
    if (e.knots.size() != r.strengths.size())
      throw std::invalid_argument("refit_rise: an extra measurement's knots do not match the response's");
    all.push_back(e.cell);
    base.push_back(e.null);
    for (size_t k = 0; k < e.knots.size(); ++k) r.pred[k].push_back(e.knots[k]);
  }
  return fit_strength(all, Emulator(base, r)).chi2;
}

}  // namespace

double refit_rise(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
                  const Response& rival, const std::vector<ExtraMeasurement>& extra) {
  const double with = chi2_with(cells, baseline, rival, extra);
  return std::max(0.0, with - fit_strength(cells, Emulator(baseline, rival)).chi2);
}

double needed_separation(double chi2_a, size_t n, const VerdictRule& rule, double luck) {
  return std::sqrt(fresh_tie_margin(chi2_a, n, rule, luck));
}

double refit_rise(const std::vector<Cell>& cells, const std::vector<RivalMember>& family) {
  double table = std::numeric_limits<double>::infinity(), with = table;
  for (const RivalMember& m : family) {
    const double t = fit_strength(cells, Emulator(*m.baseline, *m.response)).chi2;
    table = std::min(table, t);
    if (m.known) with = std::min(with, chi2_with(cells, *m.baseline, *m.response, m.extra));
  }
  return std::isfinite(with) ? std::max(0.0, with - table) : std::nan("");
}

bool pair_beats_single(const ProposalPair& pair, const Proposal& single) {
  const double s = judged_separation(single.refit_separation, single.separation);
  return pair.refit_separation >= kDecisive && pair.refit_separation > std::sqrt(2.0) * s;
}

}  // namespace wetdem::diagnose
