#include "wetdem/version.h"

#include "wetdem_git.h"  // generated at every build: #define WETDEM_GIT "<git describe>"

namespace wetdem {

const char* git_describe() {
  return WETDEM_GIT;
}

std::string code_version() {
  return std::string(WETDEM_VERSION) + "+" + WETDEM_GIT;
}

}  // namespace wetdem
