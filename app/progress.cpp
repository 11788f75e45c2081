#include "progress.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace granstack::app {

StatusLine::StatusLine() : active_(::isatty(STDERR_FILENO) == 1) {}
StatusLine::~StatusLine() { clear(); }

void StatusLine::show(const std::string& text) {
  if (!active_) return;
  const auto now = std::chrono::steady_clock::now();
  if (shown_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  std::fprintf(stderr, "\r\033[K%s", text.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void StatusLine::clear() {
  if (active_ && shown_) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    shown_ = false;
  }
}

void StatusLine::count(const std::string& what, long done, long total) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  const double fraction = total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
  if (active_) {
    show(fmt::format("{}: {}/{} ETA {}", what, done, total, eta(elapsed, fraction)));
    return;
  }
  const long tenths = static_cast<long>(10.0 * fraction);
  if (elapsed < 2.0 || tenths <= tenths_logged_) return;
  tenths_logged_ = tenths;
  std::fprintf(stderr, "%s: %ld/%ld (%.0f %%, %s)\n", what.c_str(), done, total, 100.0 * fraction,
               format_duration(elapsed).c_str());
  std::fflush(stderr);
}

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  const long t = std::lround(s);
  if (t < 60) return fmt::format("{}s", t);
  if (t < 3600) return fmt::format("{}m{:02}s", t / 60, t % 60);
  return fmt::format("{}h{:02}m", t / 3600, (t % 3600) / 60);
}

std::string eta(double elapsed, double fraction) {
  if (fraction <= 0.0 || fraction > 1.0 || elapsed <= 0.0) return "?";
  return format_duration(elapsed * (1.0 - fraction) / fraction);
}

}  // namespace granstack::app
