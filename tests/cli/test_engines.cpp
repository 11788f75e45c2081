// The LAMMPS engine as a user meets it: a case run on LAMMPS after LIGGGHTS keeps each engine's
// files apart and is owned by granstack; what LAMMPS cannot run (no lmp, a LAMMPS without
// GRANULAR, a spec without a mapping, a user template with an unknown name) is refused before the
// case is touched; validate and refsim's rules take their engines by name.
#include "../support/granstack_test.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace granstack;
using namespace granstack::test;

namespace {

class Engines : public GranstackTest {
 protected:
  fs::path make_case(const std::string& name, std::vector<std::string> flags = {}) {
    const auto c = path(name);
    std::vector<std::string> args{"generate", "-o", c.string(), "--blocks", "2", "--rows", "3"};
    args.insert(args.end(), flags.begin(), flags.end());
    EXPECT_EQ(granstack(args).code, 0);
    return c;
  }
  static nlohmann::json record(const fs::path& c) { return nlohmann::json::parse(read_bytes(c / "run.json")); }
};

}  // namespace

TEST_F(Engines, ACaseRunsOnLammpsWithItsOwnDeckLogAndScreenFiles) {
  const auto c = make_case("case", {"--restitution", "0.9"});
  ASSERT_EQ(granstack({"run", c.string()}).code, 0);
  auto r = granstack({"run", "--engine", "lammps", "--force", c.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = record(c);
  EXPECT_EQ(j.at("engine"), "lammps");
  EXPECT_EQ(j.at("lammps_deck"), "in.lammps");
  EXPECT_NE(j.at("lammps_version").get<std::string>().find("2021"), std::string::npos) << j.dump();
  // LAMMPS's own files are the run's outputs (generate --force may replace them); the LIGGGHTS
  // deck is untouched.
  const auto outputs = j.at("outputs").get<std::vector<std::string>>();
  for (const auto* f : {"in.lammps", "log.lammps", "lammps.out"}) {
    EXPECT_NE(std::find(outputs.begin(), outputs.end(), f), outputs.end()) << f;
    EXPECT_TRUE(fs::exists(c / f)) << f;
  }
  EXPECT_NE(read_bytes(c / "in.lammps").find("damping tsuji"), std::string::npos);
  ASSERT_EQ(granstack({"reduce", c.string()}).code, 0);
  r = granstack({"generate", "--force", "-o", c.string(), "--blocks", "2", "--rows", "3"});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(c / "in.lammps"));
}

TEST_F(Engines, WhatLammpsCannotRunIsRefusedBeforeTheCaseIsTouched) {
  const auto c = make_case("case");
  ASSERT_EQ(granstack({"run", c.string()}).code, 0);
  const auto before = read_bytes(c / "run.json");
  auto r = granstack({"run", "--engine", "lammps", "--force", "--lammps", path("no_lmp").string(), c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "--lammps " + path("no_lmp").string() + ": not an executable file");
  // A program that is no LAMMPS with GRANULAR: its -h lists no pair style granular.
  r = granstack({"run", "--engine", "lammps", "--force", "--lammps", "/bin/true", c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "has no pair style 'granular'");
  const auto tmpl = path("mine.tmpl");
  std::ofstream(tmpl) << "units si\n{{no_such_setting}}\n";
  r = granstack({"run", "--engine", "lammps", "--force", "--lammps-template", tmpl.string(), c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "unknown placeholder '{{no_such_setting}}'");
  EXPECT_EQ(read_bytes(c / "run.json"), before);
  EXPECT_FALSE(fs::exists(c / "in.lammps"));
  // A spec whose contact model has no counterpart.
  const auto h = make_case("hooke", {"--normal-model", "hooke"});
  r = granstack({"run", "--engine", "lammps", h.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "normal_model = 'hooke' has no counterpart in LAMMPS");
  EXPECT_FALSE(fs::exists(h / "run.json"));
  EXPECT_FALSE(fs::exists(h / "in.lammps"));
}

// LAMMPS's own error ends the run as failed, with its ERROR line; the case's earlier run is kept
// only until LAMMPS has started (as for LIGGGHTS).
TEST_F(Engines, LammpsErrorsAreTheRunsFailure) {
  const auto c = make_case("case");
  const auto tmpl = path("broken.tmpl");
  auto text = read_bytes(fs::path(GRANSTACK_SOURCE_DIR) / "templates" / "in.lammps.tmpl");
  text.replace(text.find("fix             integr all nve/sphere"), 37, "fix             integr all no_such_style");
  std::ofstream(tmpl) << text;
  const auto r = granstack({"run", "--engine", "lammps", "--lammps-template", tmpl.string(), c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "ERROR: Unrecognized fix style 'no_such_style'");
  const auto j = record(c);
  EXPECT_EQ(j.at("status"), "failed");
  EXPECT_EQ(j.at("lammps_template"), tmpl.string());
}

TEST_F(Engines, ValidateAndRefsimRulesTakeTheirEnginesByName) {
  const auto c = make_case("case", {"--restitution", "0.9", "--friction", "0.3"});
  auto r = granstack({"validate", "--engines", "lammps,lammps", c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "--engines takes two different engines");
  r = granstack({"validate", "--engines", "lammps,refsim", c.string()});
  EXPECT_EQ(r.code, 0) << r.output;
  expect_contains(r, "lammps against refsim");
  EXPECT_EQ(nlohmann::json::parse(read_bytes(c / "validate" / "refsim" / "run.json")).at("contact_rules"), "lammps");
  // LIGGGHTS against LAMMPS with friction: a model difference, reported as a disagreement (exit 5).
  r = granstack({"validate", "--engines", "liggghts,lammps", c.string()});
  EXPECT_EQ(r.code, 5) << r.output;
  r = granstack({"run", "--contact-rules", "lammps", c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "--contact-rules chooses refsim's rules");
  r = granstack({"run", "--engine", "refsim", "--contact-rules", "lammps", c.string()});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(record(c).at("contact_rules"), "lammps");
  r = granstack({"run", "--lammps-template", path("case/in.stack").string(), c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "--lammps-template is the LAMMPS deck's template");
}
