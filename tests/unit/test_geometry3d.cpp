// The nested 3D geometry (geometry = nested3d): every designed contact exact, nothing else
// touching or overlapping, counts and ids as documented, mirror symmetry in x and y, the
// four-sphere seats (sqrt(2) R_1 for the striker, sqrt(7) R_{k+1} at a ratio-2 interface), the
// impact path a chain of contacts, the walls.
#include <granstack/formats/dump.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/energy.hpp>

#include "touching.hpp"

#include <gtest/gtest.h>

#include <cmath>

using granstack::model::Geometry;
using granstack::model::Sphere;
using granstack::model::Stack;
using granstack::model::StackSpec;

namespace {


struct Nest {
  int blocks, top_columns, rows, ratio;
};

Stack build(const Nest& p, bool walls = false) {
  StackSpec s;
  s.geometry = Geometry::nested3d;
  s.blocks = p.blocks;
  s.top_columns = p.top_columns;
  s.rows = p.rows;
  s.radius_ratio = p.ratio;
  if (walls) s.bottom = s.sides = granstack::model::Boundary::wall;
  return Stack::build(s);
}

using granstack::test::gap;
using granstack::test::touching;
using granstack::test::touching_pairs;

class Geometry3dTest : public ::testing::TestWithParam<Nest> {};

TEST_P(Geometry3dTest, EveryDesignedContactTouchesExactlyAndNothingElseTouchesOrOverlaps) {
  const auto& p = GetParam();
  const auto stack = build(p);
  granstack::test::DesignedContacts designed(stack);
  const auto expect_touch = [&](int a, int b) { designed.expect(a, b); };
  for (const auto& b : stack.blocks()) {
    ASSERT_EQ(b.depth, b.columns);
    for (int i = 1; i <= b.rows; ++i) {
      for (int l = 1; l <= b.depth; ++l) {
        for (int j = 1; j <= b.columns; ++j) {
          const int id = stack.id_of(b.index, i, j, l);
          if (j < b.columns) expect_touch(id, stack.id_of(b.index, i, j + 1, l));  // along x
          if (l < b.depth) expect_touch(id, stack.id_of(b.index, i, j, l + 1));    // along y
          if (i < b.rows) expect_touch(id, stack.id_of(b.index, i + 1, j, l));     // vertical
        }
      }
    }
    if (b.index == p.blocks) continue;
    // The interface: each bottom sphere on the four (even ratio) or the one (odd) below its centre.
    for (int l = 1; l <= b.depth; ++l) {
      for (int j = 1; j <= b.columns; ++j) {
        const int top = stack.id_of(b.index, b.rows, j, l);
        const int fx = (j - 1) * p.ratio, fy = (l - 1) * p.ratio;
        if (p.ratio % 2 == 0) {
          for (const int dx : {0, 1}) {
            for (const int dy : {0, 1}) expect_touch(top, stack.id_of(b.index + 1, 1, fx + p.ratio / 2 + dx, fy + p.ratio / 2 + dy));
          }
        } else {
          expect_touch(top, stack.id_of(b.index + 1, 1, fx + (p.ratio + 1) / 2, fy + (p.ratio + 1) / 2));
        }
      }
    }
  }
  const int c = p.top_columns / 2;
  for (const int dx : {0, 1}) {
    for (const int dy : {0, 1}) expect_touch(Stack::striker_id(), stack.id_of(1, 1, c + dx, c + dy));
  }
  EXPECT_EQ(touching_pairs(stack), designed.count());
}

TEST_P(Geometry3dTest, CountsIdsSymmetryAndTheImpactPath) {
  const auto& p = GetParam();
  const auto stack = build(p);
  long expected = 1, columns = p.top_columns;
  for (int k = 1; k <= p.blocks; ++k, columns *= p.ratio) expected += columns * columns * p.rows;
  ASSERT_EQ(static_cast<long>(stack.spheres().size()), expected);
  EXPECT_EQ(granstack::model::sphere_count(stack.spec()), expected);
  for (std::size_t i = 0; i < stack.spheres().size(); ++i) {
    const auto& sp = stack.spheres()[i];
    ASSERT_EQ(sp.id, static_cast<int>(i) + 1);
    if (sp.block == 0) {
      EXPECT_EQ(sp.x, 0.0);
      EXPECT_EQ(sp.y, 0.0);
      continue;
    }
    const auto& b = stack.block(sp.block);
    EXPECT_EQ(stack.id_of(sp.block, sp.row, sp.column, sp.column_y), sp.id);
    // Mirror images in x and in y, and the diagonal swap of x and y.
    const auto& mx = stack.sphere(stack.id_of(sp.block, sp.row, b.columns + 1 - sp.column, sp.column_y));
    const auto& my = stack.sphere(stack.id_of(sp.block, sp.row, sp.column, b.depth + 1 - sp.column_y));
    const auto& swap = stack.sphere(stack.id_of(sp.block, sp.row, sp.column_y, sp.column));
    EXPECT_EQ(mx.x, -sp.x);
    EXPECT_EQ(mx.y, sp.y);
    EXPECT_EQ(my.y, -sp.y);
    EXPECT_EQ(swap.x, sp.y);
    EXPECT_EQ(swap.z, sp.z);
  }
  // The path down from the central top sphere at (R_1, R_1): a chain of contacts ending in the
  // output sphere, in the bottom layer and on the bottom face.
  for (int k = 1; k < p.blocks; ++k) {
    const int cu = stack.impact_column(k), cl = stack.impact_column(k + 1);
    EXPECT_TRUE(touching(stack.sphere(stack.id_of(k, p.rows, cu, cu)), stack.sphere(stack.id_of(k + 1, 1, cl, cl)))) << k;
  }
  const auto& out = stack.sphere(stack.output_sphere_id());
  EXPECT_EQ(out.block, p.blocks);
  EXPECT_EQ(out.row, p.rows);
  EXPECT_EQ(out.column, out.column_y);
  EXPECT_DOUBLE_EQ(out.z - out.radius, 0.0);
  if (p.ratio == 2) {
    EXPECT_DOUBLE_EQ(out.x, out.radius);
    EXPECT_DOUBLE_EQ(out.y, out.radius);
  }
  // The bottom layer: every sphere of the bottom block's last row, in id order.
  const auto bottom = stack.bottom_row_ids();
  const auto& last = stack.block(p.blocks);
  ASSERT_EQ(static_cast<int>(bottom.size()), last.layer());
  EXPECT_EQ(bottom.back() - bottom.front() + 1, last.layer());
  EXPECT_EQ(bottom.back(), last.last_id());
}

std::string nest_name(const ::testing::TestParamInfo<Nest>& info) {
  const auto& p = info.param;
  return "nb" + std::to_string(p.blocks) + "_c" + std::to_string(p.top_columns) + "_rows" + std::to_string(p.rows) +
         "_ratio" + std::to_string(p.ratio);
}

INSTANTIATE_TEST_SUITE_P(Nests, Geometry3dTest,
                         ::testing::Values(Nest{1, 2, 3, 2}, Nest{2, 2, 3, 2}, Nest{3, 2, 2, 2}, Nest{2, 4, 2, 2},
                                           Nest{2, 2, 2, 3}, Nest{2, 2, 2, 4}, Nest{2, 2, 2, 1}),
                         nest_name);

// The four-sphere seats of issue #14: a sphere on four of half its radius sits sqrt(7) r above
// them, at a horizontal distance sqrt(2) r from each; the study's striker sqrt(2) R_1 above the
// four central top spheres.
TEST(Geometry3d, FourSphereSeatsAreThoseOfTheSquarePocket) {
  const double r = 1e-3;
  EXPECT_NEAR(granstack::model::interface_height(r, 2, false, 4), std::sqrt(7.0) * r, 1e-15 * r);
  EXPECT_NEAR(granstack::model::seat_height(r, r, 4), std::sqrt(2.0) * r, 1e-15 * r);
  EXPECT_NEAR(granstack::model::interface_height(r, 3, 4), 4.0 * r, 1e-15 * r);  // odd: on the one below
  const auto stack = build({2, 2, 3, 2});
  const auto& striker = stack.sphere(Stack::striker_id());
  const auto& top = stack.sphere(stack.id_of(1, 1, 1, 1));
  EXPECT_NEAR(striker.z - top.z, std::sqrt(2.0) * top.radius, 1e-12 * top.radius);
  const auto& upper = stack.sphere(stack.id_of(1, 3, 1, 1));
  const auto& lower = stack.sphere(stack.id_of(2, 1, 1, 1));
  EXPECT_NEAR(upper.z - lower.z, std::sqrt(7.0) * lower.radius, 1e-12 * lower.radius);
  EXPECT_NEAR(std::hypot(upper.x - lower.x, upper.y - lower.y), std::sqrt(2.0) * lower.radius, 1e-12 * lower.radius);
}

// Side walls stand on all four sides, touching the lattice; the bottom at z = 0.
TEST(Geometry3d, WallsTouchTheNestOnEverySide) {
  const auto stack = build({2, 2, 2, 2}, true);
  const auto walls = stack.walls();
  ASSERT_EQ(walls.size(), 5U);
  for (const auto& w : walls) {
    double nearest = 1e300;
    for (const auto& s : stack.spheres()) {
      if (s.block == 0) continue;
      const double centre = w.axis == 0 ? s.x : w.axis == 1 ? s.y : s.z;
      nearest = std::min(nearest, std::fabs(centre - w.position) - s.radius);
    }
    EXPECT_NEAR(nearest, 0.0, 1e-15) << w.name;
  }
  EXPECT_EQ(walls[3].name, "wall_front");
  EXPECT_EQ(walls[3].axis, 1);
  EXPECT_EQ(walls[4].position, stack.half_depth());
}

}  // namespace

namespace {

// reduce's per-column energies of a 3D nest, on a frame made here: the nest at rest but for one
// sphere off the diagonal, whose 1/2 m v^2 lands in its own x-column and its own y-column.
TEST(Geometry3d, ASpheresEnergyLandsInItsOwnColumnAlongXAndAlongY) {
  const auto stack = build({2, 2, 2, 2});
  granstack::formats::DumpFrame f;
  f.columns = {"id", "mass", "radius", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"};
  f.atoms = static_cast<long>(stack.spheres().size());
  const int mover = stack.id_of(2, 1, 3, 1);  // block 2, x-column 3, y-column 1
  for (const auto& s : stack.spheres()) {
    const double mass = stack.mass(s);
    const double vz = s.id == mover ? -2.0 : 0.0;
    for (const double v : {static_cast<double>(s.id), mass, s.radius, s.x, s.y, s.z, 0.0, 0.0, vz, 0.0, 0.0, 0.0}) {
      f.values.push_back(v);
    }
  }
  granstack::postproc::FrameAnalyser analyser(stack, "made-here");
  granstack::postproc::FrameEnergy e;
  analyser.analyse(f, e);
  const double ke = 0.5 * stack.block(2).sphere_mass * 4.0;
  ASSERT_EQ(e.column_y_ke.size(), 2U);
  ASSERT_EQ(e.column_y_ke[1].size(), 4U);
  for (std::size_t c = 0; c < 4; ++c) {
    EXPECT_EQ(e.column_ke[1][c], c == 2 ? ke : 0.0) << "x-column " << c + 1;
    EXPECT_EQ(e.column_y_ke[1][c], c == 0 ? ke : 0.0) << "y-column " << c + 1;
  }
  EXPECT_EQ(e.block_ke[1], ke);
}

}  // namespace
