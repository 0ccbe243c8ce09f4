// The project's version and the git commit the binaries were built from (model/version.cmake).
#pragma once

#include <string>

namespace hrpp {

/// The project version (CMakeLists.txt, project(... VERSION)), e.g. "0.1.0".
const char* project_version();

/// `git describe --always --dirty` of the checkout at build time, e.g. "e2614ff-dirty", or
/// "unknown" when the sources were not a git checkout.
const char* git_commit();

/// One line for --version: "TOOL VERSION (commit COMMIT)".
std::string version_line(const std::string& tool);

}  // namespace hrpp
