#include "screening.hpp"

#include <granstack/design/convergence.hpp>
#include <granstack/design/objectives.hpp>
#include <granstack/design/store.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace granstack::design {

std::vector<std::optional<double>> known_axes(const Space& space, const Normalisation& n, const Geometry& g) {
  Evaluation e;
  e.spheres = g.spheres;
  e.areal_mass = g.areal_mass;
  e.height = g.height;
  std::vector<double> values;
  for (std::size_t k = 0; k < space.objectives.size(); ++k) {
    const auto o = space.objectives[k];
    values.push_back(o->geometric != nullptr ? o->geometric(e) : n.axes.at(k).ideal);
  }
  const auto p = n.point(values);
  std::vector<std::optional<double>> known;
  for (std::size_t k = 0; k < p.size(); ++k) {
    known.push_back(space.objectives[k]->geometric != nullptr ? std::optional<double>(p[k]) : std::nullopt);
  }
  return known;
}

EvidenceRegression::EvidenceRegression(std::size_t features)
    : gram_(Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(features), static_cast<Eigen::Index>(features))),
      moment_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(features))),
      sums_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(features))) {}

void EvidenceRegression::add(const Eigen::VectorXd& phi, double y) {
  gram_.selfadjointView<Eigen::Lower>().rankUpdate(phi);
  moment_ += y * phi;
  sums_ += phi;
  sum_y_ += y;
  sum_yy_ += y * y;
  ++n_;
  fitted_ = false;
}

// The evidence's fixed point (Bishop 2006, eqs. 3.87-3.95) in the Gram matrix's eigenbasis, on
// the targets less their mean: alpha = gamma / |m|^2, beta = (n - gamma) / E_D, with gamma the
// number of well-determined weights.
void EvidenceRegression::fit() {
  fitted_ = true;
  const auto p = gram_.rows();
  weights_ = Eigen::VectorXd::Zero(p);
  if (n_ == 0) return;
  const double n = static_cast<double>(n_);
  mean_y_ = sum_y_ / n;
  const Eigen::VectorXd b = moment_ - mean_y_ * sums_;
  const double yy = std::max(sum_yy_ - n * mean_y_ * mean_y_, 0.0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram_.selfadjointView<Eigen::Lower>());
  vectors_ = eigen.eigenvectors();
  const Eigen::VectorXd lambda = eigen.eigenvalues().cwiseMax(0.0);
  const Eigen::VectorXd projected = vectors_.transpose() * b;
  constexpr double kLeast = 1e-9, kMost = 1e12;
  alpha_ = 1.0;
  beta_ = std::clamp(n / std::max(yy, kLeast), kLeast, kMost);
  Eigen::VectorXd w(p), d(p);
  for (int iteration = 0; iteration < 200; ++iteration) {
    d = (alpha_ + beta_ * lambda.array()).matrix();
    w = (beta_ * projected.array() / d.array()).matrix();
    const double gamma = (beta_ * lambda.array() / d.array()).sum();
    const double misfit = std::max(yy - 2.0 * w.dot(projected) + (lambda.array() * w.array().square()).sum(), kLeast * yy + 1e-300);
    const double alpha = std::clamp(gamma / std::max(w.squaredNorm(), 1e-300), kLeast, kMost);
    const double beta = std::clamp(std::max(n - gamma, kLeast) / misfit, kLeast, kMost);
    const bool settled = std::abs(alpha - alpha_) <= 1e-6 * alpha_ && std::abs(beta - beta_) <= 1e-6 * beta_;
    alpha_ = alpha;
    beta_ = beta;
    if (settled) break;
  }
  d = (alpha_ + beta_ * lambda.array()).matrix();
  inverse_ = d.cwiseInverse();
  weights_ = vectors_ * (beta_ * projected.array() * inverse_.array()).matrix();
}

std::pair<double, double> EvidenceRegression::predict(const Eigen::VectorXd& phi) {
  if (!fitted_) fit();
  if (n_ == 0) return {0.0, 0.0};
  const Eigen::VectorXd v = vectors_.transpose() * phi;
  return {mean_y_ + weights_.dot(phi), std::sqrt((v.array().square() * inverse_.array()).sum())};
}

namespace {
std::size_t feature_count(const Space& s) {
  const auto blocks = static_cast<std::size_t>(s.max_blocks), materials = s.materials.size();
  return static_cast<std::size_t>(s.max_blocks - s.min_blocks + 1) + (blocks + 1) * materials +
         (blocks - 1) * s.radius_ratios.size() + blocks * static_cast<std::size_t>(s.max_rows - s.min_rows + 1);
}
}  // namespace

Screening::Screening(const Space& space)
    : space_(space), bounds_(space.bounds()), axes_(space.objectives.size(), EvidenceRegression(feature_count(space))) {}

Eigen::VectorXd Screening::features(const std::vector<double>& x) const {
  const auto& s = space_;
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(feature_count(s)));
  const auto gene = [&](std::size_t i, int lo, int hi) { return std::clamp(static_cast<int>(std::lround(x.at(i))), lo, hi); };
  const int nm = static_cast<int>(s.materials.size()), nr = static_cast<int>(s.radius_ratios.size()),
            rows = s.max_rows - s.min_rows + 1, blocks = gene(0, s.min_blocks, s.max_blocks);
  Eigen::Index at = 0;
  const auto one_hot = [&](int index, int width) {
    phi[at + index] = 1.0;
    at += width;
  };
  one_hot(blocks - s.min_blocks, s.max_blocks - s.min_blocks + 1);
  for (int k = 0; k < s.max_blocks; ++k) {
    if (k < blocks) one_hot(gene(static_cast<std::size_t>(1 + k), 0, nm - 1), nm);
    else at += nm;
  }
  one_hot(gene(static_cast<std::size_t>(blocks), 0, nm - 1), nm);  // the bottom block, on the wall or free
  for (int k = 0; k + 1 < s.max_blocks; ++k) {
    if (k + 1 < blocks) one_hot(gene(static_cast<std::size_t>(1 + s.max_blocks + k), 0, nr - 1), nr);
    else at += nr;
  }
  for (int k = 0; k < s.max_blocks; ++k) {
    if (k < blocks) one_hot(gene(static_cast<std::size_t>(2 * s.max_blocks + k), s.min_rows, s.max_rows) - s.min_rows, rows);
    else at += rows;
  }
  return phi;
}

void Screening::add(const std::vector<double>& genes, const std::vector<double>& point, bool feasible) {
  genes_.push_back(genes);
  feasible_.push_back(feasible);
  if (!feasible) return;
  const auto phi = features(genes);
  for (std::size_t o = 0; o < axes_.size(); ++o) axes_[o].add(phi, point.at(o));
}

double Screening::distance(const std::vector<double>& a, const std::vector<double>& b) const {
  double d = 0.0;
  for (std::size_t g = 0; g < a.size(); ++g) {
    if (space_.is_material_gene(g)) d += a[g] != b[g] ? 1.0 : 0.0;
    else d += std::abs(a[g] - b[g]) / (bounds_.second[g] - bounds_.first[g]);
  }
  return d;
}

bool Screening::likely_infeasible(const std::vector<double>& genes) const {
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t i = 0; i < genes_.size(); ++i) near.emplace_back(distance(genes, genes_[i]), i);
  const std::size_t k = std::min(kScreeningNeighbours, near.size());
  std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(k), near.end());
  double infeasible = 0.0, total = 0.0;
  for (std::size_t j = 0; j < k; ++j) {
    const double w = 1.0 / (near[j].first + 1e-3);  // a design one gene's step away weighs about as much as its neighbours
    total += w;
    if (!feasible_[near[j].second]) infeasible += w;
  }
  return infeasible > 0.5 * total;
}

std::vector<double> Screening::estimate(const std::vector<double>& genes, const std::vector<std::optional<double>>& known) {
  const std::size_t m = axes_.size();
  if (likely_infeasible(genes)) return std::vector<double>(m, kInfeasiblePoint);
  const auto phi = features(genes);
  std::vector<double> p(m);
  for (std::size_t o = 0; o < m; ++o) {
    if (o < known.size() && known[o]) {
      p[o] = *known[o];
      continue;
    }
    const auto [mean, sd] = axes_[o].predict(phi);
    p[o] = std::max(mean - kScreeningOptimism * sd, 0.0);
  }
  return p;
}

ScreeningGain::ScreeningGain(std::vector<std::vector<double>> front)
    : front_(std::move(front)), hypervolume_(box_hypervolume(front_)) {}

double ScreeningGain::operator()(const std::vector<double>& p) const {
  double nearest = std::numeric_limits<double>::infinity();
  bool dominated = false;
  for (const auto& q : front_) {
    double plus = 0.0;
    bool weakly = true;
    for (std::size_t o = 0; o < p.size(); ++o) {
      plus += std::pow(std::max(p[o] - q[o], 0.0), 2);
      weakly = weakly && q[o] <= p[o];
    }
    dominated = dominated || weakly;
    nearest = std::min(nearest, std::sqrt(plus));
  }
  if (dominated) return -nearest;
  auto with = front_;
  with.push_back(p);
  return box_hypervolume(with) - hypervolume_;
}

std::size_t screened_choice(const std::vector<double>& gains) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < gains.size(); ++i) {
    if (gains[i] > gains[best]) best = i;
  }
  return best;
}

}  // namespace granstack::design
