#include "write_behind.hpp"

#include <utility>

namespace granstack::refsim::detail {

WriteBehind::WriteBehind(bool threaded, std::size_t depth) : depth_(depth < 1 ? 1 : depth) {
  if (threaded) thread_ = std::thread([this] { loop(); });
}

WriteBehind::~WriteBehind() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(m_);
    stop_ = true;
  }
  work_.notify_one();
  thread_.join();
}

void WriteBehind::rethrow_error() {
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void WriteBehind::submit(std::function<void()> job) {
  if (!thread_.joinable()) {
    job();
    return;
  }
  std::unique_lock<std::mutex> lock(m_);
  room_.wait(lock, [&] { return jobs_.size() < depth_ || error_; });
  rethrow_error();
  jobs_.push_back(std::move(job));
  const bool idle = !running_job_ && jobs_.size() == 1;
  lock.unlock();
  // A wake-up costs a system call: only when the thread may be asleep with nothing to do.
  if (idle) work_.notify_one();
}

void WriteBehind::finish() {
  if (!thread_.joinable()) return;
  std::unique_lock<std::mutex> lock(m_);
  room_.wait(lock, [&] { return (jobs_.empty() && !running_job_) || error_; });
  rethrow_error();
}

void WriteBehind::loop() {
  std::unique_lock<std::mutex> lock(m_);
  for (;;) {
    work_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stopped, and every job given is done
    auto job = std::move(jobs_.front());
    jobs_.pop_front();
    running_job_ = true;
    lock.unlock();
    std::exception_ptr failed;
    try {
      job();
    } catch (...) {
      failed = std::current_exception();
    }
    lock.lock();
    running_job_ = false;
    if (failed) {
      error_ = failed;
      jobs_.clear();
    }
    room_.notify_one();
  }
}

}  // namespace granstack::refsim::detail
