#pragma once
// Ordinary least squares with Eigen: the decay fits and the wave-speed fit.
#include <Eigen/Dense>

#include <optional>

namespace granstack::postproc {

struct LinearFit {
  Eigen::VectorXd coefficients;           // b minimising |X b - y|
  std::optional<Eigen::MatrixXd> covariance;  // s^2 (X^T X)^-1, s^2 = rss / (n - p); none when n == p
  double rss = 0.0;                       // residual sum of squares
  long degrees_of_freedom = 0;            // n - p
  double error(Eigen::Index k) const { return std::sqrt((*covariance)(k, k)); }
};

// Fits y = X b by a column-pivoting Householder QR (no normal equations). Throws
// std::invalid_argument when X has fewer rows than columns or is rank-deficient.
LinearFit least_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y);

}  // namespace granstack::postproc
