// π for the tests, once: test files are compiled in batches (unity build, CMakeLists.txt), where a constant
// defined in each file's anonymous namespace would be defined twice. The CPU reference (tests/reference/)
// keeps its own, since it is written independently of everything it checks.
#pragma once

namespace wetdem {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace wetdem
