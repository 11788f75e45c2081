// The MPI decomposition granstack predicts and chooses (runner/decomposition.hpp) against the
// real LIGGGHTS's own counts (its Nlocal and Nghost lines), and the grids it chooses against
// the targets on the 97,921-sphere nest.
#include <granstack/formats/case.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/runner/decomposition.hpp>
#include <granstack/runner/engine_options.hpp>
#include <granstack/runner/runner.hpp>

#include "../support/scratch.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

using namespace granstack;
namespace fs = std::filesystem;

namespace {

fs::path work_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / (std::string(info->test_suite_name()) + "." + info->name())) / name;
}

std::string generate(const std::string& name, const model::StackSpec& spec) {
  generator::GenerateOptions o;
  o.output = work_dir(name);
  o.force = true;
  generator::generate({{name, spec}}, o);
  return o.output.string();
}

model::StackSpec nest(int blocks, int top_columns, int rows) {
  model::StackSpec s;
  s.geometry = model::Geometry::nested3d;
  s.blocks = blocks;
  s.top_columns = top_columns;
  s.rows = rows;
  return s;
}

// A few steps: the spheres have not yet crossed a face, so the counts are the start's.
model::StackSpec few_steps(model::StackSpec s) {
  s.duration = 4.0 * model::resolve(model::Stack::build(s)).dt;
  s.dump_every = 2;
  s.series_every = 2;
  return s;
}

// Runs the case on `ranks` ranks with `grid` (zeros: granstack's choice); returns run.json's
// "decomposition".
nlohmann::json run_decomposed(const std::string& dir, int ranks, std::array<int, 3> grid = {0, 0, 0}) {
  runner::RunOptions o;
  o.ranks = ranks;
  o.own<runner::LiggghtsOptions>().grid = grid;
  o.force = true;
  const auto outcome = runner::run_cases({dir}, o).at(0);
  EXPECT_EQ(outcome.status, runner::RunStatus::done) << outcome.message;
  return formats::Case::open(dir).run_record().record->at("decomposition");
}

}  // namespace

// LIGGGHTS prints its per-rank means to 6 significant digits ("%g"), its maxima whole.
TEST(Decomposition, PredictedLoadsAreLiggghtsOwnCounts) {
  const auto nested = generate("nest", few_steps(nest(3, 4, 6)));
  auto strip_spec = few_steps(model::StackSpec{});
  strip_spec.blocks = 3;
  strip_spec.rows = 10;
  const auto strip = generate("strip", strip_spec);
  struct Run {
    std::string dir;
    int ranks;
    std::array<int, 3> grid;
  };
  for (const auto& r : {Run{nested, 4, {0, 0, 0}}, Run{nested, 4, {1, 2, 2}}, Run{nested, 3, {3, 1, 1}},
                        Run{strip, 4, {0, 0, 0}}, Run{strip, 4, {2, 1, 2}}}) {
    SCOPED_TRACE(r.dir + " on " + std::to_string(r.ranks) + " ranks");
    const auto d = run_decomposed(r.dir, r.ranks, r.grid);
    const auto& lig = d.at("liggghts");
    const auto& pre = d.at("predicted");
    EXPECT_EQ(lig.at("grid"), d.at("grid"));
    EXPECT_NEAR(lig.at("owned_mean").get<double>(), pre.at("owned_mean").get<double>(), 5e-6 * pre.at("owned_mean").get<double>());
    EXPECT_EQ(lig.at("owned_max").get<double>(), pre.at("owned_max").get<double>());
    EXPECT_NEAR(lig.at("ghosts_mean").get<double>(), pre.at("ghosts_mean").get<double>(),
                5e-6 * pre.at("ghosts_mean").get<double>());
  }
}

// The nest (4 blocks under 8 x 8 top columns, 18 rows: 97,921 spheres). LIGGGHTS's own
// choice for `processors * * 1` on the box with a top radius of margin put the faces through
// block 2's columns: its busiest of 16 ranks held 1.28 times the mean. Its ghosts cannot fall
// below its owned spheres on any balanced grid of 16: the top block's 8 mm spheres set a ghost
// reach of 8.3 mm + r, and the bottom block, 3/4 of the spheres, is 128 mm wide and 34 mm high.
TEST(Decomposition, TheNestIsSharedEvenlyAndNeverSplitAcrossItsBlocks) {
  const auto c = formats::Case::open(generate("nest", few_steps(nest(4, 8, 18))));
  ASSERT_EQ(c.stack().spheres().size(), 97921u);
  for (const int ranks : {4, 16, 64}) {
    SCOPED_TRACE(ranks);
    const auto d = runner::choose_decomposition(c, ranks);
    EXPECT_EQ(d.ranks(), ranks);
    EXPECT_EQ(d.grid[2], 1);  // a split in z leaves the bottom block, 3/4 of the spheres, to a few ranks
    EXPECT_LT(d.imbalance(), 1.01);
  }
  // Fewer ghosts than owned spheres come only with a split in z, and with it a busiest rank
  // holding twice the mean or more.
  for (const auto& d : runner::candidate_decompositions(c, 16)) {
    if (d.ghosts_per_owned() < 1.0) {
      EXPECT_GT(d.imbalance(), 1.9) << d.grid[0] << "x" << d.grid[1] << "x" << d.grid[2];
    }
  }
}
