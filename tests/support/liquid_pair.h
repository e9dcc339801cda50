// The spheres of the pair-level liquid tests (test_liquid_*.cpp, test_wet_hold.cpp): 1 mm radius, 2,500
// kg/m³, V_max = 1e-12 m³ in liquid units of 1e-21 m³. One definition, since the test files are compiled in
// batches (unity build, CMakeLists.txt).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

namespace wetdem::test {

inline constexpr double kR = 1e-3, kRho = 2500.0;
inline constexpr int64_t kVmax = 1'000'000'000;  // 1e-12 m^3 in units of 1e-21 m^3

// Position of a sphere whose surface gap to the sphere at `from` (same radius kR) is `gap`, along `dir`.
inline glm::dvec3 beside(const glm::dvec3& from, const glm::dvec3& dir, double gap) {
  return from + (2.0 * kR + gap) * glm::normalize(dir);
}

}  // namespace wetdem::test
