#pragma once
// Jobs run one after another in the order given: on a thread of their own, so that a run's
// formatting and writing of its dumps and series overlap its steps on another core, or at once
// on the caller's thread. A job that throws ends the queue: the jobs after it are dropped and
// the caller gets its error at the next submit() or at finish().
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace granstack::refsim::detail {

class WriteBehind {
 public:
  // threaded: jobs run on a thread of this object's; at most `depth` wait at a time (submit
  // waits for room), so what they hold stays bounded however fast the steps come.
  explicit WriteBehind(bool threaded, std::size_t depth = 4);
  ~WriteBehind();  // waits for the jobs given (a run stopped by a signal keeps the frames it made)
  WriteBehind(const WriteBehind&) = delete;
  WriteBehind& operator=(const WriteBehind&) = delete;

  void submit(std::function<void()> job);  // rethrows an earlier job's error
  void finish();                           // waits for every job; rethrows a job's error

 private:
  void loop();
  void rethrow_error();  // with m_ held

  std::mutex m_;
  std::condition_variable work_, room_;
  std::deque<std::function<void()>> jobs_;
  std::exception_ptr error_;
  bool running_job_ = false, stop_ = false;
  std::size_t depth_;
  std::thread thread_;
};

}  // namespace granstack::refsim::detail
