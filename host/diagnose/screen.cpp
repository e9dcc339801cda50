#include "diagnose/screen.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "diagnose/procedure.h"

namespace wetdem::diagnose {

double screen_score(const std::vector<Cell>& cells, const std::vector<Prediction>& baseline,
                    const std::vector<Prediction>& probe) {
  if (baseline.size() != cells.size() || probe.size() != cells.size())
    throw std::invalid_argument("screen_score: one prediction per cell");
  double zr = 0, rr = 0;
  for (size_t k = 0; k < cells.size(); ++k) {
    const double s = std::sqrt(cells[k].sigma * cells[k].sigma + baseline[k].se * baseline[k].se);
    const double r = (probe[k].mean - baseline[k].mean) / s;
    zr += z_score(cells[k], baseline[k]) * r;
    rr += r * r;
  }
  return rr > 0 ? zr / std::sqrt(rr) : 0.0;
}

}  // namespace wetdem::diagnose

namespace wetdem::diagnose {

namespace {

// The probe index of e to screen with: from the middle downwards, the first that has not failed and may run.
// Returns -1 when none can; `ask`: whether that probe still needs its runs.
int screen_probe(Procedure& p, const std::string& e, bool want, bool* ask, std::vector<std::string>* notes) {
  const std::vector<double>& probes = p.d.probes.at(e);
  for (int i = int(probes.size() / 2); i >= 0; --i) {
    const Variant v = p.variant(e, probes[size_t(i)]);
    if (const std::string why = p.failure(v, p.probe_seeds); !why.empty()) {
      if (notes)
        notes->push_back(fmt::format("screen: {} failed ({}); a weaker probe is used", v.label(), why));
      continue;
    }
    if (want) {
      if (const std::string why = p.want(v, p.probe_seeds); !why.empty()) {
        if (notes) notes->push_back(fmt::format("screen: {} {}", v.label(), why));
        continue;
      }
    }
    *ask = true;
    return i;
  }
  return -1;
}

}  // namespace

void want_screen(Procedure& p) {
  for (const std::string& e : p.effects) {
    bool ask = false;
    screen_probe(p, e, true, &ask, nullptr);
  }
}

void run_screen(Procedure& p) {
  p.screened.clear();
  std::vector<std::string> pending = p.effects;
  for (int round = 0; !pending.empty() && round < 8; ++round) {
    std::vector<std::string> again;
    for (const std::string& e : pending) {
      bool ask = false;
      std::vector<std::string> notes;
      const int i = screen_probe(p, e, true, &ask, &notes);
      if (i < 0) {
        for (const std::string& n : notes) p.notes.push_back(n);
        p.notes.push_back(fmt::format("screen: no probe of {} could run; it scores 0", e));
        p.screened.push_back({0.0, e, 0.0});
        continue;
      }
      const double s = p.d.probes.at(e)[size_t(i)];
      const Variant v = p.variant(e, s);
      if (!p.book.has_summaries(p.tab.conditions, v, p.probe_seeds)) {
        again.push_back(e);  // wanted just now: run, then score
        continue;
      }
      for (const std::string& n : notes) p.notes.push_back(n);
      std::vector<Prediction> probe = p.predict(v, p.probe_seeds);
      for (size_t k = 0; k < probe.size(); ++k)
        probe[k].mean = p.baselines[0][k].mean + (probe[k].mean - p.seed1[0][k].mean);
      p.screened.push_back({screen_score(p.tab.cells, p.baselines[0], probe), e, s});
    }
    if (!again.empty()) p.run();
    pending = again;
  }
  std::stable_sort(p.screened.begin(), p.screened.end(),
                   [](const Screened& a, const Screened& b) { return a.score > b.score; });
}

}  // namespace wetdem::diagnose
