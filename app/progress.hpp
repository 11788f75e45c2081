#pragma once
// One status line on stderr, redrawn in place; silent when stderr is not a terminal.
#include <chrono>
#include <string>

namespace granstack::app {

class StatusLine {
 public:
  StatusLine();
  ~StatusLine();
  bool active() const { return active_; }
  void show(const std::string& text);  // at most every 100 ms unless `force`
  void clear();

 private:
  bool active_ = false;
  bool shown_ = false;
  std::chrono::steady_clock::time_point last_{};
};

// "12s", "3m05s", "1h02m"
std::string format_duration(double seconds);
// Remaining time from progress so far, or "?" before anything is known.
std::string eta(double elapsed, double fraction_done);

}  // namespace granstack::app
