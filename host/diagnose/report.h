// What a diagnosis writes: diagnosis.json (schema in docs/diagnosis.md), report.md with a plain-language
// verdict, tables and figures (scripts/plot_diagnosis.py, Debian's matplotlib).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "diagnose/candidates.h"
#include "diagnose/files.h"
#include "diagnose/where.h"

namespace wetdem::diagnose {

struct Report {
  const DiagnosisSpec* spec = nullptr;
  std::vector<Cell> cells;
  std::vector<std::string> cell_condition;  // label per cell
  std::vector<Prediction> baseline;
  std::vector<CellGap> gaps;
  std::vector<std::string> where;
  std::vector<std::pair<double, std::string>> screened;  // (score, effect), best first
  std::vector<Response> responses;                       // the fitted candidates (at their refit setting)
  std::vector<RefitSetting> settings;                    // refit settings (one, as calibrated, without refit)
  std::vector<Prediction> null_refit_pred;  // with refit: the model without effect at the null's setting
  std::vector<CellGap> null_refit_gaps;
  Verdict verdict;
  double chosen_strength = 0.0;
  std::vector<Prediction> after;  // the chosen effect, fresh seeds (empty unless verdict is "effect")
  std::vector<CellGap> gaps_after;
  size_t runs = 0, computed = 0;
  std::string device, store;
  double wall_s = 0.0;
};

// Writes DIR/diagnosis.json, DIR/report.md and (figures) DIR/figures/*.png; returns diagnosis.json.
nlohmann::json write_report(const std::string& dir, const Report& r, bool figures);

// The plain-language paragraph of report.md.
std::string verdict_paragraph(const Report& r);

// "liquid.v_max re-fitted to 0.5 %" ("liquid.v_max kept as calibrated") for refit setting j; "" without
// refit.
std::string refit_phrase(const Report& r, size_t j);

}  // namespace wetdem::diagnose
