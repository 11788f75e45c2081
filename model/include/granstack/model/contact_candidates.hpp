#pragma once
// Which spheres may touch at a frame: a cell search kept from frame to frame, shared by reduce
// (the elastic energy, the contact pressures) and refsim's in-situ run (the contact pressures),
// so both look at the same pairs.
#include <granstack/model/stack.hpp>

#include <cstddef>
#include <utility>
#include <vector>

namespace granstack::model {

// The pairs of spheres close enough to touch, kept from frame to frame: rebuilt (from a cell
// grid) only when some sphere has moved more than half the skin since the last build, as an
// MD neighbour list. Frames of one run barely move the spheres, so most frames reuse it.
class ContactCandidates {
 public:
  explicit ContactCandidates(const Stack& stack);
  // Pairs (i, j), i < j by index, that may overlap at positions x, y, z (and some farther
  // ones: the caller checks distances).
  const std::vector<std::pair<std::size_t, std::size_t>>& pairs(const std::vector<double>& x, const std::vector<double>& y,
                                                                const std::vector<double>& z);
  long builds() const { return builds_; }

 private:
  const Stack& stack_;
  double skin_;
  std::vector<std::pair<std::size_t, std::size_t>> pairs_;
  std::vector<double> x_at_build_, y_at_build_, z_at_build_;
  long builds_ = 0;
};

}  // namespace granstack::model
