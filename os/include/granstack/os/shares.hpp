#pragma once
// Work over [0, count) split into contiguous shares, one per thread: the loops over many
// independent items (cases, files) that the commands run on every core they may use.
#include <cstddef>
#include <functional>

namespace granstack::os {

// Runs job(begin, end) on `threads` contiguous shares of [0, count) (fewer when count is smaller;
// the calling thread takes the first) and returns when every share is done. The first exception a
// share throws, by share order, is rethrown after all have ended.
void for_shares(std::size_t count, int threads, const std::function<void(std::size_t, std::size_t)>& job);

}  // namespace granstack::os
