// The nested-stack geometry against physics.md section 1: exact touching, no overlap, counts,
// mirror symmetry, the striker's seat and the interface angle.
#include <granstack/model/stack.hpp>

#include "touching.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>
#include <vector>

using granstack::model::Stack;
using granstack::model::StackSpec;

namespace {

struct Layout {
  int blocks;
  int top_columns;
  int rows;
  int ratio;
  // A design's: each interface's ratio and each block's rows (empty: ratio and rows for all).
  std::vector<int> ratios = {}, block_rows = {};
  StackSpec spec() const {
    StackSpec s;
    s.blocks = blocks;
    s.top_columns = top_columns;
    s.rows = rows;
    s.radius_ratio = ratio;
    s.radius_ratios = ratios;
    s.block_rows = block_rows;
    return s;
  }
};

class GeometryTest : public ::testing::TestWithParam<Layout> {
 protected:
  Stack build() const { return Stack::build(GetParam().spec()); }
};

using granstack::test::gap;
using granstack::test::touching;
using granstack::test::touching_pairs;

TEST_P(GeometryTest, EveryDesignedContactTouchesExactlyAndNothingElseTouchesOrOverlaps) {
  const auto stack = build();
  const auto& p = GetParam();
  long designed = 0;
  auto expect_touch = [&](int a, int b) {
    EXPECT_TRUE(touching(stack.sphere(a), stack.sphere(b)))
        << "ids " << a << " and " << b << " gap " << gap(stack.sphere(a), stack.sphere(b));
    ++designed;
  };
  for (const auto& b : stack.blocks()) {
    for (int i = 1; i <= b.rows; ++i) {
      for (int j = 1; j <= b.columns; ++j) {
        if (j < b.columns) expect_touch(stack.id_of(b.index, i, j), stack.id_of(b.index, i, j + 1));  // horizontal
        if (i < b.rows) expect_touch(stack.id_of(b.index, i, j), stack.id_of(b.index, i + 1, j));     // vertical
      }
    }
    if (b.index < p.blocks) {  // interface: each bottom sphere on the sphere(s) below its centre
      const auto& below = stack.block(b.index + 1);
      const int n = p.spec().ratio_below(b.index);
      for (int j = 1; j <= b.columns; ++j) {
        const int first = (j - 1) * n;  // columns of the lower block under column j: first+1 .. first+n
        const int top = stack.id_of(b.index, b.rows, j);
        if (n % 2 == 0) {
          expect_touch(top, stack.id_of(below.index, 1, first + n / 2));
          expect_touch(top, stack.id_of(below.index, 1, first + n / 2 + 1));
        } else {
          expect_touch(top, stack.id_of(below.index, 1, first + (n + 1) / 2));
        }
      }
    }
  }
  const int c = stack.block(1).columns;
  expect_touch(Stack::striker_id(), stack.id_of(1, 1, c / 2));
  expect_touch(Stack::striker_id(), stack.id_of(1, 1, c / 2 + 1));

  EXPECT_EQ(touching_pairs(stack), designed);
}

TEST_P(GeometryTest, CountsIdsAndLayoutFollowTheDocumentedOrder) {
  const auto stack = build();
  const auto& p = GetParam();
  const auto spec = p.spec();
  long expected = 1;
  long columns = p.top_columns;
  for (int k = 1; k <= p.blocks; ++k) {
    expected += columns * spec.rows_of(k);
    if (k < p.blocks) columns *= spec.ratio_below(k);
  }
  ASSERT_EQ(static_cast<long>(stack.spheres().size()), expected);
  if (p.rows == 8 && p.ratio == 2 && p.ratios.empty() && p.block_rows.empty()) {
    EXPECT_EQ(expected, 8L * p.top_columns * ((1L << p.blocks) - 1) + 1);  // physics.md section 6
  }
  for (std::size_t i = 0; i < stack.spheres().size(); ++i) {
    const auto& sp = stack.spheres()[i];
    EXPECT_EQ(sp.id, static_cast<int>(i) + 1);
    EXPECT_EQ(sp.atom_type, sp.block == 0 ? p.blocks + 1 : sp.block);
    if (sp.block > 0) {
      EXPECT_EQ(stack.id_of(sp.block, sp.row, sp.column), sp.id);
    }
  }
  // Every block spans the same width, 2 C R_1, centred on x = 0.
  for (const auto& b : stack.blocks()) {
    EXPECT_NEAR(b.columns * 2.0 * b.radius, 2.0 * stack.half_width(), 1e-15);
    double ratio_product = 1.0;  // R_k / R_N
    for (int j = b.index; j < p.blocks; ++j) ratio_product *= spec.ratio_below(j);
    EXPECT_DOUBLE_EQ(b.radius, 1e-3 * ratio_product);
    EXPECT_EQ(b.rows, spec.rows_of(b.index));
  }
  // The bottom face is z = 0; the output sphere is in the bottom row, on the impact path: just
  // right of the axis for ratio 2, straight below the top block's right central sphere
  // (x = R_1) for an odd ratio (each sphere rests on one).
  const auto& out = stack.sphere(stack.output_sphere_id());
  EXPECT_EQ(out.block, p.blocks);
  EXPECT_EQ(out.row, spec.rows_of(p.blocks));
  if (p.ratios.empty() && p.ratio == 2) {
    EXPECT_DOUBLE_EQ(out.x, out.radius);  // the study's definition
  }
  if (p.ratios.empty() && p.ratio % 2 == 1) {
    EXPECT_DOUBLE_EQ(out.x, stack.block(1).radius);
  }
  EXPECT_DOUBLE_EQ(out.z - out.radius, 0.0);
  // Down the impact path, the top sphere of each block's impact column touches the bottom sphere
  // of the impact column above it: the path is a chain of contacts.
  for (int k = 1; k < p.blocks; ++k) {
    const auto& upper = stack.sphere(stack.id_of(k, spec.rows_of(k), stack.impact_column(k)));
    const auto& lower = stack.sphere(stack.id_of(k + 1, 1, stack.impact_column(k + 1)));
    EXPECT_NEAR(std::hypot(upper.x - lower.x, upper.z - lower.z), upper.radius + lower.radius, 1e-12 * upper.radius)
        << "block " << k;
  }
}

TEST_P(GeometryTest, MirrorSymmetricAboutTheImpactAxis) {
  const auto stack = build();
  for (const auto& sp : stack.spheres()) {
    if (sp.block == 0) {
      EXPECT_EQ(sp.x, 0.0);
      continue;
    }
    const auto& twin = stack.sphere(stack.id_of(sp.block, sp.row, stack.block(sp.block).columns + 1 - sp.column));
    EXPECT_EQ(twin.x, -sp.x);
    EXPECT_EQ(twin.z, sp.z);
    EXPECT_EQ(twin.radius, sp.radius);
  }
}

std::string layout_name(const ::testing::TestParamInfo<Layout>& info) {
  const auto& p = info.param;
  if (!p.ratios.empty()) {
    return fmt::format("nb{}_c{}_rows_{}_ratios_{}", p.blocks, p.top_columns, fmt::join(p.block_rows, "_"),
                       fmt::join(p.ratios, "_"));
  }
  return "nb" + std::to_string(p.blocks) + "_c" + std::to_string(p.top_columns) + "_rows" + std::to_string(p.rows) +
         "_ratio" + std::to_string(p.ratio);
}

std::vector<Layout> layouts() {
  std::vector<Layout> out;
  for (int nb = 1; nb <= 5; ++nb) {
    for (int c : {2, 4, 6}) out.push_back({nb, c, 8, 2});
  }
  // The general radius ratio: even ratios rest on two spheres, odd ones on the one below.
  for (int ratio : {1, 3, 4}) out.push_back({3, 2, 5, ratio});
  out.push_back({2, 8, 3, 2});
  // A design's stack: each interface its own ratio (odd and even mixed), each block its rows.
  out.push_back({3, 2, 8, 2, {3, 2}, {4, 2, 3}});
  out.push_back({4, 2, 8, 2, {2, 3, 2}, {2, 3, 1, 2}});
  out.push_back({3, 4, 8, 2, {4, 1}, {3, 3, 2}});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Stacks, GeometryTest, ::testing::ValuesIn(layouts()), layout_name);

// The stacking chosen against the ratio's parity (physics.md section 1): ratio 2 aligned sets each
// bottom-row sphere straight on one sphere of a block of 2 C + 1 columns, equal spheres nested on
// two of C + 1; each sphere touches exactly the one or two below it and nothing else touches, the
// stack stays mirror-symmetric, and the impact path is a chain of contacts.
TEST(Geometry, AStackingAgainstTheRatiosParityAddsAColumnAndRestsEachSphereAsChosen) {
  using granstack::model::Stacking;
  struct Case {
    std::vector<int> ratios;
    Stacking stacking;
  };
  for (const auto& c : {Case{{2, 2}, Stacking::aligned}, Case{{1, 1}, Stacking::nested}, Case{{3, 1}, Stacking::nested},
                        Case{{4, 1}, Stacking::aligned}, Case{{2, 1}, Stacking::nested}}) {
    StackSpec spec;
    spec.blocks = 3;
    spec.rows = 3;
    spec.radius_ratios = c.ratios;
    spec.stacking = c.stacking;
    const auto stack = Stack::build(spec);
    const auto name = fmt::format("ratios {} {}", fmt::join(c.ratios, ","), granstack::model::to_string(c.stacking));
    const int supports = c.stacking == Stacking::aligned ? 1 : 2;
    granstack::test::DesignedContacts designed(stack);
    for (const auto& b : stack.blocks()) {
      for (int i = 1; i <= b.rows; ++i) {
        for (int j = 1; j <= b.columns; ++j) {
          if (j < b.columns) designed.expect(stack.id_of(b.index, i, j), stack.id_of(b.index, i, j + 1));
          if (i < b.rows) designed.expect(stack.id_of(b.index, i, j), stack.id_of(b.index, i + 1, j));
        }
      }
      if (b.index == spec.blocks) continue;
      const auto& below = stack.block(b.index + 1);
      const int n = spec.ratio_below(b.index);
      const int natural = n * b.columns;
      EXPECT_EQ(below.columns, natural + ((n % 2 == 0) == (supports == 1) ? 1 : 0)) << name << ", block " << below.index;
      for (int j = 1; j <= b.columns; ++j) {  // every sphere below within a radius sum of this one's centre
        const auto& upper = stack.sphere(stack.id_of(b.index, b.rows, j));
        int touches = 0;
        for (int l = 1; l <= below.columns; ++l) {
          const int id = stack.id_of(below.index, 1, l);
          if (touching(upper, stack.sphere(id))) {
            designed.expect(upper.id, id);
            ++touches;
          }
        }
        EXPECT_EQ(touches, supports) << name << ", block " << b.index << " column " << j;
      }
    }
    const int cols = stack.block(1).columns;
    designed.expect(Stack::striker_id(), stack.id_of(1, 1, cols / 2));
    designed.expect(Stack::striker_id(), stack.id_of(1, 1, cols / 2 + 1));
    EXPECT_EQ(touching_pairs(stack), designed.count()) << name;
    for (const auto& sp : stack.spheres()) {
      if (sp.block == 0) continue;
      EXPECT_EQ(stack.sphere(stack.id_of(sp.block, sp.row, stack.block(sp.block).columns + 1 - sp.column)).x, -sp.x) << name;
    }
    for (int k = 1; k < spec.blocks; ++k) {
      const auto& upper = stack.sphere(stack.id_of(k, spec.rows, stack.impact_column(k)));
      const auto& lower = stack.sphere(stack.id_of(k + 1, 1, stack.impact_column(k + 1)));
      EXPECT_TRUE(touching(upper, lower)) << name << ": the impact path breaks below block " << k;
      if (supports == 1) {
        EXPECT_EQ(lower.x, upper.x) << name;
      }
    }
  }
}

TEST(Geometry, AStackingOtherThanTheRatiosIsRefusedWithSideWallsOrOffTheStrip) {
  StackSpec s;
  s.stacking = granstack::model::Stacking::nested;
  s.radius_ratio = 1;
  s.sides = granstack::model::Boundary::wall;
  auto issues = granstack::model::validate(s);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].field, "stacking");
  EXPECT_NE(issues[0].message.find("use sides = free"), std::string::npos) << issues[0].message;
  s.sides = granstack::model::Boundary::free_surface;
  s.geometry = granstack::model::Geometry::nested3d;
  issues = granstack::model::validate(s);
  ASSERT_FALSE(issues.empty());
  EXPECT_EQ(issues[0].field, "stacking");
  EXPECT_NE(issues[0].message.find("applies to geometry = strip only"), std::string::npos) << issues[0].message;
}

// The isolated collision of physics.md section 5: a striker rho times the top radius on one row
// of two spheres touches both, at sin(theta) = 1 / (rho + 1) from the vertical, and nothing else.
TEST(Geometry, ALargeStrikerRestsOnTheTwoCentralSpheresAtTheAngleOfItsRadius) {
  for (const double rho : {1.0, 2.0, 3.0, 4.0, 7.5}) {
    StackSpec s;
    s.blocks = 1;
    s.rows = 1;
    s.striker_radius_ratio = rho;
    const auto stack = Stack::build(s);
    const auto& striker = stack.sphere(Stack::striker_id());
    EXPECT_DOUBLE_EQ(striker.radius, rho * stack.block(1).radius);
    for (const int j : {1, 2}) {
      const auto& small = stack.sphere(stack.id_of(1, 1, j));
      EXPECT_TRUE(touching(striker, small)) << "rho " << rho << " gap " << gap(striker, small);
      EXPECT_NEAR(std::fabs(striker.x - small.x) / (striker.radius + small.radius), 1.0 / (rho + 1.0), 1e-15);
    }
    EXPECT_NEAR(stack.striker_mass(), rho * rho * rho * stack.block(1).sphere_mass, 1e-15 * stack.striker_mass());
  }
}

TEST(Geometry, InterfaceAndStrikerAnglesAreThoseOfPhysicsMd) {
  StackSpec s;
  s.blocks = 2;
  const auto stack = Stack::build(s);
  // Bottom-left sphere of block 1 and the first sphere of block 2's top row below it.
  const auto& upper = stack.sphere(stack.id_of(1, 8, 1));
  const auto& lower = stack.sphere(stack.id_of(2, 1, 1));
  const double cos_theta = (upper.z - lower.z) / (upper.radius + lower.radius);
  EXPECT_NEAR(cos_theta, 2.0 * std::sqrt(2.0) / 3.0, 1e-14);
  const auto& striker = stack.sphere(Stack::striker_id());
  const auto& right = stack.sphere(stack.id_of(1, 1, 2));
  EXPECT_NEAR((striker.z - right.z) / (2.0 * right.radius), std::cos(M_PI / 6.0), 1e-14);  // 30 degrees
}

// An off-centre blow at -k is the mirror image of the one at k (#46, M1): the striker at -x, every
// sphere's twin at -x, and the impact path (so the output and middle spheres) the mirror image of
// k's, block by block and row by row. The path's bottom sphere lies one bottom radius beside the
// striker's axis, on the far side from the stack's axis, at every offset the top row allows. (The
// path for k < 0 once started from the inner struck sphere: 3 bottom radii off for k = -1 on 2
// blocks of 6 top columns, and a 13 % lower output fraction than its mirror image.)
TEST(Geometry, ABlowAtMinusKIsTheMirrorImageOfTheBlowAtK) {
  for (const auto& layout : {Layout{2, 6, 3, 2}, Layout{3, 6, 3, 2}, Layout{3, 8, 2, 2, {3, 2}}, Layout{2, 8, 2, 2, {1}},
                             Layout{4, 4, 3, 2}}) {
    const int most = layout.top_columns / 2 - 1;
    for (int k = 1; k <= most; ++k) {
      auto spec = layout.spec();
      spec.impact_offset = k;
      const auto right = Stack::build(spec);
      spec.impact_offset = -k;
      const auto left = Stack::build(spec);
      const auto name = fmt::format("{} blocks, {} top columns, offset {}", layout.blocks, layout.top_columns, k);
      const auto& sr = right.sphere(Stack::striker_id());
      const auto& sl = left.sphere(Stack::striker_id());
      EXPECT_EQ(sr.x, 2.0 * k * right.block(1).radius) << name;
      EXPECT_EQ(sl.x, -sr.x) << name;
      EXPECT_EQ(sl.z, sr.z) << name;
      for (const auto& sp : right.spheres()) {
        if (sp.block == 0) continue;
        const auto& twin = left.sphere(left.id_of(sp.block, sp.row, left.block(sp.block).columns + 1 - sp.column));
        EXPECT_EQ(twin.x, -sp.x) << name;
        EXPECT_EQ(twin.z, sp.z) << name;
      }
      for (const auto& b : right.blocks()) {
        EXPECT_EQ(left.impact_column(b.index), b.columns + 1 - right.impact_column(b.index)) << name << ", block " << b.index;
        for (int i = 1; i <= b.rows; ++i) {
          EXPECT_EQ(left.sphere(left.impact_path_id(b.index, i)).x, -right.sphere(right.impact_path_id(b.index, i)).x)
              << name << ", block " << b.index << " row " << i;
        }
      }
      const auto& bottom = right.block(layout.blocks);
      const auto& out_r = right.sphere(right.output_sphere_id());
      const auto& out_l = left.sphere(left.output_sphere_id());
      if (layout.ratios.empty() || layout.ratios[0] % 2 == 0) {  // even ratios: the path steps toward the axis
        EXPECT_NEAR(out_r.x - sr.x, bottom.radius, 1e-12 * bottom.radius) << name;
        EXPECT_NEAR(out_l.x - sl.x, -bottom.radius, 1e-12 * bottom.radius) << name;
      }
      EXPECT_EQ(out_l.x, -out_r.x) << name;
    }
  }
}

}  // namespace
