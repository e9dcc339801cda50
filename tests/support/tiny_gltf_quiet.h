// tinygltf for the tests that read glTF back, with the warnings its header raises under the project's flags
// (-Wshadow, -Wunused-parameter, -Wpedantic) silenced for that header only. The implementation comes from
// Debian's libtinygltf (host/CMakeLists.txt).
#pragma once

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop
