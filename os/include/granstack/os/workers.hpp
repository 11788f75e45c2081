#pragma once
// granstack's one worker pool: threads started once that run a job together and return when all
// are done (fork-join). Every parallel loop of the program runs on it: refsim's steps, reduce's
// frames, a data file's pieces, the cases of `run`, a design search's designs, the folders of
// `status` and `submit`.
#include <granstack/os/for_shares.hpp>

#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <thread>
#include <utility>
#include <vector>

namespace granstack::os {

class Workers {
 public:
  // `threads` - 1 helper threads, started here; the caller is thread 0 of every run.
  explicit Workers(int threads);
  ~Workers();  // ends and joins the helpers
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  int size() const { return threads_; }
  // job(t) on every thread t of [0, size()), the caller's t = 0; returns when all have ended. The
  // first exception, by thread order, is rethrown after that. Waiting threads spin briefly (a
  // step of refsim lasts microseconds), then yield, then sleep until the next run.
  void run(const std::function<void(int)>& job);
  // Share `index` of [0, count) in size() contiguous shares, its bounds multiples of `align`
  // (but count itself).
  std::pair<std::size_t, std::size_t> share(std::size_t count, int index, std::size_t align = 1) const;
  // job(begin, end) on every thread's share; on the caller alone with one thread.
  void for_shares(std::size_t count, const std::function<void(std::size_t, std::size_t)>& job, std::size_t align = 1);
  // job(i) for every i of [0, count), each thread taking the next i as it becomes free (work of
  // uneven length: cases, designs). An exception stops no other i; the first, by i, is rethrown.
  void for_each(std::size_t count, const std::function<void(std::size_t)>& job);
  // This pool's for_shares, as a library's loop takes it.
  ForShares shares();

 private:
  void helper(int index);

  int threads_;
  std::vector<std::thread> helpers_;
  const std::function<void(int)>* job_ = nullptr;
  std::vector<std::exception_ptr> errors_;
  std::atomic<long> generation_{0};
  std::atomic<int> finished_{0};
  std::atomic<bool> stop_{false};
};

// A pool of `threads` for one call: job(begin, end) over contiguous shares of [0, count) (fewer
// threads when count is smaller).
void for_shares(std::size_t count, int threads, const std::function<void(std::size_t, std::size_t)>& job);
// A pool of `threads` for one call: job(i) for every i of [0, count), as Workers::for_each.
void for_each(std::size_t count, int threads, const std::function<void(std::size_t)>& job);

}  // namespace granstack::os
