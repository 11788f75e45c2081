#pragma once
// Frames of a dump through a pool of threads, results back in frame order (reduce's engine).
#include <granstack/formats/batches.hpp>
#include <granstack/os/workers.hpp>

#include <condition_variable>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace granstack::postproc {

// Runs work(state, frame, result, last_of_batch) for every frame of `source` on `threads`
// threads (the caller's among them, each with its own state from make_state()), and
// deliver(result) for every frame in frame order, one at a time. At most 2 * threads batches are
// between being taken and being delivered, so memory does not grow with the number of frames.
// The error that ended the dump (or one thrown by work or deliver) is rethrown after every frame
// before it has been delivered.
template <typename Result, typename MakeState, typename Work, typename Deliver>
void for_each_frame_in_order(formats::FrameBatchSource& source, int threads, MakeState make_state, Work work,
                             Deliver deliver) {
  struct Slot {
    formats::FrameBatch batch;
    std::vector<Result> results;
  };
  const long window = 2L * std::max(threads, 1);
  std::mutex mutex;
  std::condition_variable changed;
  std::map<long, std::unique_ptr<Slot>> done;  // analysed, waiting for their turn
  std::vector<std::unique_ptr<Slot>> spare;
  long reserved = 0, delivered = 0;
  bool delivering = false, stop = false;
  std::exception_ptr failure;

  // Delivers every batch whose turn has come; one thread at a time.
  auto deliver_ready = [&](std::unique_lock<std::mutex>& lock) {
    if (delivering) return;
    delivering = true;
    while (!stop) {
      auto it = done.find(delivered);
      if (it == done.end()) break;
      auto slot = std::move(it->second);
      done.erase(it);
      lock.unlock();
      std::exception_ptr error;
      try {
        source.settle(slot->batch);
        for (std::size_t k = 0; k < slot->batch.frames.size(); ++k) deliver(slot->results[k]);
        error = slot->batch.error;
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      if (error) {
        failure = error;
        stop = true;
      }
      ++delivered;
      spare.push_back(std::move(slot));
      changed.notify_all();
    }
    delivering = false;
  };

  auto run = [&] {
    auto state = make_state();
    for (;;) {
      std::unique_ptr<Slot> slot;
      {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return stop || reserved - delivered < window; });
        if (stop) return;
        ++reserved;
        if (!spare.empty()) {
          slot = std::move(spare.back());
          spare.pop_back();
        } else {
          slot = std::make_unique<Slot>();
        }
      }
      bool taken = false;
      try {
        taken = source.take(slot->batch);
      } catch (...) {
        std::lock_guard lock(mutex);
        failure = std::current_exception();
        stop = true;
        changed.notify_all();
        return;
      }
      if (!taken) {
        std::lock_guard lock(mutex);
        --reserved;
        changed.notify_all();
        return;
      }
      // Each frame is worked on as soon as the next is parsed (whether it is the batch's last is
      // known then), while its values are still in the cache; the last once parsing ends.
      auto& batch = slot->batch;
      std::size_t worked = 0;
      std::exception_ptr work_error;  // comes before any parse error, which is later in the file
      auto work_on = [&](std::size_t k, bool last) {
        if (slot->results.size() <= k) slot->results.resize(k + 1);
        try {
          work(*state, batch.frames[k], slot->results[k], last);
          worked = k + 1;
        } catch (...) {
          work_error = std::current_exception();
        }
        return !work_error;
      };
      source.parse(batch, [&](std::size_t k) { return k == 0 || work_on(k - 1, false); });
      while (!work_error && worked < batch.frames.size()) work_on(worked, worked + 1 == batch.frames.size());
      if (work_error) {
        batch.error = work_error;
        batch.frames.resize(worked);
      }
      slot->results.resize(batch.frames.size());
      std::unique_lock lock(mutex);
      done[batch.index] = std::move(slot);
      deliver_ready(lock);
    }
  };

  auto guarded = [&] {
    try {
      run();
    } catch (...) {
      std::lock_guard lock(mutex);
      if (!failure) failure = std::current_exception();
      stop = true;
      changed.notify_all();
    }
  };
  os::Workers(threads).run([&](int) { guarded(); });
  if (failure) std::rethrow_exception(failure);
}

}  // namespace granstack::postproc
