// A fourth engine is its file and its row: the stand-in engine (tests/standin/standin_engine.cpp,
// refsim's integrator under another name with an option of its own), built into a program with
// granstack's commands, is in run's help with its group, runs a case with its option, is refused
// by name where another engine runs, is set beside refsim by validate, and its run is reduced.
// Nothing of granstack names it: what these tests see, the table's row gave.
#include "../support/granstack_test.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace granstack;
using namespace granstack::test;

namespace {

class Standin : public GranstackTest {
 protected:
  fs::path make_case(const std::string& name) {
    const auto c = path(name);
    const auto r = granstack({"generate", "-o", c.string(), "--blocks", "2", "--rows", "3", "--restitution", "0.9"});
    EXPECT_EQ(r.code, 0) << r.output;
    return c;
  }
  static nlohmann::json record(const fs::path& run) { return nlohmann::json::parse(read_bytes(run / "run.json")); }
  // The outputs' XXH3-128 digests run.json records (the dump and the series).
  static nlohmann::json digests(const fs::path& run) {
    auto out = record(run).at("digests").at("outputs");
    for (auto& [file, d] : out.items()) d = d.at("xxh3_128");
    return out;
  }
};

}  // namespace

TEST_F(Standin, ItsRowGivesRunItsNameItsHelpAndItsOptionGroup) {
  const auto r = granstack({"run", "--help"});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("--engine TEXT:{liggghts,refsim,lammps,standin}=liggghts"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("or standin (refsim under another name, a test's stand-in engine)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[Option Group: standin]\n  For --engine standin\n  Options:\n    --standin-threads INT:INT in "
                          "[1 - 256]=1"),
            std::string::npos)
      << r.output;
}

TEST_F(Standin, ItRunsACaseWithItsOwnOptionToRefsimsBitsAndReduceReadsTheRun) {
  const auto c = make_case("standin"), reference = make_case("refsim");
  auto r = granstack({"run", "--engine", "standin", "--standin-threads", "2", c.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = record(c);
  EXPECT_EQ(j.at("engine"), "standin");
  EXPECT_EQ(j.at("status"), "done");
  EXPECT_EQ(j.at("threads"), 2);
  r = granstack({"run", "--engine", "refsim", reference.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(digests(c).size(), 2u);
  EXPECT_EQ(digests(c), digests(reference));
  for (const auto& run : {c, reference}) {
    r = granstack({"reduce", run.string()});
    ASSERT_EQ(r.code, 0) << r.output;
  }
  for (const auto* table : {"block_ke.csv", "energy_parts.csv"}) {
    EXPECT_EQ(read_bytes(c / "reduce" / table), read_bytes(reference / "reduce" / table)) << table;
  }
}

TEST_F(Standin, ItsOptionIsRefusedByNameWhereAnotherEngineRuns) {
  const auto c = make_case("case");
  const auto r = granstack({"run", "--engine", "refsim", "--standin-threads", "2", c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--standin-threads is for standin and none runs here (refsim)"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(c / "run.json"));
}

TEST_F(Standin, ValidateSetsItBesideRefsimAndTheyAgreeToTheBit) {
  const auto c = make_case("case");
  const auto r = granstack({"validate", "--engines", "refsim,standin", c.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(record(c / "validate" / "standin").at("engine"), "standin");
  EXPECT_EQ(digests(c / "validate" / "standin"), digests(c / "validate" / "refsim"));
}
