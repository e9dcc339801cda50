#include "wetdem/version.h"

#ifndef WETDEM_GIT
#define WETDEM_GIT "unknown"
#endif

namespace wetdem {

const char* git_describe() {
  return WETDEM_GIT;
}

std::string code_version() {
  return std::string(WETDEM_VERSION) + "+" + WETDEM_GIT;
}

}  // namespace wetdem
