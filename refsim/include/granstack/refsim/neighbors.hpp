#pragma once
// The candidate pairs of a neighbour-list build: every pair of spheres whose centres are within
// (R_i + R_j) * contact_distance_factor + skin of each other, the criterion of LIGGGHTS's
// granular neighbour lists (neigh_gran), found through a grid in time linear in the spheres.
#include <granstack/os/for_shares.hpp>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace granstack::refsim {

// Sphere k has its centre at (x[k], y[k], z[k]) and radius radius[k].
struct SphereArrays {
  const double* x;
  const double* y;
  const double* z;
  const double* radius;
  std::size_t count = 0;
};

using os::ForShares;

// Pairs (i, j), i < j, in increasing (i, j) order, for which
//   rsq <= cut * cut,  rsq = dx*dx + dy*dy + dz*dz (d = x_i - x_j),  cut = (R_i + R_j) * factor + skin,
// evaluated in that order in double precision: the same pairs as testing every pair that way.
// The search runs in `for_shares`' shares (empty: in one); the result does not depend on them.
std::vector<std::pair<std::int32_t, std::int32_t>> candidate_pairs(const SphereArrays& spheres, double factor, double skin,
                                                                   const ForShares& for_shares = {});

}  // namespace granstack::refsim
