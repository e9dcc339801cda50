#include "wetdem/version.h"

#include "wetdem_git.h"  // generated at every build: WETDEM_GIT "<git describe>", WETDEM_RUN_SOURCES "<hash>"

namespace wetdem {

const char* git_describe() {
  return WETDEM_GIT;
}

std::string code_version() {
  return std::string(WETDEM_VERSION) + "+" + WETDEM_GIT;
}

std::string run_version() {
  return std::string(WETDEM_VERSION) + "+run-" + WETDEM_RUN_SOURCES;
}

}  // namespace wetdem
