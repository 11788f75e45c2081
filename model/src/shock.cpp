#include <granstack/model/shock.hpp>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace granstack::model {

namespace {
constexpr double kDesignFactor = 2.0775;  // SAE J211-1 appendix C: the two-pole design frequency over CFC

double design_frequency(int cfc) { return kDesignFactor * cfc; }

// One pass of the two-pole filter over y (in place), from rest.
void two_pole_pass(std::vector<double>& y, double a0, double b1, double b2) {
  double x1 = 0.0, x2 = 0.0, y1 = 0.0, y2 = 0.0;
  for (double& v : y) {
    const double x = v;
    v = a0 * (x + 2.0 * x1 + x2) + b1 * y1 + b2 * y2;
    x2 = x1;
    x1 = x;
    y2 = y1;
    y1 = v;
  }
}
}  // namespace

double channel_design_frequency(int cfc) { return design_frequency(cfc); }

double highest_resolved_frequency(double interval) { return interval > 0.0 ? 0.1 / interval : 0.0; }

std::string unresolved(const std::string& what, double frequency, double interval) {
  if (frequency <= highest_resolved_frequency(interval)) return "";
  return fmt::format("{} reads up to {:.4g} Hz, and the series samples every {:.3g} s, which resolves up to {:.4g} Hz (ten "
                     "samples a period)",
                     what, frequency, interval, highest_resolved_frequency(interval));
}

bool is_channel_class(int cfc) { return cfc == 60 || cfc == 180 || cfc == 600 || cfc == 1000; }
double channel_corner_frequency(int cfc) { return 5.0 / 3.0 * cfc; }

double channel_filter_gain(double f, double interval, int cfc) {
  const double ratio = std::tan(std::numbers::pi * f * interval) / std::tan(std::numbers::pi * design_frequency(cfc) * interval);
  return 1.0 / (1.0 + std::pow(ratio, 4));
}

Filtered channel_filter(const std::vector<double>& x, double interval, int cfc) {
  if (!is_channel_class(cfc)) throw std::invalid_argument(fmt::format("channel frequency class {}: 60, 180, 600 or 1000", cfc));
  const double fd = design_frequency(cfc);
  if (!(interval > 0.0) || !(fd * interval <= 0.1)) {
    throw std::invalid_argument(fmt::format("samples {:.3g} s apart are too sparse for CFC {} (at most {:.3g} s)", interval, cfc,
                                            0.1 / fd));
  }
  const double wa = std::tan(std::numbers::pi * fd * interval);  // sin(w_d T / 2) / cos(w_d T / 2), w_d = 2 pi f_d
  const double den = 1.0 + std::numbers::sqrt2 * wa + wa * wa;
  const double a0 = wa * wa / den;
  const double b1 = -2.0 * (wa * wa - 1.0) / den;
  const double b2 = (-1.0 + std::numbers::sqrt2 * wa - wa * wa) / den;
  // Zeros before and after, long enough for the filter's response to die away (8 periods of its
  // design frequency: its impulse response decays as exp(-2 pi f_d t / sqrt 2), to 1e-15 there).
  const auto pad = static_cast<std::size_t>(std::ceil(8.0 / (fd * interval)));
  std::vector<double> y(pad + 1, 0.0);  // one more: F = 0 at the start, the sample before the first
  y.insert(y.end(), x.begin(), x.end());
  y.resize(y.size() + pad, 0.0);
  two_pole_pass(y, a0, b1, b2);
  std::reverse(y.begin(), y.end());
  two_pole_pass(y, a0, b1, b2);
  std::reverse(y.begin(), y.end());
  // Where the signal is above 1e-12 of its largest value, on either side of the samples' span.
  double largest = 0.0;
  for (const double v : y) largest = std::max(largest, std::fabs(v));
  const auto negligible = [&](double v) { return std::fabs(v) <= 1e-12 * largest; };
  std::size_t begin = 0, end = y.size();
  while (begin < pad + 1 && negligible(y[begin])) ++begin;
  while (end > pad + 1 + x.size() && negligible(y[end - 1])) --end;
  Filtered f;
  f.first = pad + 1 - begin;
  f.values.assign(y.begin() + static_cast<std::ptrdiff_t>(begin), y.begin() + static_cast<std::ptrdiff_t>(end));
  return f;
}

double shock_response(const std::vector<double>& base, double interval, double f_n, double zeta) {
  // The relative displacement z of the mass: z'' + 2 zeta w z' + w^2 z = -a(t); its absolute
  // acceleration is -(2 zeta w z' + w^2 z). With the input's slope s as a state (a' = s, s' = 0),
  // exp of the augmented matrix over one interval gives the exact step for a linear input.
  const double w = 2.0 * std::numbers::pi * f_n;
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 1) = 1.0;
  m(1, 0) = -w * w;
  m(1, 1) = -2.0 * zeta * w;
  m(1, 2) = -1.0;  // the base acceleration a drives z''
  m(2, 3) = 1.0;   // a' = s
  const Eigen::Matrix4d step = (m * interval).exp();
  const Eigen::RowVector2d out(-w * w, -2.0 * zeta * w);
  double peak = 0.0;
  Eigen::Vector4d state = Eigen::Vector4d::Zero();  // z, z', a, s
  double previous = 0.0;                            // a = 0 at t = 0
  for (const double a : base) {
    state(2) = previous;
    state(3) = (a - previous) / interval;
    state = step * state;
    peak = std::max(peak, std::fabs(out * state.head<2>()));
    previous = a;
  }
  // Free vibration after the last sample, the base at rest (the input back to zero over one more
  // interval first, as the filter takes the signal).
  state(2) = previous;
  state(3) = -previous / interval;
  state = step * state;
  peak = std::max(peak, std::fabs(out * state.head<2>()));
  const double h = 1.0 / (256.0 * f_n);
  const Eigen::Matrix2d free = (m.topLeftCorner<2, 2>() * h).exp();
  Eigen::Vector2d z = state.head<2>();
  for (int k = 0; k < 384; ++k) {
    z = free * z;
    peak = std::max(peak, std::fabs(out * z));
  }
  return peak;
}

std::vector<double> shock_response_frequencies(double low, double high) {
  std::vector<double> f;
  const double step = std::pow(2.0, 1.0 / 12.0);
  for (double v = low; v < high * (1.0 - 1e-12); v *= step) f.push_back(v);
  f.push_back(high);
  return f;
}

ShockResponsePeak shock_response_peak(const std::vector<double>& base, double interval, double low, double high, double zeta) {
  ShockResponsePeak p;
  for (const double f : shock_response_frequencies(low, high)) {
    const double a = shock_response(base, interval, f, zeta);
    if (a > p.acceleration) p = {a, f};
  }
  return p;
}

}  // namespace granstack::model
