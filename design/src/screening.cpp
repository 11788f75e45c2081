#include "screening.hpp"

#include <granstack/design/convergence.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace granstack::design {

Screening::Screening(const Space& space) : space_(space), bounds_(space.bounds()) {}

void Screening::add(const std::vector<double>& genes, const std::vector<double>& point) {
  genes_.push_back(genes);
  std::vector<double> p(point.size());
  std::transform(point.begin(), point.end(), p.begin(), [](double v) { return std::min(v, kInfeasiblePoint); });
  points_.push_back(std::move(p));
}

double Screening::distance(const std::vector<double>& a, const std::vector<double>& b) const {
  double d = 0.0;
  for (std::size_t g = 0; g < a.size(); ++g) {
    if (space_.is_material_gene(g)) d += a[g] != b[g] ? 1.0 : 0.0;
    else d += std::abs(a[g] - b[g]) / (bounds_.second[g] - bounds_.first[g]);
  }
  return d;
}

std::vector<double> Screening::estimate(const std::vector<double>& genes) const {
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t i = 0; i < genes_.size(); ++i) near.emplace_back(distance(genes, genes_[i]), i);
  const std::size_t k = std::min(kScreeningNeighbours, near.size());
  std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(k), near.end());
  const std::size_t m = space_.objectives.size();
  std::vector<double> mean(m, 0.0), square(m, 0.0);
  double total = 0.0;
  for (std::size_t j = 0; j < k; ++j) {
    const double w = 1.0 / (near[j].first + 1e-3);  // a design one gene's step away weighs about as much as its neighbours
    for (std::size_t o = 0; o < m; ++o) {
      const double v = points_[near[j].second][o];
      mean[o] += w * v;
      square[o] += w * v * v;
    }
    total += w;
  }
  for (std::size_t o = 0; o < m && total > 0.0; ++o) {
    mean[o] /= total;
    const double spread = std::sqrt(std::max(square[o] / total - mean[o] * mean[o], 0.0));
    mean[o] = std::max(mean[o] - kScreeningOptimism * spread, 0.0);
  }
  return mean;
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

}  // namespace granstack::design
