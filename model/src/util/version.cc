#include "hrpp/util/version.h"

#include "hrpp_git_commit.h"  // generated at build time (model/version.cmake)

namespace hrpp {

const char* project_version() { return HRPP_VERSION; }

const char* git_commit() { return HRPP_GIT_COMMIT; }

std::string version_line(const std::string& tool) {
  return tool + " " + project_version() + " (commit " + git_commit() + ")";
}

}  // namespace hrpp
