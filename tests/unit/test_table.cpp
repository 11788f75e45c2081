// The decay fit against hand-computed least squares, and the output-fraction table's grouping.
#include <granstack/postproc/fit.hpp>
#include <granstack/postproc/table.hpp>
#include <granstack/postproc/waves.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace granstack;

namespace {

TEST(DecayFit, RecoversAnExactExponential) {
  const std::vector<int> nb{1, 2, 3, 4};
  std::vector<double> f;
  for (int n : nb) f.push_back(0.8 * std::exp(-1.3 * n));
  const auto fit = postproc::fit_decay(nb, f);
  EXPECT_NEAR(fit.alpha, 1.3, 1e-12);
  EXPECT_NEAR(fit.prefactor, 0.8, 1e-12);
  EXPECT_NEAR(*fit.alpha_error, 0.0, 1e-12);
  EXPECT_EQ(fit.points, 4);
}

TEST(DecayFit, MatchesLeastSquaresWorkedByHand) {
  // ln f = -1, -2.5, -3 at N = 1, 2, 3: slope -1, intercept -1/6, residuals 1/6, -1/3, 1/6,
  // s^2 = 1/6 (one degree of freedom), se(alpha) = sqrt(s^2 / 2); through the origin
  // alpha = 15/14 with residual sum (1/14)^2 + (5/14)^2 + (3/14)^2 = 35/196 over 2 dof.
  const auto fit = postproc::fit_decay({1, 2, 3}, {std::exp(-1.0), std::exp(-2.5), std::exp(-3.0)});
  EXPECT_NEAR(fit.alpha, 1.0, 1e-12);
  EXPECT_NEAR(fit.prefactor, std::exp(-1.0 / 6.0), 1e-12);
  EXPECT_NEAR(*fit.alpha_error, std::sqrt(1.0 / 12.0), 1e-12);
  EXPECT_NEAR(*fit.prefactor_error, fit.prefactor * std::sqrt(1.0 / 6.0 * (1.0 / 3.0 + 4.0 / 2.0)), 1e-12);
  EXPECT_NEAR(fit.alpha_origin, 15.0 / 14.0, 1e-12);
  EXPECT_NEAR(*fit.alpha_origin_error, std::sqrt(35.0 / 196.0 / 2.0 / 14.0), 1e-12);
  // cov(ln A, alpha) = -cov(intercept, slope) = s^2 mean(N) / S_NN = (1/6) 2 / 2.
  EXPECT_NEAR(*fit.covariance_ln_prefactor_alpha, 1.0 / 6.0, 1e-12);
}

TEST(DecayFit, RefusesWhatCannotBeFitted) {
  EXPECT_THROW(postproc::fit_decay({2, 2}, {0.1, 0.2}), std::invalid_argument);
  EXPECT_THROW(postproc::fit_decay({1, 2}, {0.1, 0.0}), std::invalid_argument);
  EXPECT_FALSE(postproc::fit_decay({1, 2}, {0.3, 0.1}).alpha_error.has_value());  // no degree of freedom left
}

postproc::CaseReduction reduction(int blocks, double e, double fraction) {
  postproc::CaseReduction r;
  r.spec.blocks = blocks;
  r.spec.restitution.value = e;
  r.output_fraction = fraction;
  r.output_separated = true;
  r.case_dir = "nb" + std::to_string(blocks) + "_e" + std::to_string(e);
  return r;
}

TEST(OutputTable, GroupsByEverythingButBlocksAndFitsEachGroup) {
  std::vector<postproc::CaseReduction> rs;
  for (double e : {0.9, 1.0}) {
    for (int nb = 1; nb <= 3; ++nb) rs.push_back(reduction(nb, e, std::exp(-(1.1 / e) * nb)));
  }
  const auto t = postproc::build_table(rs);
  ASSERT_EQ(t.groups.size(), 2u);
  EXPECT_EQ(t.groups[0].label, "e=1");  // highest restitution first
  EXPECT_EQ(t.groups[1].label, "e=0.9");
  EXPECT_EQ(t.blocks, (std::vector<int>{1, 2, 3}));
  ASSERT_TRUE(t.groups[1].fit);
  EXPECT_NEAR(t.groups[1].fit->alpha * 0.9, 1.1, 1e-12);  // the study's alpha/e form
  const auto md = postproc::table_markdown(t);
  EXPECT_NE(md.find("| N_B | e=1 | e=0.9 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| e=0.9 | 3 |"), std::string::npos) << md;
  EXPECT_NE(postproc::fits_csv(t).find("\"e=0.9\",0.9,3,"), std::string::npos);
  // The same case twice with the same output to the bit (a reproduction runs one spec in two
  // experiments): one row. With another output: refused, both outputs named.
  rs.push_back(reduction(2, 1.0, std::exp(-1.1 * 2)));
  rs.back().case_dir = "elsewhere/nb2_e1";
  const auto again = postproc::build_table(rs);
  ASSERT_EQ(again.groups.size(), 2u);
  EXPECT_EQ(again.groups[0].cases.size(), 3u);
  rs.push_back(reduction(2, 1.0, 0.1));
  try {
    postproc::build_table(rs);
    FAIL() << "two outputs of one case were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("yet their outputs differ"), std::string::npos) << e.what();
  }
}

// Groups that differ in a number are ordered by its value, not by its text.
TEST(OutputTable, OrdersGroupsByValue) {
  std::vector<postproc::CaseReduction> rs;
  for (const int rows : {12, 8, 10}) {
    for (int nb = 1; nb <= 2; ++nb) {
      rs.push_back(reduction(nb, 1.0, std::exp(-1.1 * nb)));
      rs.back().spec.rows = rows;
    }
  }
  const auto t = postproc::build_table(rs);
  ASSERT_EQ(t.groups.size(), 3u);
  EXPECT_EQ(t.groups[0].label, "rows=8");
  EXPECT_EQ(t.groups[1].label, "rows=10");
  EXPECT_EQ(t.groups[2].label, "rows=12");
}

// Containers whose matrix is one custom material defined apart (the stiffness study): the groups
// are told apart by the constant that differs, ordered by its value; a group without the
// material is named by the field that uses it.
TEST(OutputTable, NamesTheCustomMaterialConstantThatTellsGroupsApart) {
  std::vector<postproc::CaseReduction> rs;
  const auto container = [&](double fraction) {
    rs.push_back(reduction(3, 1.0, fraction));
    rs.back().spec.geometry = granstack::model::Geometry::panels;
    rs.back().spec.panels = 3;
  };
  for (const double y : {1e9, 1e7}) {
    container(0.03);
    rs.back().spec.custom_materials = {{"matrix", 2170.0, y, 0.46, {}}};
    rs.back().spec.matrix_material = "matrix";
  }
  container(0.034);
  const auto t = postproc::build_table(rs);
  ASSERT_EQ(t.groups.size(), 3u);
  EXPECT_EQ(t.groups[0].label, "matrix_material=default");
  EXPECT_EQ(t.groups[1].label, "matrix_material=matrix, matrix.youngs_modulus=10000000");
  EXPECT_EQ(t.groups[2].label, "matrix_material=matrix, matrix.youngs_modulus=1000000000");
}

TEST(Peaks, ProminenceRuleKeepsDistinctPeaksAndDropsRipples) {
  // Two clear peaks (1.0 and 0.6) separated by a dip to 0.2, with a ripple of 0.02 on the first.
  const std::vector<double> y{0.0, 0.5, 0.98, 0.96, 1.0, 0.7, 0.2, 0.4, 0.6, 0.3, 0.0};
  EXPECT_EQ(postproc::prominent_peaks(y, 0.05), (std::vector<std::size_t>{4, 8}));
  EXPECT_EQ(postproc::prominent_peaks(y, 0.01), (std::vector<std::size_t>{2, 4, 8}));
  EXPECT_TRUE(postproc::prominent_peaks({1.0, 1.0, 1.0}, 0.05).empty());
}

}  // namespace
