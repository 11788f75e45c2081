#include <granstack/postproc/least_squares.hpp>

#include <stdexcept>

namespace granstack::postproc {

LinearFit least_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  const Eigen::Index n = x.rows(), p = x.cols();
  if (n < p || y.size() != n) throw std::invalid_argument("least squares: fewer points than parameters");
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  if (qr.rank() < p) throw std::invalid_argument("least squares: the parameters cannot be told apart (rank-deficient)");
  LinearFit f;
  f.coefficients = qr.solve(y);
  f.rss = (x * f.coefficients - y).squaredNorm();
  f.degrees_of_freedom = n - p;
  if (f.degrees_of_freedom > 0) {
    const double s2 = f.rss / static_cast<double>(f.degrees_of_freedom);
    // (X^T X)^-1 = P R^-1 R^-T P^T with X P = Q R.
    const Eigen::MatrixXd r = qr.matrixR().topLeftCorner(p, p).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd r_inverse = r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
    const Eigen::MatrixXd inner = r_inverse * r_inverse.transpose();
    f.covariance = s2 * (qr.colsPermutation() * inner * qr.colsPermutation().transpose());
  }
  return f;
}

}  // namespace granstack::postproc
