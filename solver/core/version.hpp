// The build's identity: the git commit the sources were built from ("-dirty" when tracked
// files had uncommitted changes), generated at build time by cmake/git_version.cmake.
#pragma once

namespace efsi {
const char* build_commit();
}
