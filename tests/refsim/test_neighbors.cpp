// The grid search for candidate pairs finds exactly the pairs that testing every pair finds,
// whatever the spheres' sizes and places: the neighbour list decides which histories survive,
// so one pair more or less would change a result.
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/refsim/neighbors.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using granstack::refsim::candidate_pairs;
using Pairs = std::vector<std::pair<std::int32_t, std::int32_t>>;

struct Spheres {
  std::vector<double> x, y, z, r;
  void add(double px, double py, double pz, double radius) {
    x.push_back(px);
    y.push_back(py);
    z.push_back(pz);
    r.push_back(radius);
  }
  granstack::refsim::SphereArrays arrays() const { return {x.data(), y.data(), z.data(), r.data(), x.size()}; }
};

// Written out independently of the library: every pair, the criterion as neigh_gran tests it.
Pairs every_pair(const Spheres& s, double factor, double skin) {
  Pairs found;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    for (std::size_t j = i + 1; j < s.x.size(); ++j) {
      const double dx = s.x[i] - s.x[j], dy = s.y[i] - s.y[j], dz = s.z[i] - s.z[j];
      const double rsq = dx * dx + dy * dy + dz * dz;
      const double cut = (s.r[i] + s.r[j]) * factor + skin;
      if (!(rsq > cut * cut)) found.emplace_back(static_cast<std::int32_t>(i), static_cast<std::int32_t>(j));
    }
  }
  return found;
}

void expect_same_pairs(const Spheres& s, double factor, double skin) {
  const Pairs expected = every_pair(s, factor, skin);
  EXPECT_EQ(candidate_pairs(s.arrays(), factor, skin), expected) << s.x.size() << " spheres, " << expected.size() << " pairs";
}

TEST(Neighbors, RandomSpheresOfMixedSizesInThreeAndTwoDimensions) {
  std::mt19937_64 rng(20261122);
  for (int trial = 0; trial < 40; ++trial) {
    const bool planar = trial % 2 == 1;  // a lattice's spheres share one y
    const double box = 0.004 * (1 + trial % 5);
    std::uniform_real_distribution<double> place(-box, box);
    std::uniform_int_distribution<int> size(0, 4);  // radius ratios up to 16
    Spheres s;
    for (int k = 0; k < 300; ++k) s.add(place(rng), planar ? 0.0 : place(rng), place(rng), 1e-3 / (1 << size(rng)));
    if (trial % 4 == 0) s.add(1e3, 0.0, -2e3, 1e-3);  // one sphere far away: wider cells
    if (trial % 8 == 3) s.add(s.x[7], s.y[7], s.z[7], s.r[7]);  // two at one place
    expect_same_pairs(s, 1.01, 2.5e-4);
    expect_same_pairs(s, 1.0, 0.0);
  }
}

// Spheres exactly at, and a few rounding steps either side of, the cut distance along each axis
// and diagonally, far from the origin too: the grid's cell bounds must not lose one.
TEST(Neighbors, PairsAtTheCutDistanceToTheLastBit) {
  const double factor = 1.01, skin = 2.5e-4;
  for (const double origin : {0.0, 0.37, -123.456, 4.0e6}) {
    Spheres s;
    for (const double radius : {1e-3, 0.5e-3, 0.125e-3}) {
      const double cut = (1e-3 + radius) * factor + skin;
      for (int axis = 0; axis < 4; ++axis) {
        for (int step = -3; step <= 3; ++step) {
          double d = cut;
          for (int k = 0; k < std::abs(step); ++k) d = std::nextafter(d, step > 0 ? 1.0 : 0.0);
          const double c = axis == 3 ? d / std::sqrt(3.0) : 0.0;
          s.add(origin, origin, origin, 1e-3);
          s.add(origin + (axis == 0 ? d : c), origin + (axis == 1 ? d : c), origin + (axis == 2 ? d : c), radius);
        }
      }
    }
    expect_same_pairs(s, factor, skin);
  }
}

TEST(Neighbors, AGeneratedStackAndItsLattice) {
  granstack::model::StackSpec spec;
  spec.blocks = 4;
  spec.top_columns = 8;
  const auto stack = granstack::model::Stack::build(spec);
  Spheres s;
  for (const auto& p : granstack::refsim::particles_from(granstack::generator::data_file(stack, "neighbors"))) {
    s.add(p.x[0], p.x[1], p.x[2], p.radius);
  }
  expect_same_pairs(s, 1.01, 2.5e-4);
  expect_same_pairs(s, 1.0, 0.0);  // touching spheres only, to the last bit
}

TEST(Neighbors, PositionsThatAreNotFiniteAreTestedLikeAnyOther) {
  Spheres s;
  for (int k = 0; k < 20; ++k) s.add(1e-3 * k, 0.0, 0.0, 0.6e-3);
  s.x[5] = std::numeric_limits<double>::quiet_NaN();
  s.z[9] = std::numeric_limits<double>::infinity();
  expect_same_pairs(s, 1.01, 2.5e-4);
  EXPECT_TRUE(candidate_pairs(Spheres{}.arrays(), 1.01, 2.5e-4).empty());
}

}  // namespace
