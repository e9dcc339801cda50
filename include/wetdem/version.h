// The code version written into outputs ("<project version>+<git describe>"), and the run version that enters
// run hashes ("<project version>+run-<content hash of the run's sources>", cmake/git_describe.cmake). Defined
// in one source file (host/core/version.cpp) so that a new commit recompiles that file, not the whole tree.
#pragma once

#include <string>

namespace wetdem {

std::string code_version();  // e.g. "0.1.0+fd09d11-dirty"
const char* git_describe();  // e.g. "fd09d11-dirty"
// e.g. "0.1.0+run-3f2a9c0d1e4b": changes with any source that decides what a run computes (shaders, GPU
// system, core, run driver and observables, public headers), not with study, diagnosis or CLI code.
std::string run_version();

}  // namespace wetdem
