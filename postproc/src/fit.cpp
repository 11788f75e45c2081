#include <granstack/postproc/fit.hpp>

#include <granstack/postproc/least_squares.hpp>

#include <fmt/format.h>

#include <algorithm>

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
  // ln f = ln A - alpha N, with a free prefactor and through the origin (A = 1).
  Eigen::MatrixXd free(static_cast<Eigen::Index>(n), 2), origin(static_cast<Eigen::Index>(n), 1);
  Eigen::VectorXd ln(static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    free(i, 0) = 1.0;
    free(i, 1) = x[k];
    origin(i, 0) = x[k];
    ln(i) = y[k];
  }
  if (n < 2 || std::all_of(x.begin(), x.end(), [&](double v) { return v == x.front(); })) {
    throw std::invalid_argument("fit_decay: needs at least two different block counts");
  }
  const auto with_prefactor = least_squares(free, ln);
  const auto through_origin = least_squares(origin, ln);
  DecayFit f;
  f.points = static_cast<int>(n);
  f.alpha = -with_prefactor.coefficients(1);
  f.prefactor = std::exp(with_prefactor.coefficients(0));
  f.alpha_origin = -through_origin.coefficients(0);
  if (with_prefactor.covariance) {
    f.alpha_error = with_prefactor.error(1);
    f.prefactor_error = f.prefactor * with_prefactor.error(0);  // A = exp(ln A): dA = A d(ln A)
    f.covariance_ln_prefactor_alpha = -(*with_prefactor.covariance)(0, 1);
  }
  f.alpha_origin_error = through_origin.error(0);
  return f;
}

}  // namespace granstack::postproc
