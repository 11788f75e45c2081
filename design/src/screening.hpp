#pragma once
// The asynchronous search's screening ([search] screening): of several bred designs, the one to
// run is the one whose estimated point in the normalised box gains the front the most. The
// estimate is the designs run so far nearest in genes: their mean point, weighted by the inverse
// of the distance, less their spread (optimistic where the neighbours disagree, so that a region
// the search knows little of is not ruled out by a guess).
#include <granstack/design/space.hpp>

#include <cstddef>
#include <vector>

namespace granstack::design {

inline constexpr std::size_t kScreeningNeighbours = 5;
inline constexpr double kScreeningOptimism = 1.0;  // spreads taken off the mean

class Screening {
 public:
  explicit Screening(const Space& space);
  // A design run: its genes (Space::encode) and its point in the box (fitness(), normalised; an
  // infeasible design's penalty is held at kInfeasiblePoint on every axis).
  void add(const std::vector<double>& genes, const std::vector<double>& point);
  // The estimate for genes not yet run, from the kScreeningNeighbours nearest designs added
  // (a material gene differs by 1 or 0, another by its change over its range): per axis, the
  // weighted mean less kScreeningOptimism weighted standard deviations, at least 0.
  std::vector<double> estimate(const std::vector<double>& genes) const;
  std::size_t size() const { return genes_.size(); }

 private:
  double distance(const std::vector<double>& a, const std::vector<double>& b) const;
  const Space& space_;
  std::pair<std::vector<double>, std::vector<double>> bounds_;
  std::vector<std::vector<double>> genes_, points_;
};

inline constexpr double kInfeasiblePoint = 1.5;  // beyond the reference point 1.1

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

}  // namespace granstack::design
