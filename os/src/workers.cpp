#include <granstack/os/workers.hpp>

#include <algorithm>

namespace granstack::os {

namespace {

// Waits until `ready()`: pause-spinning first (a refsim step's threads meet every few
// microseconds), then yielding (oversubscribed: let the other work run), then sleeping on `word`
// until it changes from `seen`.
template <class T, class Ready>
void wait_for(const std::atomic<T>& word, Ready ready) {
  for (long spins = 0; !ready(); ++spins) {
    if (spins < 2000) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    } else if (spins < 20000) {
      std::this_thread::yield();
    } else {
      const T seen = word.load(std::memory_order_acquire);
      if (!ready()) word.wait(seen, std::memory_order_acquire);
    }
  }
}

}  // namespace

Workers::Workers(int threads) : threads_(std::max(1, threads)), errors_(static_cast<std::size_t>(threads_)) {
  helpers_.reserve(static_cast<std::size_t>(threads_ - 1));
  for (int t = 1; t < threads_; ++t) helpers_.emplace_back([this, t] { helper(t); });
}

Workers::~Workers() {
  stop_ = true;
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (auto& h : helpers_) h.join();
}

void Workers::helper(int index) {
  long seen = 0;
  for (;;) {
    wait_for(generation_, [&] { return generation_.load(std::memory_order_acquire) != seen; });
    seen = generation_.load(std::memory_order_acquire);
    if (stop_) return;
    try {
      (*job_)(index);
    } catch (...) {
      errors_[static_cast<std::size_t>(index)] = std::current_exception();
    }
    finished_.fetch_add(1, std::memory_order_release);
    finished_.notify_one();
  }
}

void Workers::run(const std::function<void(int)>& job) {
  std::fill(errors_.begin(), errors_.end(), nullptr);
  if (threads_ > 1) {
    job_ = &job;
    finished_.store(0, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
  }
  try {
    job(0);
  } catch (...) {
    errors_[0] = std::current_exception();
  }
  if (threads_ > 1) wait_for(finished_, [&] { return finished_.load(std::memory_order_acquire) == threads_ - 1; });
  for (const auto& e : errors_) {
    if (e) std::rethrow_exception(e);
  }
}

std::pair<std::size_t, std::size_t> Workers::share(std::size_t count, int index, std::size_t align) const {
  const std::size_t t = static_cast<std::size_t>(threads_), k = static_cast<std::size_t>(index);
  const std::size_t units = (count + align - 1) / align;
  return {std::min(count, units * k / t * align), std::min(count, units * (k + 1) / t * align)};
}

void Workers::for_shares(std::size_t count, const std::function<void(std::size_t, std::size_t)>& job, std::size_t align) {
  if (threads_ <= 1) {
    job(0, count);
    return;
  }
  run([&](int t) {
    const auto [begin, end] = share(count, t, align);
    job(begin, end);
  });
}

void Workers::for_each(std::size_t count, const std::function<void(std::size_t)>& job) {
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(count);
  run([&](int) {
    for (std::size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < count;) {
      try {
        job(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  });
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

ForShares Workers::shares() {
  return [this](std::size_t count, const std::function<void(std::size_t, std::size_t)>& job) { for_shares(count, job); };
}

void for_shares(std::size_t count, int threads, const std::function<void(std::size_t, std::size_t)>& job) {
  if (count == 0) return;
  Workers(static_cast<int>(std::min<std::size_t>(count, static_cast<std::size_t>(std::max(1, threads))))).for_shares(count, job);
}

void for_each(std::size_t count, int threads, const std::function<void(std::size_t)>& job) {
  if (count == 0) return;
  Workers(static_cast<int>(std::min<std::size_t>(count, static_cast<std::size_t>(std::max(1, threads))))).for_each(count, job);
}

}  // namespace granstack::os
