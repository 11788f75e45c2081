#include <granstack/model/contact_candidates.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace granstack::model {

namespace {

// Calls fn(i, j), i < j, for every pair of spheres whose centres are closer than the sum of
// their radii plus `skin` (and some farther ones: the caller checks distances). One grid per
// sphere size, with cells of that size's diameter, so a large sphere looks through the few
// cells it covers of each finer grid instead of at every sphere. Cells span x, y and z (a
// strip's spheres all sit in one y cell).
template <typename Fn>
void for_each_close_pair(const Stack& stack, const std::array<const std::vector<double>*, 3>& position, double skin,
                         Fn&& fn) {
  const auto& spheres = stack.spheres();
  const std::size_t n = spheres.size();
  const auto at = [&](std::size_t d, std::size_t i) { return (*position[d])[i]; };
  const auto finite = [&](std::size_t i) { return std::isfinite(at(0, i)) && std::isfinite(at(1, i)) && std::isfinite(at(2, i)); };
  struct Grid {
    double radius = 0.0, cell = 0.0;
    std::array<std::int64_t, 3> lo{}, count{};      // dense cell range
    std::vector<std::size_t> start, members;        // counting-sorted cell lists
    std::vector<std::size_t> spheres;
  };
  std::vector<Grid> grids;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t g = 0;
    while (g < grids.size() && grids[g].radius != spheres[i].radius) ++g;
    if (g == grids.size()) grids.push_back({spheres[i].radius, 2.0 * spheres[i].radius, {}, {}, {}, {}, {}});
    if (finite(i)) grids[g].spheres.push_back(i);  // a blown-up sphere touches nothing
  }
  auto cell_of = [](double v, double cell) { return static_cast<std::int64_t>(std::floor(v / cell)); };
  auto flat = [](const Grid& g, const std::array<std::int64_t, 3>& c) {
    return static_cast<std::size_t>(((c[0] - g.lo[0]) * g.count[1] + (c[1] - g.lo[1])) * g.count[2] + (c[2] - g.lo[2]));
  };
  for (auto& g : grids) {
    if (g.spheres.empty()) continue;
    auto bound = [&] {
      for (std::size_t d = 0; d < 3; ++d) {
        std::int64_t lo = std::numeric_limits<std::int64_t>::max(), hi = std::numeric_limits<std::int64_t>::min();
        for (const auto i : g.spheres) {
          lo = std::min(lo, cell_of(at(d, i), g.cell));
          hi = std::max(hi, cell_of(at(d, i), g.cell));
        }
        g.lo[d] = lo;
        g.count[d] = hi - lo + 1;
      }
    };
    bound();
    // Spheres scattered far apart (long after the impact): coarsen the cells so the dense grid
    // stays about as large as the number of spheres; fewer cells only means more candidates.
    const auto cells = [&] {
      return static_cast<double>(g.count[0]) * static_cast<double>(g.count[1]) * static_cast<double>(g.count[2]);
    };
    while (cells() > 4.0 * static_cast<double>(g.spheres.size()) + 64.0) {
      g.cell *= 2.0;
      bound();
    }
    g.start.assign(static_cast<std::size_t>(cells()) + 1, 0);
    auto index = [&](std::size_t i) {
      return flat(g, {cell_of(at(0, i), g.cell), cell_of(at(1, i), g.cell), cell_of(at(2, i), g.cell)});
    };
    for (const auto i : g.spheres) ++g.start[index(i) + 1];
    for (std::size_t c = 0; c + 1 < g.start.size(); ++c) g.start[c + 1] += g.start[c];
    g.members.resize(g.spheres.size());
    std::vector<std::size_t> fill(g.start.begin(), g.start.end() - 1);
    for (const auto i : g.spheres) g.members[fill[index(i)]++] = i;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite(i)) continue;
    for (const auto& g : grids) {
      if (g.spheres.empty()) continue;
      const double reach = spheres[i].radius + g.radius + skin;
      std::array<std::int64_t, 3> c0{}, c1{};
      for (std::size_t d = 0; d < 3; ++d) {
        c0[d] = std::max(g.lo[d], cell_of(at(d, i) - reach, g.cell));
        c1[d] = std::min(g.lo[d] + g.count[d] - 1, cell_of(at(d, i) + reach, g.cell));
      }
      for (auto cx = c0[0]; cx <= c1[0]; ++cx) {
        for (auto cy = c0[1]; cy <= c1[1]; ++cy) {
          for (auto cz = c0[2]; cz <= c1[2]; ++cz) {
            const auto c = flat(g, {cx, cy, cz});
            for (std::size_t k = g.start[c]; k < g.start[c + 1]; ++k) {
              if (g.members[k] > i) fn(i, g.members[k]);
            }
          }
        }
      }
    }
  }
}

}  // namespace

ContactCandidates::ContactCandidates(const Stack& stack)
    : stack_(stack), skin_(0.5 * stack.blocks().back().radius) {}

const std::vector<std::pair<std::size_t, std::size_t>>& ContactCandidates::pairs(const std::vector<double>& x,
                                                                                 const std::vector<double>& y,
                                                                                 const std::vector<double>& z) {
  bool rebuild = x_at_build_.size() != x.size();
  const double limit = 0.25 * skin_ * skin_;  // moved more than half the skin
  for (std::size_t i = 0; !rebuild && i < x.size(); ++i) {
    const double dx = x[i] - x_at_build_[i], dy = y[i] - y_at_build_[i], dz = z[i] - z_at_build_[i];
    rebuild = !(dx * dx + dy * dy + dz * dz <= limit);  // also true for a non-finite position
  }
  if (rebuild) {
    pairs_.clear();
    const auto& spheres = stack_.spheres();
    for_each_close_pair(stack_, {&x, &y, &z}, skin_, [&](std::size_t i, std::size_t j) {
      const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
      const double reach = spheres[i].radius + spheres[j].radius + skin_;
      if (dx * dx + dy * dy + dz * dz < reach * reach) pairs_.emplace_back(i, j);
    });
    x_at_build_ = x;
    y_at_build_ = y;
    z_at_build_ = z;
    ++builds_;
  }
  return pairs_;
}

}  // namespace granstack::model
