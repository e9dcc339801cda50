#include "app/case/case_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace wetdem::app {

std::string node_text(const toml::node& n) {
  std::ostringstream os;
  if (const auto* s = n.as_string()) {
    os << '"' << s->get() << '"';
  } else if (const auto* f = n.as_floating_point()) {
    os << fmt::format("{}", f->get());
  } else {
    n.visit([&](const auto& v) { os << v; });
  }
  return os.str();
}

std::string type_text(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    default:
      return "a date/time";
  }
}

void fail(const Q& q, const std::string& why) {
  throw CaseError(q.key, why + ", got " + q.raw);
}

void require_positive(const Q& q) {
  if (!(q.v > 0)) fail(q, "must be > 0");
}

void require_nonnegative(const Q& q) {
  if (!(q.v >= 0)) fail(q, "must be >= 0");
}

void require_in(const Q& q, double lo, bool lo_open, double hi, bool hi_open, const std::string& interval) {
  const bool ok_lo = lo_open ? q.v > lo : q.v >= lo;
  const bool ok_hi = hi_open ? q.v < hi : q.v <= hi;
  if (!(ok_lo && ok_hi)) fail(q, "must be in " + interval);
}

Section::Section(const toml::table* t, std::string path) : t_(t), path_(std::move(path)) {}

const toml::node* Section::get(const std::string& k, bool hint) {
  asked_.insert(k);
  if (hint && std::find(hint_.begin(), hint_.end(), k) == hint_.end()) hint_.push_back(k);
  return t_ ? t_->get(k) : nullptr;
}

bool Section::has(const std::string& k) const {
  return t_ && t_->get(k) != nullptr;
}

std::optional<Q> Section::quantity(const std::string& base, Dim d, const std::vector<KeyUnit>& aliases) {
  // Candidate spellings with the factor a plain number under them carries (0: no plain number allowed).
  struct Cand {
    std::string name;
    double factor;
  };
  std::vector<Cand> cands;
  const bool plain_ok = d == Dim::Dimensionless || d == Dim::Fraction;
  cands.push_back({base, plain_ok ? 1.0 : 0.0});
  if (d != Dim::Dimensionless)
    for (const KeyUnit& u : key_units(d)) cands.push_back({base + "_" + u.suffix, u.factor});
  for (const KeyUnit& a : aliases) cands.push_back({a.suffix, a.factor});

  const toml::node* found = nullptr;
  Cand which{};
  for (const Cand& c : cands) {
    const toml::node* n = get(c.name, c.name == base);
    if (!n) continue;
    if (found)
      throw CaseError(key(c.name), "given twice (also as " + key(which.name) + "); keep one spelling");
    found = n;
    which = c;
  }
  if (!found) return std::nullopt;

  Q q;
  q.key = key(which.name);
  q.raw = node_text(*found);
  if (found->is_integer() || found->is_floating_point()) {
    const double x =
        found->is_integer() ? double(found->as_integer()->get()) : found->as_floating_point()->get();
    // Zero is zero in every unit: `snapshot_interval = 0` needs none.
    if (which.factor == 0.0 && x != 0.0)
      throw CaseError(q.key,
                      std::string("a plain number has no unit; write it with one (e.g. \"140 mm\") or use ") +
                          key(base + "_" + si_unit(d)) + ", got " + q.raw);
    q.v = which.factor == 0.0 ? 0.0 : apply_factor(x, which.factor);
  } else if (const auto* s = found->as_string()) {
    try {
      q.v = parse_quantity(s->get(), d);
    } catch (const std::invalid_argument& e) {
      throw CaseError(q.key, e.what());
    }
  } else {
    throw CaseError(q.key, std::string("must be ") + dim_name(d) + ", got " + type_text(*found));
  }
  if (!std::isfinite(q.v)) fail(q, "must be finite");
  return q;
}

Q Section::required(const std::string& base, Dim d, const std::vector<KeyUnit>& aliases) {
  std::optional<Q> q = quantity(base, d, aliases);
  if (!q) {
    std::string spell = key(base);
    if (d != Dim::Dimensionless && d != Dim::Fraction) spell += " (or " + key(base + "_" + si_unit(d)) + ")";
    throw CaseError(key(base), std::string("required: ") + dim_name(d) + " under " + spell);
  }
  return *q;
}

std::optional<bool> Section::boolean(const std::string& k) {
  const toml::node* n = get(k);
  if (!n) return std::nullopt;
  if (const auto* b = n->as_boolean()) return b->get();
  throw CaseError(key(k), "must be true or false, got " + type_text(*n));
}

std::optional<int64_t> Section::integer(const std::string& k) {
  const toml::node* n = get(k);
  if (!n) return std::nullopt;
  if (const auto* i = n->as_integer()) return i->get();
  throw CaseError(key(k), "must be an integer, got " + type_text(*n) + " " + node_text(*n));
}

std::optional<std::string> Section::string(const std::string& k) {
  const toml::node* n = get(k);
  if (!n) return std::nullopt;
  if (const auto* s = n->as_string()) return s->get();
  throw CaseError(key(k), "must be a string, got " + type_text(*n));
}

std::optional<std::string> Section::choice(const std::string& k, const std::vector<std::string>& allowed) {
  std::optional<std::string> s = string(k);
  if (!s) return s;
  std::string list;
  for (const std::string& a : allowed) {
    if (a == *s) return s;
    list += (list.empty() ? "\"" : ", \"") + a + "\"";
  }
  throw CaseError(key(k), "must be one of " + list + ", got \"" + *s + "\"");
}

std::optional<std::vector<std::string>> Section::strings(const std::string& k) {
  const toml::node* n = get(k);
  if (!n) return std::nullopt;
  const auto* a = n->as_array();
  if (!a) throw CaseError(key(k), "must be an array of strings, got " + type_text(*n));
  std::vector<std::string> out;
  for (const toml::node& e : *a) {
    if (!e.is_string()) throw CaseError(key(k), "must be an array of strings, has " + type_text(e));
    out.push_back(e.as_string()->get());
  }
  return out;
}

const toml::table* Section::table(const std::string& k) {
  const toml::node* n = get(k);
  if (!n) return nullptr;
  if (const auto* t = n->as_table()) return t;
  throw CaseError(key(k), "must be a table, got " + type_text(*n));
}

void Section::finish() const {
  if (!t_) return;
  for (auto&& [k, v] : *t_) {
    const std::string name(k.str());
    if (asked_.count(name)) continue;
    std::string known;
    for (const std::string& a : hint_) known += (known.empty() ? "" : ", ") + a;
    throw CaseError(key(name), "unknown key (known here: " + known + ")");
  }
}

}  // namespace wetdem::app
