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
  // `done` of `total` items of `what`: on a terminal the status line with an ETA; elsewhere (a
  // log, a pipe) a line per tenth once the work has taken 2 s, so a short command stays silent.
  void count(const std::string& what, long done, long total);

 private:
  bool active_ = false;
  bool shown_ = false;
  std::chrono::steady_clock::time_point last_{};
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  long tenths_logged_ = 0;
};

// "12s", "3m05s", "1h02m"
std::string format_duration(double seconds);
// Remaining time from progress so far, or "?" before anything is known.
std::string eta(double elapsed, double fraction_done);

}  // namespace granstack::app
