// Bitwise comparison of two downloaded states that names the first field where they differ: a bitwise test
// that fails on a device where it cannot be stepped through by hand (a lent GPU) says what diverged first.
#pragma once

#include <cstring>
#include <string>

#include "wetdem/state.h"

namespace wetdem::test {

// "" when a and b are bitwise equal (particle fields, pair records); else e.g. "v[17]" or "pair 3 (4,9)".
inline std::string first_difference(const SystemState& a, const SystemState& b) {
  auto diff = [](const char* name, const auto& x, const auto& y) -> std::string {
    if (x.size() != y.size()) return std::string(name) + " size";
    for (size_t k = 0; k < x.size(); ++k)
      if (std::memcmp(&x[k], &y[k], sizeof(x[k])) != 0)
        return std::string(name) + "[" + std::to_string(k) + "]";
    return "";
  };
  for (const std::string& d :
       {diff("x", a.p.x, b.p.x), diff("v", a.p.v, b.p.v), diff("w", a.p.w, b.p.w), diff("f", a.p.f, b.p.f),
        diff("t", a.p.t, b.p.t), diff("film", a.p.film, b.p.film)})
    if (!d.empty()) return d;
  if (a.pairs.size() != b.pairs.size()) return "pair count";
  for (size_t k = 0; k < a.pairs.size(); ++k) {
    const PairRecord &p = a.pairs[k], &q = b.pairs[k];
    if (p.id_i != q.id_i || p.id_j != q.id_j || p.bridge != q.bridge || p.flags != q.flags ||
        std::memcmp(&p.spring_t, &q.spring_t, sizeof(p.spring_t)) ||
        std::memcmp(&p.spring_r, &q.spring_r, sizeof(p.spring_r)))
      return "pair " + std::to_string(k) + " (" + std::to_string(p.id_i) + "," + std::to_string(p.id_j) + ")";
  }
  return "";
}

inline bool bitwise_equal(const SystemState& a, const SystemState& b) {
  return first_difference(a, b).empty();
}

}  // namespace wetdem::test
