// The LAMMPS engine as a user meets it: a case run on LAMMPS after LIGGGHTS keeps each engine's
// files apart and is owned by granstack; what LAMMPS cannot run (no lmp, a LAMMPS without
// GRANULAR, a spec without a mapping, a user template with an unknown name) is refused before the
// case is touched; validate and refsim's rules take their engines by name.
#include "../support/granstack_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <functional>

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
  // A program that is no LAMMPS: its -h prints no LAMMPS banner, or fails.
  r = granstack({"run", "--engine", "lammps", "--force", "--lammps", "/bin/true", c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "/bin/true is not a LAMMPS: '/bin/true -h' does not print LAMMPS's banner");
  r = granstack({"run", "--engine", "lammps", "--force", "--lammps", "/bin/false", c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "/bin/false is not a LAMMPS: '/bin/false -h' ended with exit status 1");
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
  // A harmless command (thermo output) that LAMMPS itself refuses.
  text.replace(text.find("thermo_style    custom step atoms ke c_gs_erot cpu"), 50,
               "thermo_style    custom step atoms ke c_gs_erot no_such_keyword");
  std::ofstream(tmpl) << text;
  const auto r = granstack({"run", "--engine", "lammps", "--lammps-template", tmpl.string(), c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "ERROR: Unknown keyword 'no_such_keyword' in thermo_style custom command");
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
  expect_contains(r, "--contact-rules is for refsim and none runs here (liggghts)");
  r = granstack({"run", "--engine", "refsim", "--contact-rules", "lammps", c.string()});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(record(c).at("contact_rules"), "lammps");
  r = granstack({"run", "--lammps-template", path("case/in.stack").string(), c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "--lammps-template is for lammps and none runs here (liggghts)");
}

namespace {
// A LAMMPS that says another version to -h and otherwise is Debian's: what the version's rules
// choose can be seen in the deck it is given.
fs::path fake_lammps(const fs::path& dir, const std::string& version) {
  const auto program = dir / ("lmp-" + std::to_string(std::hash<std::string>{}(version)));
  std::ofstream(program) << "#!/bin/sh\nif [ \"$1\" = -h ]; then lmp -h | sed 's/29 Sep 2021 - Update 2/" << version
                         << "/'; exit 0; fi\nexec lmp \"$@\"\n";
  fs::permissions(program, fs::perms::owner_all);
  return program;
}
}  // namespace

// LAMMPS's version chooses the mapping (#46): a version whose rules granstack does not know is
// refused by name with the known ones listed, before the case is touched; a release of the 2023
// rewrite gets its walls' E' (E* = E / (2 (1 - nu^2)): steel on steel passes steel's own E, where
// the 2021 wall's E' is E / (1 + nu)) and coeff_restitution, and its run.json names the rules.
TEST_F(Engines, LammpsVersionChoosesTheMapping) {
  const auto c = make_case("case", {"--bottom", "wall", "--restitution", "0.9"});
  auto r = granstack({"run", "--engine", "lammps", "--lammps", fake_lammps(dir_, "2 Aug 2023").string(), c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "is version '2 Aug 2023', whose granular rules granstack does not know");
  expect_contains(r, "29 Sep 2021 (every update), run against a real binary; 27 Jun 2024 to 22 Jul 2025, written from its "
                     "source, not run");
  EXPECT_FALSE(fs::exists(c / "run.json"));
  EXPECT_FALSE(fs::exists(c / "in.lammps"));
  // Debian's own: the 2021 wall.
  r = granstack({"run", "--engine", "lammps", c.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(record(c).at("lammps_rules"), "LAMMPS 29 Sep 2021");
  auto deck = read_bytes(c / "in.lammps");
  EXPECT_NE(deck.find(fmt::format("wall/gran granular hertz/material {:.17g} ", 2.0 * (1.0 - 0.3) * 193e9 / (2.0 * (1 - 0.09)))),
            std::string::npos)
      << deck;
  // A 2024 release: the rewrite's wall and coeff_restitution. Debian's binary refuses the damping it lacks.
  r = granstack({"run", "--engine", "lammps", "--force", "--lammps", fake_lammps(dir_, "29 Aug 2024 - Update 1").string(),
                 c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "damping");
  deck = read_bytes(c / "in.lammps");
  EXPECT_NE(deck.find("wall/gran granular hertz/material 193000000000 0.90000000000000002 0.29999999999999999 damping "
                      "coeff_restitution"),
            std::string::npos)
      << deck;
  EXPECT_EQ(record(c).at("lammps_rules"), "LAMMPS 27 Jun 2024 to 22 Jul 2025");
  EXPECT_EQ(deck.find("damping tsuji"), std::string::npos);
}

// A user's LAMMPS template is held to the case as the LIGGGHTS deck is (#46 M3, M4; #65): a
// hard-coded time step, another contact, a dump sent outside the case or a shell command are
// refused before the case is touched, naming the line and what to do; nothing is written outside
// the case.
TEST_F(Engines, ALammpsTemplateIsHeldToTheSpec) {
  const auto c = make_case("case");
  const auto own = read_bytes(fs::path(GRANSTACK_SOURCE_DIR) / "templates" / "in.lammps.tmpl");
  const auto outside = path("elsewhere");
  fs::create_directories(outside);
  const auto refused = [&](const std::string& from, const std::string& to, const std::string& words,
                           const std::string& mend) {
    auto text = own;
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const auto tmpl = path("mine.tmpl");
    std::ofstream(tmpl) << text;
    const auto r = granstack({"run", "--engine", "lammps", "--lammps-template", tmpl.string(), c.string()});
    EXPECT_EQ(r.code, 1) << r.output;
    expect_contains(r, words);
    expect_contains(r, "to mend: " + mend);
    expect_contains(r, "(from " + tmpl.string() + ") does not run its case as the spec says");
    EXPECT_FALSE(fs::exists(c / "run.json")) << words;
    EXPECT_FALSE(fs::exists(c / "in.lammps")) << words;
  };
  const std::string placeholders = "leave it to the template's placeholders";
  refused("timestep        {{dt}}", "timestep        1e-9", "'timestep 1e-9' is not what granstack's deck runs for this case",
          placeholders);
  refused("{{pair_coeffs}}", "{{pair_coeffs}}\npair_coeff 1 1 hertz/material 1e9 0 0.3 damping viscoelastic tangential "
                             "linear_nohistory 0 0",
          "'pair_coeff 1 1 hertz/material 1e9 0 0.3 damping viscoelastic tangential linear_nohistory 0 0' is not what "
          "granstack's deck runs",
          placeholders);
  refused("{{dump_file}}", (outside / "dump.txt").string(), "writes " + (outside / "dump.txt").string() + ", outside the case",
          "write inside the case");
  refused("read_data       {{data_file}}", "read_data       {{data_file}}\nshell touch gotcha",
          "'shell touch gotcha' cannot be followed: it runs a program", "write out the commands it stands for");
  refused("read_data       {{data_file}}", "read_data       {{data_file}}\nlog ../../log.lammps",
          "'log ../../log.lammps' cannot be followed", "write out the commands it stands for");
  refused("read_data       {{data_file}}", "read_data       {{data_file}}\nwrite_dump all atom ../USERFILE.txt",
          "writes ../USERFILE.txt, outside the case", "write inside the case");
  EXPECT_TRUE(fs::is_empty(outside));
}

// A case run on LAMMPS, then on LIGGGHTS, then validated on LAMMPS against refsim keeps LAMMPS's
// files and validate/lammps/: all granstack's, so generate --force replaces them (it called them
// "not written by granstack").
TEST_F(Engines, AnotherEnginesFilesAreGranstacksToReplace) {
  const auto c = make_case("case");
  ASSERT_EQ(granstack({"run", "--engine", "lammps", c.string()}).code, 0);
  // A new run takes the earlier run's files with it, whichever engine wrote them (#65 M19): none of
  // them stands beside the new record.
  ASSERT_EQ(granstack({"run", "--force", c.string()}).code, 0);
  for (const auto* f : {"in.lammps", "log.lammps", "lammps.out"}) EXPECT_FALSE(fs::exists(c / f)) << f;
  ASSERT_EQ(granstack({"run", "--engine", "refsim", "--force", c.string()}).code, 0);
  for (const auto* f : {"log.liggghts", "liggghts.out"}) EXPECT_FALSE(fs::exists(c / f)) << f;
  ASSERT_EQ(granstack({"run", "--engine", "lammps", "--force", c.string()}).code, 0);
  auto r = granstack({"validate", "--engines", "lammps,refsim", c.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  for (const auto* f : {"in.lammps", "log.lammps", "lammps.out", "validate/lammps/run.json"}) EXPECT_TRUE(fs::exists(c / f)) << f;
  r = granstack({"generate", "--force", "-o", c.string(), "--blocks", "2", "--rows", "3"});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(c / "in.lammps"));
  EXPECT_FALSE(fs::exists(c / "validate"));
}
