#pragma once
// Landlock (Linux 5.13 and later): a process, and all it starts, that may write only beneath
// chosen folders; reading stays free. The rules are made before the child starts (they
// allocate); the child applies them before it executes, with two system calls.
#include <filesystem>
#include <vector>

namespace granstack::os::detail {

// The Landlock rule set that allows writing (making, changing, removing files and folders)
// beneath `writable` alone, as a file descriptor; -1 where the kernel has no Landlock. A path
// that does not exist is left out.
int write_confinement(const std::vector<std::filesystem::path>& writable);

// In the child (async-signal-safe): no new privileges, then the rule set. False when refused.
bool apply_write_confinement(int ruleset);

}  // namespace granstack::os::detail
