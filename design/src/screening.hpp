#pragma once
// The asynchronous search's screening ([search] screening): of several bred designs, the one to
// run is the one whose estimated point in the normalised box gains the front the most.
//
// The estimate of a design not yet run, per axis of the box:
// - an axis its geometry gives before the run (areal mass, height) is that value, exact;
// - a run measure is a Bayesian linear regression's (Bishop 2006, section 3.5: its prior's and
//   noise's precisions by the evidence) on features of the genes, fitted to the feasible designs
//   run: the number of blocks, each block's material, the bottom block's material, each
//   interface's ratio and each block's rows (one-hot each, a block past N_B none), less the
//   regression's own standard deviation there (optimistic where the designs run say little, so
//   that a region the search knows little of is not ruled out by a guess);
// - a design whose kScreeningNeighbours nearest designs run (in genes: a material differs by 1 or
//   0, another gene by its change over its range) are infeasible by the larger inverse-distance
//   weight is estimated infeasible (kInfeasiblePoint on every axis).
#include <granstack/design/space.hpp>

#include <Eigen/Dense>

#include <cstddef>
#include <optional>
#include <vector>

namespace granstack::design {

struct Normalisation;

inline constexpr std::size_t kScreeningNeighbours = 5;
inline constexpr double kScreeningOptimism = 1.0;  // the regression's standard deviations taken off its mean
inline constexpr double kInfeasiblePoint = 1.5;    // beyond the reference point 1.1

// The axes a design's geometry gives before it runs (the space's geometric objectives), as points
// in the box; nullopt on the run measures' axes.
std::vector<std::optional<double>> known_axes(const Space& space, const Normalisation& n, const Geometry& g);

// Bayesian linear regression of one target on features, kept as its sufficient statistics (the
// features' Gram matrix and moments), so that adding a design costs the features' count squared
// whatever the designs so far.
class EvidenceRegression {
 public:
  explicit EvidenceRegression(std::size_t features);
  void add(const Eigen::VectorXd& phi, double y);
  // The posterior mean and standard deviation (of the mean function, without the noise) at phi;
  // with no design added, {0, 0}.
  std::pair<double, double> predict(const Eigen::VectorXd& phi);
  double alpha() const { return alpha_; }  // the prior's precision (after predict)
  double beta() const { return beta_; }    // the noise's precision (after predict)

 private:
  void fit();
  Eigen::MatrixXd gram_;
  Eigen::VectorXd moment_, sums_;  // sum phi y, sum phi
  double sum_y_ = 0.0, sum_yy_ = 0.0;
  long n_ = 0;
  bool fitted_ = false;
  double alpha_ = 1.0, beta_ = 1.0, mean_y_ = 0.0;
  Eigen::MatrixXd vectors_;      // the Gram matrix's eigenvectors
  Eigen::VectorXd inverse_;      // 1 / (alpha + beta lambda_i): the posterior covariance in that basis
  Eigen::VectorXd weights_;      // the posterior mean of the weights
};

class Screening {
 public:
  explicit Screening(const Space& space);
  // A design run: its genes (Space::encode), its point in the box (fitness(), normalised) and
  // whether it met the constraints (an infeasible design's point is a penalty, not a measure).
  void add(const std::vector<double>& genes, const std::vector<double>& point, bool feasible);
  // The estimate for genes not yet run (above); `known`: known_axes() of the design, or empty.
  std::vector<double> estimate(const std::vector<double>& genes, const std::vector<std::optional<double>>& known = {});
  // The regression's features of a decision vector (one-hot blocks, materials, bottom material,
  // ratios and rows; a block past N_B has none).
  Eigen::VectorXd features(const std::vector<double>& genes) const;
  std::size_t size() const { return genes_.size(); }

 private:
  double distance(const std::vector<double>& a, const std::vector<double>& b) const;
  bool likely_infeasible(const std::vector<double>& genes) const;
  const Space& space_;
  std::pair<std::vector<double>, std::vector<double>> bounds_;
  std::vector<std::vector<double>> genes_;
  std::vector<bool> feasible_;
  std::vector<EvidenceRegression> axes_;  // one per objective
};

// What running a design of estimated point p would gain a front (points in the box): the
// hypervolume it adds against the reference point; when a point of the front weakly dominates p,
// minus p's IGD+ distance to the front (the least it must improve to stop being dominated). The
// front's own hypervolume is taken once, for every candidate of a draw.
class ScreeningGain {
 public:
  explicit ScreeningGain(std::vector<std::vector<double>> front);
  double operator()(const std::vector<double>& p) const;

 private:
  std::vector<std::vector<double>> front_;
  double hypervolume_;
};

// The candidate screening runs: the one whose estimate gains the front the most (ScreeningGain),
// the first drawn of equals.
std::size_t screened_choice(const std::vector<double>& gains);

}  // namespace granstack::design
