// The code version written into outputs and run hashes: "<project version>+<git describe>". Defined in one
// source file (host/core/version.cpp) so that a new commit recompiles that file, not the whole tree.
#pragma once

#include <string>

namespace wetdem {

std::string code_version();  // e.g. "0.1.0+fd09d11-dirty"
const char* git_describe();  // e.g. "fd09d11-dirty"

}  // namespace wetdem
