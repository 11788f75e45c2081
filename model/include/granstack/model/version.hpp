#pragma once
#include <string_view>

namespace granstack {
// The granstack release ("0.1.0").
std::string_view version();
// The git commit the program was built from, with "-dirty" for uncommitted changes, or "unknown".
std::string_view git_commit();
}  // namespace granstack
