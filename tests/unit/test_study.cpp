// The study catalogue (study/data/catalogue.toml) and the judging of claims.
#include "../../study/src/curves.hpp"

#include <granstack/study/catalogue.hpp>
#include <granstack/study/reproduce.hpp>

#include <gtest/gtest.h>

#include <algorithm>

using namespace granstack::study;

namespace {

TEST(Catalogue, TheBuiltInCatalogueHoldsTheStudysSevenExperimentsWithValidCasesAndClaims) {
  const auto& c = builtin_catalogue();
  const std::vector<std::string> expected{"fig2", "fig3", "friction", "fig4", "sandwich", "eq3", "eq45"};
  EXPECT_EQ(c.names(), expected);
  for (const auto& e : c.experiments) {
    EXPECT_FALSE(e.claims.empty()) << e.name;
    for (const auto& claim : e.claims) {
      EXPECT_LE(claim.low, claim.high) << claim.id;
      EXPECT_FALSE(claim.band_reason.empty()) << claim.id;
      if (claim.paper && claim.id != "eq45.2" && claim.id != "fig3.7") {
        // A stated value lies inside its own acceptance band (except where the claim is the
        // paper's value set against another law).
        EXPECT_TRUE(*claim.paper >= claim.low && *claim.paper <= claim.high) << claim.id;
      }
    }
  }
  // Fig. 3 is the 4 x 4 sweep, named as generate names sweep cases.
  const auto* fig3 = c.find("fig3");
  ASSERT_NE(fig3, nullptr);
  EXPECT_EQ(fig3->cases.size(), 16u);
  EXPECT_EQ(fig3->cases.front().name, "nb1_e1");
  EXPECT_EQ(fig3->cases.back().name, "nb4_e0.9");
  // The isolated collision is a stack granstack can build: one row of two spheres, a striker twice their radius.
  const auto& eq3 = c.find("eq3")->cases.front();
  EXPECT_EQ(eq3.spec.rows, 1);
  EXPECT_EQ(eq3.spec.striker_radius_ratio, 2.0);
}

TEST(Catalogue, SelectionAddsWhatAnExperimentNeedsAndRefusesUnknownNames) {
  const auto& c = builtin_catalogue();
  const auto fig4 = select(c, {"fig4"}, false);
  ASSERT_EQ(fig4.size(), 2u);
  EXPECT_EQ(fig4[0]->name, "fig2");  // the catalogue's order
  EXPECT_EQ(fig4[1]->name, "fig4");
  EXPECT_EQ(select(c, {}, false).size(), c.experiments.size());
  for (const auto* e : select(c, {}, true)) EXPECT_TRUE(e->quick || e->name == "fig2") << e->name;
  try {
    select(c, {"fig9"}, false);
    FAIL() << "an unknown experiment was accepted";
  } catch (const UnknownExperiment& e) {
    EXPECT_NE(std::string(e.what()).find("unknown experiment 'fig9'; known: fig2, fig3, friction"), std::string::npos) << e.what();
  }
}

TEST(Catalogue, ABrokenEntryIsRefusedNamingIt) {
  const auto bad_spec = R"([[experiment]]
name = "x"
title = "t"
source = "s"
analysis = "fig3"
  [experiment.cases.a]
  blocks = 40
)";
  try {
    parse_catalogue(bad_spec, "test.toml");
    FAIL();
  } catch (const CatalogueError& e) {
    EXPECT_NE(std::string(e.what()).find("experiment x case a"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("blocks"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_catalogue("[[experiment]]\nname = \"x\"\ntitle = \"t\"\nsource = \"s\"\nanalysis = \"a\"\nneeds = [\"y\"]\n", "t"),
               CatalogueError);
  EXPECT_THROW(parse_catalogue("[[experiment]\n", "t"), CatalogueError);
}

TEST(Judge, TheFirstReadingWithinTheBandDecidesAndOutsideSaysByHowMuch) {
  Claim c;
  c.quantities = {"a", "b", "c"};
  c.low = 0.08;
  c.high = 0.125;
  auto v = judge(c, {{"a", 0.33}, {"b", 0.1}, {"c", 0.11}}, {});
  EXPECT_EQ(v.verdict, "within");
  EXPECT_EQ(v.reading, "b");
  EXPECT_EQ(v.readings.size(), 3u);
  v = judge(c, {{"a", 0.25}, {"c", 0.15}}, {});
  EXPECT_EQ(v.verdict, "outside");
  EXPECT_EQ(v.reading, "c");                          // the closer of the two
  EXPECT_NEAR(v.off, (0.15 - 0.125) / 0.125, 1e-15);  // relative to the band's scale
  EXPECT_FALSE(v.readings[1].second.has_value());     // b: not measured
  v = judge(c, {}, {});
  EXPECT_EQ(v.verdict, "not measured");
  EXPECT_FALSE(v.value.has_value());
  v = judge(c, {{"a", std::nan("")}}, {});
  EXPECT_EQ(v.verdict, "not measured");  // a NaN is never passed on as a number
}

TEST(Kicks, StepsSeparatedByQuietStretchesAreCountedWithTheEnergyAfterEach) {
  Curve c;
  // Energy 0, rising to 1 over t = 10..12, quiet, rising to 3 over t = 30..31, quiet to t = 50.
  for (int i = 0; i <= 50; ++i) {
    const double t = i;
    c.t.push_back(t);
    c.y.push_back(t < 10 ? 0.0 : t < 12 ? (t - 9) / 3.0 : t < 30 ? 1.0 : t < 31 ? 2.0 : 3.0);
  }
  const auto k = kicks(c, 5.0, 1e-9);
  ASSERT_EQ(k.size(), 2u);
  EXPECT_EQ(k[0].end, 12.0);
  EXPECT_EQ(k[0].after, 1.0);
  EXPECT_EQ(k[1].end, 31.0);
  EXPECT_EQ(k[1].after, 3.0);
  EXPECT_EQ(kicks(c, 25.0, 1e-9).size(), 1u);  // quiet stretches shorter than min_gap join the kicks
}

}  // namespace
