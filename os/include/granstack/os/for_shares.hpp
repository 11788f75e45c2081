#pragma once
// What a library's parallel loop takes to stay free of who runs it (os::Workers::shares() gives
// one): a header of its own, so that a public header can name it without the pool.
#include <cstddef>
#include <functional>

namespace granstack::os {

// Runs job(begin, end) over shares of [0, count) that cover it, perhaps several at once (empty:
// one share, on the caller).
using ForShares = std::function<void(std::size_t count, const std::function<void(std::size_t, std::size_t)>& job)>;

}  // namespace granstack::os
