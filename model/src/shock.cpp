#include <granstack/model/shock.hpp>

#include "shock_simd.hpp"

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

namespace {
// The oscillator of natural frequency f_n and damping ratio zeta, its relative displacement z:
// z'' + 2 zeta w z' + w^2 z = -a(t); its absolute acceleration is -(2 zeta w z' + w^2 z). With the
// input's slope s as a state (a' = s, s' = 0), exp of the augmented matrix over one interval h
// gives the exact step for a linear input: z' = P z + G a + H s, s = (a_after - a_before) / h.
struct Oscillator {
  Eigen::Matrix2d free;  // P: the state's own step
  Eigen::Vector2d before, after;  // G - H / h and H / h: what a_before and a_after add
  Eigen::RowVector2d out;
  Eigen::Matrix2d ring;  // the free vibration's step, 1 / (256 f_n)
};
Oscillator oscillator(double interval, double f_n, double zeta) {
  const double w = 2.0 * std::numbers::pi * f_n;
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 1) = 1.0;
  m(1, 0) = -w * w;
  m(1, 1) = -2.0 * zeta * w;
  m(1, 2) = -1.0;  // the base acceleration a drives z''
  m(2, 3) = 1.0;   // a' = s
  const Eigen::Matrix4d step = (m * interval).exp();
  Oscillator o;
  o.free = step.topLeftCorner<2, 2>();
  o.after = step.block<2, 1>(0, 3) / interval;
  o.before = step.block<2, 1>(0, 2) - o.after;
  o.out = Eigen::RowVector2d(-w * w, -2.0 * zeta * w);
  o.ring = (m.topLeftCorner<2, 2>() * (1.0 / (256.0 * f_n))).exp();
  return o;
}

// The largest absolute acceleration of each oscillator (natural frequencies `f`, Hz): over the
// samples, all frequencies in one pass (detail::run_oscillators), then over the input's return to
// zero in one more interval (as the filter takes the signal) and the free vibration after it (one
// and a half natural periods, 256 points a period).
std::vector<double> shock_responses(const std::vector<double>& base, double interval, const std::vector<double>& f, double zeta) {
  std::vector<Oscillator> each;
  for (const double f_n : f) each.push_back(oscillator(interval, f_n, zeta));
  detail::Oscillators all;
  const std::size_t lanes = detail::kOscillatorLanes;
  all.count = (each.size() + lanes - 1) / lanes * lanes;
  for (std::size_t k = 0; k < all.count; ++k) {
    const auto& o = each[std::min(k, each.size() - 1)];
    for (auto [to, v] : {std::pair{&all.p00, o.free(0, 0)}, {&all.p01, o.free(0, 1)}, {&all.p10, o.free(1, 0)},
                         {&all.p11, o.free(1, 1)}, {&all.c0, o.before(0)}, {&all.c1, o.before(1)}, {&all.d0, o.after(0)},
                         {&all.d1, o.after(1)}, {&all.o0, o.out(0)}, {&all.o1, o.out(1)}}) {
      to->push_back(v);
    }
  }
  std::vector<double> z0(all.count), z1(all.count), peak(all.count);
  detail::run_oscillators(all, base.data(), base.size(), z0.data(), z1.data(), peak.data());
  const double last = base.empty() ? 0.0 : base.back();
  peak.resize(f.size());
  for (std::size_t k = 0; k < f.size(); ++k) {
    const auto& o = each[k];
    Eigen::Vector2d z = o.free * Eigen::Vector2d(z0[k], z1[k]) + o.before * last;  // the base back to 0
    peak[k] = std::max(peak[k], std::fabs(o.out * z));
    for (int j = 0; j < 384; ++j) {
      z = o.ring * z;
      peak[k] = std::max(peak[k], std::fabs(o.out * z));
    }
  }
  return peak;
}
}  // namespace

double shock_response(const std::vector<double>& base, double interval, double f_n, double zeta) {
  return shock_responses(base, interval, {f_n}, zeta).front();
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
  const auto f = shock_response_frequencies(low, high);
  const auto a = shock_responses(base, interval, f, zeta);
  for (std::size_t k = 0; k < f.size(); ++k) {
    if (a[k] > p.acceleration) p = {a[k], f[k]};
  }
  return p;
}

}  // namespace granstack::model
