#include <granstack/postproc/fit.hpp>

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace granstack::postproc {

DecayFit fit_decay(const std::vector<int>& blocks, const std::vector<double>& fractions) {
  if (blocks.size() != fractions.size()) throw std::invalid_argument("fit_decay: as many fractions as block counts");
  const std::size_t n = blocks.size();
  std::vector<double> x(n), y(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (!(fractions[k] > 0.0) || !std::isfinite(fractions[k])) {
      throw std::invalid_argument(fmt::format("fit_decay: output fraction {} at N_B = {} is not > 0", fractions[k], blocks[k]));
    }
    x[k] = blocks[k];
    y[k] = std::log(fractions[k]);
  }
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < n; ++k) {
    mx += x[k];
    my += y[k];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0, sxy = 0, xx = 0, xy = 0;
  for (std::size_t k = 0; k < n; ++k) {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
    xx += x[k] * x[k];
    xy += x[k] * y[k];
  }
  if (n < 2 || sxx == 0.0) throw std::invalid_argument("fit_decay: needs at least two different block counts");
  DecayFit f;
  f.points = static_cast<int>(n);
  const double slope = sxy / sxx;
  const double intercept = my - slope * mx;
  f.alpha = -slope;
  f.prefactor = std::exp(intercept);
  f.alpha_origin = -xy / xx;
  if (n > 2) {
    double rss = 0;
    for (std::size_t k = 0; k < n; ++k) rss += std::pow(y[k] - (intercept + slope * x[k]), 2);
    const double s2 = rss / static_cast<double>(n - 2);
    f.alpha_error = std::sqrt(s2 / sxx);
    f.prefactor_error = f.prefactor * std::sqrt(s2 * (1.0 / static_cast<double>(n) + mx * mx / sxx));
  }
  double rss0 = 0;
  for (std::size_t k = 0; k < n; ++k) rss0 += std::pow(y[k] + f.alpha_origin * x[k], 2);
  f.alpha_origin_error = std::sqrt(rss0 / static_cast<double>(n - 1) / xx);
  return f;
}

}  // namespace granstack::postproc
