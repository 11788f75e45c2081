// The study's container (geometry = panels): P strips side by side along y at a pitch of the top
// spheres' diameter, with a matrix of soft-sphere chains, rigid walls or nothing between them.
// Every designed contact exact, nothing else touching or overlapping (every pair tried), counts by
// formula, ids, the mirror symmetry between panels, the chains' geometry, the separators.
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include "touching.hpp"

#include <gtest/gtest.h>

#include <cmath>

using granstack::model::Geometry;
using granstack::model::matrix_chain;
using granstack::model::Separator;
using granstack::model::Sphere;
using granstack::model::Stack;
using granstack::model::StackSpec;
using granstack::test::gap;
using granstack::test::touching;
using granstack::test::touching_pairs;

namespace {

struct Container {
  int panels, blocks, top_columns, rows, ratio, impact_panel;
};

StackSpec spec_of(const Container& p, Separator separator = Separator::matrix) {
  StackSpec s;
  s.geometry = Geometry::panels;
  s.panels = p.panels;
  s.blocks = p.blocks;
  s.top_columns = p.top_columns;
  s.rows = p.rows;
  s.radius_ratio = p.ratio;
  s.impact_panel = p.impact_panel;
  s.separator = separator;
  return s;
}

// ceil(N + 1 - sqrt(2)) chain spheres in a pocket of a block N = R_1 / R_k times smaller.
long chain_count(long n) { return n <= 1 ? 0 : static_cast<long>(std::ceil(static_cast<double>(n) + 1.0 - std::sqrt(2.0))); }

class ContainerTest : public ::testing::TestWithParam<Container> {};

TEST_P(ContainerTest, EveryDesignedContactTouchesExactlyAndNothingElseTouchesOrOverlaps) {
  const auto& p = GetParam();
  const auto stack = Stack::build(spec_of(p));
  granstack::test::DesignedContacts designed(stack);
  const auto expect_touch = [&](int a, int b) { designed.expect(a, b); };
  for (const auto& b : stack.blocks()) {
    ASSERT_EQ(b.depth, p.panels);
    for (int l = 1; l <= p.panels; ++l) {
      // Each panel is the study's strip: along x, vertically, and each bottom sphere on the two
      // (even ratio) or the one (odd) below it.
      for (int i = 1; i <= b.rows; ++i) {
        for (int j = 1; j <= b.columns; ++j) {
          const int id = stack.id_of(b.index, i, j, l);
          if (j < b.columns) expect_touch(id, stack.id_of(b.index, i, j + 1, l));
          if (i < b.rows) expect_touch(id, stack.id_of(b.index, i + 1, j, l));
          // Neighbouring panels' top blocks touch (the pitch is their diameter).
          if (b.index == 1 && l < p.panels) expect_touch(id, stack.id_of(1, i, j, l + 1));
          if (i == b.rows && b.index < p.blocks) {
            const int f = (j - 1) * p.ratio;
            if (p.ratio % 2 == 0) {
              for (const int d : {0, 1}) expect_touch(id, stack.id_of(b.index + 1, 1, f + p.ratio / 2 + d, l));
            } else {
              expect_touch(id, stack.id_of(b.index + 1, 1, f + (p.ratio + 1) / 2, l));
            }
          }
        }
      }
    }
  }
  // Each striker on the two central top spheres of its panel.
  for (int id = 1; id <= stack.strikers(); ++id) {
    const int panel = p.impact_panel == granstack::model::kAllPanels ? id : stack.impact_panel();
    for (const int d : {0, 1}) expect_touch(id, stack.id_of(1, 1, p.top_columns / 2 + d, panel));
    if (id > 1) expect_touch(id - 1, id);  // strikers of neighbouring panels, like their top blocks
  }
  // The chains: each sphere on the next, the first and the last on the four spheres around
  // their panel's pocket.
  for (std::size_t i = static_cast<std::size_t>(stack.first_matrix_id() - 1); i < stack.spheres().size(); ++i) {
    const auto& m = stack.spheres()[i];
    const int count = matrix_chain(stack.block(m.block).radius, stack.block(1).radius).count;
    if (m.chain < count) expect_touch(m.id, m.id + 1);
    if (m.chain == 1 || m.chain == count) {
      const int panel = m.chain == 1 ? m.column_y : m.column_y + 1;
      for (const int di : {0, 1}) {
        for (const int dj : {0, 1}) expect_touch(m.id, stack.id_of(m.block, m.row + di, m.column + dj, panel));
      }
    }
  }
  EXPECT_EQ(touching_pairs(stack), designed.count());
}

TEST_P(ContainerTest, CountsIdsSymmetryAndTheImpactedPanel) {
  const auto& p = GetParam();
  const auto stack = Stack::build(spec_of(p));
  long panel_spheres = 0, matrix = 0, columns = p.top_columns, n = 1;
  for (int k = 1; k <= p.blocks; ++k, columns *= p.ratio, n *= p.ratio) {
    panel_spheres += p.panels * columns * p.rows;
    matrix += (p.panels - 1) * (columns - 1) * (p.rows - 1) * chain_count(n);
  }
  const bool all = p.impact_panel == granstack::model::kAllPanels;
  const long strikers = all ? p.panels : 1;
  ASSERT_EQ(stack.strikers(), strikers);
  ASSERT_EQ(static_cast<long>(stack.spheres().size()), strikers + panel_spheres + matrix);
  EXPECT_EQ(granstack::model::sphere_count(stack.spec()), strikers + panel_spheres + matrix);
  EXPECT_EQ(stack.block(1).first_id, strikers + 1);
  EXPECT_EQ(stack.first_matrix_id(), strikers + 1 + panel_spheres);
  // The measured panel: the one hit, the centre one by default and when every panel is hit.
  const int impact = p.impact_panel > 0 ? p.impact_panel : (p.panels + 1) / 2;
  EXPECT_EQ(stack.impact_panel(), impact);
  const double r1 = stack.block(1).radius;
  for (const auto& sp : stack.spheres()) {
    ASSERT_EQ(&sp - stack.spheres().data() + 1, sp.id);
    if (sp.block == 0) {
      // Strikers first, one per panel hit, in panel order.
      ASSERT_LE(sp.id, strikers);
      EXPECT_EQ(sp.y, (2 * (all ? sp.id : impact) - 1 - p.panels) * r1);
      continue;
    }
    EXPECT_GT(sp.id, strikers);
    if (stack.is_matrix(sp)) {
      EXPECT_GE(sp.id, stack.first_matrix_id());
      EXPECT_EQ(sp.atom_type, stack.matrix_type());
      continue;
    }
    EXPECT_EQ(stack.id_of(sp.block, sp.row, sp.column, sp.column_y), sp.id);
    EXPECT_EQ(sp.y, (2 * sp.column_y - 1 - p.panels) * r1);  // panel p's plane, exactly
    // Mirror images across the container's centre plane y = 0, and in x within a panel.
    const auto& my = stack.sphere(stack.id_of(sp.block, sp.row, sp.column, p.panels + 1 - sp.column_y));
    const auto& mx = stack.sphere(stack.id_of(sp.block, sp.row, stack.block(sp.block).columns + 1 - sp.column, sp.column_y));
    EXPECT_EQ(my.y, -sp.y);
    EXPECT_EQ(my.z, sp.z);
    EXPECT_EQ(mx.x, -sp.x);
  }
  // The output sphere and the bottom row are the impacted panel's.
  const auto& out = stack.sphere(stack.output_sphere_id());
  EXPECT_EQ(out.column_y, impact);
  EXPECT_EQ(out.block, p.blocks);
  EXPECT_EQ(out.row, p.rows);
  const auto bottom = stack.bottom_row_ids();
  ASSERT_EQ(static_cast<int>(bottom.size()), stack.block(p.blocks).columns);
  for (const int id : bottom) {
    EXPECT_EQ(stack.sphere(id).column_y, impact);
    EXPECT_EQ(stack.sphere(id).row, p.rows);
  }
}

std::string container_name(const ::testing::TestParamInfo<Container>& info) {
  const auto& p = info.param;
  return "p" + std::to_string(p.panels) + "_nb" + std::to_string(p.blocks) + "_c" + std::to_string(p.top_columns) + "_rows" +
         std::to_string(p.rows) + "_ratio" + std::to_string(p.ratio) + "_hit" +
         (p.impact_panel == granstack::model::kAllPanels ? std::string("all") : std::to_string(p.impact_panel));
}

INSTANTIATE_TEST_SUITE_P(Containers, ContainerTest,
                         ::testing::Values(Container{2, 2, 2, 3, 2, 0}, Container{3, 3, 2, 3, 2, 0},
                                           Container{3, 4, 2, 2, 2, 1}, Container{4, 2, 4, 3, 2, 4},
                                           Container{2, 2, 2, 3, 3, 0}, Container{2, 2, 2, 2, 4, 2},
                                           Container{3, 3, 2, 2, 3, 0}, Container{3, 2, 2, 3, 2, -1},
                                           Container{2, 3, 2, 2, 2, -1}),
                         container_name);

// The chains' own geometry: the study's ratio 2 puts two spheres of 5/6 R_2 in a block-2 pocket
// (the offset sqrt((R + r)^2 - 2 R^2) and the chain span the pitch: 2 (offset + r) = 2 R_1 = 4 R),
// and none beside the top block, whose panels touch.
TEST(Container, ChainsSpanThePitchWithSpheresSmallerThanTheBlocks) {
  const double r1 = 4e-3;
  EXPECT_EQ(matrix_chain(r1, r1).count, 0);
  const auto two = matrix_chain(r1 / 2, r1);
  EXPECT_EQ(two.count, 2);
  EXPECT_NEAR(two.radius, 5.0 / 6.0 * r1 / 2, 1e-15 * r1);
  for (long n = 2; n <= 64; n *= 2) {
    const double r = r1 / static_cast<double>(n);
    const auto c = matrix_chain(r, r1);
    EXPECT_EQ(c.count, chain_count(n)) << n;
    EXPECT_LT(c.radius, r) << n;
    EXPECT_NEAR(c.offset, std::sqrt((r + c.radius) * (r + c.radius) - 2 * r * r), 1e-14 * r) << n;
    EXPECT_NEAR(2 * c.offset + 2 * c.radius * (c.count - 1), 2 * r1, 1e-13 * r1) << n;
  }
}

// The rigid-separator limit: a wall midway between neighbouring panels, touching their top
// blocks on both sides, and no matrix; front and back walls with walled sides.
TEST(Container, SeparatorWallsStandMidwayAndTouchTheTopBlocks) {
  auto s = spec_of({3, 2, 2, 2, 2, 0}, Separator::walls);
  s.sides = granstack::model::Boundary::wall;
  const auto stack = Stack::build(s);
  EXPECT_FALSE(stack.has_matrix());
  EXPECT_EQ(stack.matrix_type(), 0);
  EXPECT_EQ(static_cast<long>(stack.spheres().size()), 1 + 3 * (2 + 4) * 2);
  const auto walls = stack.walls();
  ASSERT_EQ(walls.size(), 6U);
  const double r1 = stack.block(1).radius;
  EXPECT_EQ(walls[2].name, "wall_front");
  EXPECT_EQ(walls[2].position, -3 * r1);
  EXPECT_EQ(walls[4].name, "wall_separator1");
  EXPECT_EQ(walls[4].position, -r1);
  EXPECT_EQ(walls[5].position, r1);
  for (const auto& w : walls) {
    double nearest = 1e300;
    for (const auto& sp : stack.spheres()) {
      if (sp.block != 1) continue;
      nearest = std::min(nearest, std::fabs((w.axis == 0 ? sp.x : sp.y) - w.position) - sp.radius);
    }
    EXPECT_NEAR(nearest, 0.0, 1e-15) << w.name;
  }
}

// A striker on every panel: E_in is every striker's, and the measured panel the centre one.
TEST(Container, AStrikerOnEveryPanelBringsEachItsEnergy) {
  auto s = spec_of({3, 2, 2, 3, 2, 0});
  const auto one = Stack::build(s);
  s.impact_panel = granstack::model::kAllPanels;
  const auto all = Stack::build(s);
  EXPECT_EQ(all.incident_energy(), 3 * one.incident_energy());
  EXPECT_EQ(all.impact_panel(), 2);
  EXPECT_TRUE(all.struck(1) && all.struck(2) && all.struck(3));
  EXPECT_TRUE(!one.struck(1) && one.struck(2) && !one.struck(3));
}

// Every sphere's mass, as the data file gives LIGGGHTS and refsim (its type's density and its
// diameter), is Stack::mass's: the matrix's spheres weigh as Teflon, the panels as steel.
TEST(Container, MassesAreTheDataFilesForEverySphere) {
  const auto stack = Stack::build(spec_of({3, 3, 2, 3, 2, 0}));
  const auto data = granstack::generator::data_file(stack, "masses");
  ASSERT_EQ(data.atoms.size(), stack.spheres().size());
  for (const auto& a : data.atoms) {
    const auto& s = stack.sphere(static_cast<int>(a.id));
    EXPECT_EQ(granstack::model::sphere_mass(0.5 * a.diameter, a.density), stack.mass(s)) << s.id;
    EXPECT_EQ(a.density, stack.is_matrix(s) ? 2170.0 : 8000.0) << s.id;
  }
}

// The time step sees the matrix's contacts: a matrix far softer than the panels leaves dt alone;
// one far stiffer and lighter sets it.
TEST(Container, TheTimeStepSeesTheMatrixContacts) {
  auto s = spec_of({2, 2, 2, 3, 2, 0});
  s.custom_materials = {{"stiff", 1000.0, 1e12, 0.2, {}}};
  s.matrix_material = "stiff";
  const auto stiff = granstack::model::resolve(Stack::build(s));
  EXPECT_NE(stiff.min_contact_pair.find("matrix"), std::string::npos) << stiff.min_contact_pair;
  s.matrix_material = "teflon";
  const auto soft = granstack::model::resolve(Stack::build(s));
  EXPECT_EQ(soft.min_contact_pair.find("matrix"), std::string::npos) << soft.min_contact_pair;
  EXPECT_LT(stiff.dt, soft.dt);
}

}  // namespace
