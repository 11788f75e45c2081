#include <granstack/os/shares.hpp>

#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

namespace granstack::os {

void for_shares(std::size_t count, int threads, const std::function<void(std::size_t, std::size_t)>& job) {
  const std::size_t shares = std::min<std::size_t>(count, static_cast<std::size_t>(std::max(1, threads)));
  if (shares <= 1) {
    if (count > 0) job(0, count);
    return;
  }
  std::vector<std::exception_ptr> errors(shares);
  const auto run = [&](std::size_t s) {
    try {
      job(count * s / shares, count * (s + 1) / shares);
    } catch (...) {
      errors[s] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  workers.reserve(shares - 1);
  for (std::size_t s = 1; s < shares; ++s) workers.emplace_back(run, s);
  run(0);
  for (auto& w : workers) w.join();
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace granstack::os
