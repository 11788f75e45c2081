#include <granstack/model/protection.hpp>

#include <algorithm>
#include <cmath>

namespace granstack::model {

namespace {
// The integral of F over [0, s] within the sample interval [a, b] of length h, F linear from fa to fb.
double partial(double fa, double fb, double h, double s) { return s * (fa + 0.5 * (fb - fa) * s / h); }
}  // namespace

double peak_window_impulse(const std::vector<double>& force, double interval, double window) {
  const std::size_t n = force.size();
  if (n < 2) return n == 1 ? force.front() * std::min(window, interval) : 0.0;
  // cumulative[k]: the trapezoid integral from sample 0 to sample k.
  std::vector<double> cumulative(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) cumulative[k] = cumulative[k - 1] + 0.5 * interval * (force[k - 1] + force[k]);
  const double span = interval * static_cast<double>(n - 1);
  const auto whole = static_cast<std::size_t>(std::floor(window / interval));
  if (window >= span || whole + 1 >= n) return cumulative.back();
  const double rest = window - interval * static_cast<double>(whole);
  double best = 0.0;
  for (std::size_t k = 0; k + whole < n; ++k) {
    const std::size_t end = k + whole;  // the window ends `rest` past sample `end`
    double impulse = cumulative[end] - cumulative[k];
    if (rest > 0.0) {
      if (end + 1 >= n) break;
      impulse += partial(force[end], force[end + 1], interval, rest);
    }
    best = std::max(best, impulse);
  }
  return best;
}

StrokeMeter::StrokeMeter(const Stack& stack) {
  start_z_ = stack.spheres().front().z;
  for (int id = 1; id <= stack.strikers(); ++id) start_z_ = std::min(start_z_, stack.spheres()[static_cast<std::size_t>(id - 1)].z);
}

void StrokeMeter::sample(double lowest_striker_z) { stroke_ = std::max(stroke_, start_z_ - lowest_striker_z); }

}  // namespace granstack::model
