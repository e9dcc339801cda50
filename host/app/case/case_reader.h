// Reading one TOML table of a case file: typed getters that remember which keys were read, so that a key
// nobody asked for is reported as unknown, and that name the offending key in every error.
#pragma once

#include <toml++/toml.h>

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "app/case/case.h"
#include "app/case/units.h"

namespace wetdem::app {

// A quantity read from the file: SI value, the key it was found under, and the value as written.
struct Q {
  double v = 0;
  std::string key, raw;
};

[[noreturn]] void fail(const Q& q, const std::string& why);  // throws CaseError(q.key, why + ", got " + raw)
void require_positive(const Q& q);
void require_nonnegative(const Q& q);
void require_in(const Q& q, double lo, bool lo_open, double hi, bool hi_open, const std::string& interval);

class Section {
 public:
  // t == nullptr: the table is absent (every getter returns nullopt; required ones throw).
  Section(const toml::table* t, std::string path);

  bool present() const { return t_ != nullptr; }
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }

  // A quantity under `base` (a string with a unit; a plain number for Dimensionless/Fraction) or under
  // base_<unit> (a number in that unit, or a string with a unit). `aliases`: extra full key names with
  // their factors (e.g. "rpm"). Two spellings at once are an error.
  std::optional<Q> quantity(const std::string& base, Dim d, const std::vector<KeyUnit>& aliases = {});
  Q required(const std::string& base, Dim d, const std::vector<KeyUnit>& aliases = {});
  std::optional<bool> boolean(const std::string& k);
  std::optional<int64_t> integer(const std::string& k);
  std::optional<std::string> string(const std::string& k);
  std::optional<std::string> choice(const std::string& k, const std::vector<std::string>& allowed);
  std::optional<std::vector<std::string>> strings(const std::string& k);
  const toml::table* table(const std::string& k);      // nullptr when absent; error when not a table
  bool has(const std::string& k) const;                // any node under exactly this key (not marked as read)
  const toml::table* table_ptr() const { return t_; }  // the table itself (nullptr when absent)

  // Every key of the table must have been asked for: the first other one is reported as unknown.
  void finish() const;

 private:
  const toml::node* get(const std::string& k, bool hint = true);
  const toml::table* t_;
  std::string path_;
  std::set<std::string> asked_;
  std::vector<std::string> hint_;  // base names in the order asked, for the unknown-key message
};

std::string node_text(const toml::node& n);  // the value as written (strings quoted)
std::string type_text(const toml::node& n);  // "a string", "an integer", ...

}  // namespace wetdem::app
