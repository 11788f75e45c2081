// The study catalogue (study/data/catalogue.toml) and the judging of claims.

#include <granstack/study/catalogue.hpp>
#include <granstack/study/reproduce.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

using namespace granstack::study;

namespace {

TEST(Catalogue, TheBuiltInCatalogueHoldsTheStudysExperimentsWithValidCasesAndClaims) {
  const auto& c = builtin_catalogue();
  const std::vector<std::string> expected{"fig2", "fig3", "scale", "friction", "fig4", "sandwich", "container", "eq3", "eq45", "mechanisms", "rows", "plasticity"};
  EXPECT_EQ(c.names(), expected);
  for (const auto& e : c.experiments) {
    // The paper's experiments judge its claims; one beyond the paper has none of its own.
    EXPECT_EQ(e.claims.empty(), e.beyond) << e.name;
    for (const auto& claim : e.claims) {
      EXPECT_LE(claim.low, claim.high) << claim.id;
      EXPECT_FALSE(claim.band_reason.empty()) << claim.id;
      EXPECT_FALSE(claim.quantity.empty()) << claim.id;
      if (claim.paper && claim.id != "fig3.7") {
        // A stated value lies inside its own acceptance band (except where the claim is the
        // paper's value set against another law).
        EXPECT_TRUE(*claim.paper >= claim.low && *claim.paper <= claim.high) << claim.id;
      }
    }
  }
  // Fig. 3 is the 4 x 4 sweep, named as generate names sweep cases, and two heights of three blocks.
  const auto* fig3 = c.find("fig3");
  ASSERT_NE(fig3, nullptr);
  EXPECT_EQ(fig3->cases.size(), 18u);
  auto has = [](const Experiment& e, const std::string& name) {
    return std::any_of(e.cases.begin(), e.cases.end(), [&](const CaseEntry& x) { return x.name == name; });
  };
  EXPECT_TRUE(has(*fig3, "nb1_e1") && has(*fig3, "nb4_e0.9") && has(*fig3, "rows4")) << "fig3's cases";
  // The isolated collision is a stack granstack can build: one row of two spheres, a striker twice their radius.
  const auto& eq3 = c.find("eq3")->cases.front();
  EXPECT_EQ(eq3.spec.rows, 1);
  EXPECT_EQ(eq3.spec.striker_radius_ratio, 2.0);
  // The tall blocks of Fig. 2 and 4 (the paper's "large enough"), and the convergence study only with --full.
  EXPECT_EQ(c.find("fig2")->cases.front().spec.rows, 24);
  EXPECT_TRUE(c.find("rows")->full);
  // One geometry for the figures that share a stack: Fig. 2, Fig. 4 and the sandwich built from
  // Fig. 4's stack run one height, and every claim of the Teflon figures has its 8-row reading.
  auto main_case = [&](const char* name) {
    const auto* e = c.find(name);
    return *std::find_if(e->cases.begin(), e->cases.end(), [&](const CaseEntry& x) { return x.name == e->main; });
  };
  EXPECT_EQ(main_case("fig4").spec.rows, main_case("fig2").spec.rows);
  EXPECT_EQ(main_case("sandwich").spec.rows, main_case("fig4").spec.rows);
  for (const char* name : {"fig4", "sandwich"}) {
    for (const auto& claim : c.find(name)->claims) {
      EXPECT_TRUE(std::any_of(claim.sensitivity.begin(), claim.sensitivity.end(),
                              [](const std::string& q) { return q.find("rows8") != std::string::npos; }))
          << claim.id << " has no 8-row sensitivity reading";
    }
  }
}

// Every number the report gives as measured is computed by the run: an explanation written by
// hand in the catalogue holds no percentage and no number of three or more significant digits
// (the parameters it names, such as 24 rows or e = 0.5, have fewer).
TEST(Catalogue, NoMeasuredValueIsWrittenByHandInAnExplanation) {
  const std::regex decimal(R"([0-9]+\.[0-9]+)");
  for (const auto& e : builtin_catalogue().experiments) {
    EXPECT_EQ(e.explanation.find('%'), std::string::npos) << e.name;
    for (auto it = std::sregex_iterator(e.explanation.begin(), e.explanation.end(), decimal); it != std::sregex_iterator(); ++it) {
      std::string digits;
      for (const char ch : it->str()) {
        if (ch != '.' && !(digits.empty() && ch == '0')) digits += ch;
      }
      EXPECT_LT(digits.size(), 3u) << e.name << ": " << it->str();
    }
  }
}

TEST(Catalogue, SelectionAddsWhatAnExperimentNeedsAndRefusesUnknownNames) {
  const auto& c = builtin_catalogue();
  const auto fig4 = select(c, {"fig4"}, false);
  ASSERT_EQ(fig4.size(), 2u);
  EXPECT_EQ(fig4[0]->name, "fig2");  // the catalogue's order
  EXPECT_EQ(fig4[1]->name, "fig4");
  EXPECT_EQ(select(c, {}, false).size(), c.experiments.size() - 2);  // all but the convergence study and plasticity
  EXPECT_EQ(select(c, {}, false, true).size(), c.experiments.size());  // --full
  EXPECT_EQ(select(c, {"rows"}, false).size(), 1u);                   // named, it runs
  for (const auto* e : select(c, {}, true)) EXPECT_TRUE(e->quick || e->name == "fig2") << e->name;
  try {
    select(c, {"fig9"}, false);
    FAIL() << "an unknown experiment was accepted";
  } catch (const UnknownExperiment& e) {
    EXPECT_NE(std::string(e.what()).find("unknown experiment 'fig9'; known: fig2, fig3, scale, friction"), std::string::npos) << e.what();
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

TEST(Judge, ThePrimaryReadingAloneDecidesAndOutsideSaysByHowMuchBeyondTheNearerEdge) {
  Claim c;
  c.quantity = "a";
  c.sensitivity = {"b", "c"};
  c.paper = 0.10;
  c.low = 0.08;
  c.high = 0.125;
  // A sensitivity reading inside the band is no pass.
  auto v = judge(c, {{"a", 0.33}, {"b", 0.1}, {"c", 0.11}}, {});
  EXPECT_EQ(v.verdict, "outside");
  EXPECT_NEAR(v.off, (0.33 - 0.125) / 0.125, 1e-15);  // beyond the upper edge, relative to it
  EXPECT_NEAR(*v.from_paper, (0.33 - 0.10) / 0.10, 1e-15);
  ASSERT_EQ(v.sensitivity.size(), 2u);
  EXPECT_EQ(v.sensitivity[0].first, "b");
  EXPECT_EQ(*v.sensitivity[0].second, 0.1);
  v = judge(c, {{"a", 0.06}}, {});
  EXPECT_EQ(v.verdict, "outside");
  EXPECT_NEAR(v.off, (0.08 - 0.06) / 0.08, 1e-15);  // below the lower edge, relative to it
  EXPECT_FALSE(v.sensitivity[1].second.has_value());  // c: not measured
  v = judge(c, {{"a", 0.11}}, {{"a", 0.004}});
  EXPECT_EQ(v.verdict, "within");
  EXPECT_EQ(v.off, 0.0);
  EXPECT_NEAR(*v.sigmas, (0.11 - 0.10) / 0.004, 1e-12);  // the distance in standard errors
  v = judge(c, {{"b", 0.1}}, {});
  EXPECT_EQ(v.verdict, "not measured");
  EXPECT_FALSE(v.value.has_value());
  v = judge(c, {{"a", std::nan("")}}, {});
  EXPECT_EQ(v.verdict, "not measured");  // a NaN is never passed on as a number
}

TEST(Catalogue, AClaimWithSeveralPrimaryReadingsIsRefused) {
  const auto text = R"([[experiment]]
name = "x"
title = "t"
source = "s"
analysis = "fig3"
  [[experiment.claim]]
  statement = "s"
  quantity = ["a", "b"]
  band = [0, 1]
  band_reason = "r"
  expect = "within"
)";
  try {
    parse_catalogue(text, "t");
    FAIL() << "a list of primary readings was accepted";
  } catch (const CatalogueError& e) {
    EXPECT_NE(std::string(e.what()).find("one primary reading"), std::string::npos) << e.what();
  }
}

// The catalogue's record: every claim's statement, reading, band, paper value and scope, and every
// experiment's geometry, is what its first fixed values and its recorded changes give.
TEST(Catalogue, EveryChangeToAReadingBandPaperValueOrGeometryIsRecorded) {
  for (const auto& e : builtin_catalogue().experiments) {
    const auto problems = unrecorded_changes(e);
    EXPECT_TRUE(problems.empty()) << e.name << ":\n" << fmt::format("{}", fmt::join(problems, "\n"));
    for (const auto& c : e.claims) EXPECT_FALSE(c.record.date.empty()) << c.id << " has no record";
    if (!e.cases.empty()) {
      EXPECT_FALSE(e.record.date.empty()) << e.name << " has no record of its geometry";
    }
  }
}

// A catalogue of one experiment x (fig3's analysis; `experiment` adds its fixed record and cases)
// holding one claim of quantity q, its band and its fixed record.
std::string one_claim_catalogue(const std::string& experiment, const std::string& band, const std::string& fixed) {
  return fmt::format(R"([[experiment]]
name = "x"
title = "t"
source = "s"
analysis = "fig3"
{}  [[experiment.claim]]
  statement = "s"
  quantity = "q"
  band = {}
  band_reason = "r"
  expect = "within"
  fixed = {}
)",
                     experiment, band, fixed);
}

// A claim whose band was first fixed in the commit that first reported its results (the
// mechanisms experiment's) says so in its record, as a yes or no; text there is refused by name.
TEST(Catalogue, AFirstFixingMadeWithTheResultsInViewIsRecordedAsSuch) {
  const auto parse = [&](const std::string& known) {
    const auto fixed = fmt::format(R"({{ date = "2026-01-01", commit = "abcdef0", {}statement = "s", quantity = "q", band = "[0, 1]", paper = "none" }})", known);
    return parse_catalogue(one_claim_catalogue("", "[0, 1]", fixed), "t").experiments.front();
  };
  EXPECT_FALSE(parse("").claims.front().record.fixed_with_results);
  const auto known = parse("results_known = true, ");
  EXPECT_TRUE(known.claims.front().record.fixed_with_results);
  EXPECT_TRUE(unrecorded_changes(known).empty());
  try {
    parse("results_known = \"yes\", ");
    FAIL() << "a text results_known was taken";
  } catch (const CatalogueError& e) {
    EXPECT_NE(std::string(e.what()).find("'results_known'"), std::string::npos) << e.what();
  }
}

TEST(Catalogue, AChangeWithoutARecordOrWithAWrongBeforeIsFound) {
  const std::string head = one_claim_catalogue(
      R"(fixed = { date = "2026-01-01", geometry = "1 block of 8 rows, 2 top columns, steel, bottom free, sides free, stop duration", physics = "e = 1, mu = 0, striker 1 m/s, radius 1 R_1, steel, bottom radius 0.001 m, model hertz tangential history" }
  [experiment.cases.a]
  blocks = 1
)",
      "[0, 2]", R"({ date = "2026-01-01", statement = "s", quantity = "q", band = "[0, 1]", paper = "none" })");
  // The band moved from [0, 1] to [0, 2] with no record.
  auto problems = unrecorded_changes(parse_catalogue(head, "t").experiments.front());
  ASSERT_EQ(problems.size(), 1u) << fmt::format("{}", fmt::join(problems, "\n"));
  EXPECT_NE(problems[0].find("claim x.1: its band is \"[0, 2]\" but its record gives \"[0, 1]\""), std::string::npos) << problems[0];
  // Recorded, it passes; a change whose before is not the recorded value is found.
  const std::string change = R"(  [[experiment.claim.change]]
  date = "2026-01-02"
  field = "band"
  before = "BEFORE"
  after = "[0, 2]"
  why = "w"
  results_known = true
)";
  auto with = [&](const std::string& before) {
    auto text = head + change;
    text.replace(text.find("BEFORE"), 6, before);
    return unrecorded_changes(parse_catalogue(text, "t").experiments.front());
  };
  EXPECT_TRUE(with("[0, 1]").empty());
  // Made a day after the claim was first fixed (and run), a change that says its results were not
  // known is wrong (three such flags were).
  auto unknowing = head + change;
  unknowing.replace(unknowing.find("BEFORE"), 6, "[0, 1]");
  unknowing.replace(unknowing.find("  results_known = true\n"), 23, "");
  problems = unrecorded_changes(parse_catalogue(unknowing, "t").experiments.front());
  ASSERT_EQ(problems.size(), 1u) << fmt::format("{}", fmt::join(problems, "\n"));
  EXPECT_NE(problems[0].find("claim x.1: its change of band on 2026-01-02 came after it was first fixed and run "
                             "(2026-01-01): say results_known = true"),
            std::string::npos)
      << problems[0];
  // A statement rewritten with no record (mechanisms.3's was, #68.2) is found too.
  auto reworded = head + change;
  reworded.replace(reworded.find("BEFORE"), 6, "[0, 1]");
  reworded.replace(reworded.find("statement = \"s\"\n"), 16, "statement = \"said otherwise\"\n");
  problems = unrecorded_changes(parse_catalogue(reworded, "t").experiments.front());
  ASSERT_EQ(problems.size(), 1u) << fmt::format("{}", fmt::join(problems, "\n"));
  EXPECT_NE(problems[0].find("claim x.1: its statement is \"said otherwise\" but its record gives \"s\""), std::string::npos)
      << problems[0];
  problems = with("[0, 3]");
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("says before = \"[0, 3]\", but the record had \"[0, 1]\""), std::string::npos) << problems[0];
  // The main case's geometry and physics are recorded too: 24 rows where the record says 8, a
  // restitution of 0.95 where it says 1.
  const auto with_case_field = [&](const std::string& field) {
    auto text = head + change;
    text.replace(text.find("BEFORE"), 6, "[0, 1]");
    text.replace(text.find("blocks = 1\n"), 11, "blocks = 1\n  " + field + "\n");
    return unrecorded_changes(parse_catalogue(text, "t").experiments.front());
  };
  for (const auto& [field, said] : {std::pair{"rows = 24", "experiment x: its geometry is \"1 block of 24 rows"},
                                    std::pair{"restitution = 0.95", "experiment x: its physics is \"e = 0.95, mu = 0"}}) {
    problems = with_case_field(field);
    ASSERT_EQ(problems.size(), 1u) << fmt::format("{}", fmt::join(problems, "\n"));
    EXPECT_NE(problems[0].find(said), std::string::npos) << problems[0];
  }
}

}  // namespace
