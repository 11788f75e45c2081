// What ran is what is checked (issue #65): a run on LIGGGHTS or LAMMPS is held to the commands
// the program executed, read from its log, not to its deck's lines; a deck run by hand is adopted
// once its log and outputs show the case's deck, whole. Each test is a user's template or hand run
// on the real programs, and fails on the commit before.
#include "../support/granstack_test.hpp"

#include <granstack/os/mpi_session.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using namespace granstack;
using namespace granstack::test;

namespace {

class WhatRan : public GranstackTest {
 protected:
  // A template of LIGGGHTS's (engine "liggghts") or LAMMPS's with `from` replaced by `to`.
  fs::path edited(const std::string& engine, const std::string& from, const std::string& to, const std::string& name) {
    auto text = read_bytes(fs::path(GRANSTACK_SOURCE_DIR) / "templates" /
                           (engine == "liggghts" ? "in.granstack.tmpl" : "in.lammps.tmpl"));
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    const auto tmpl = path(name + "." + engine + ".tmpl");
    std::ofstream(tmpl) << text;
    return tmpl;
  }
  // A one-block case, its deck from `tmpl` where that is LIGGGHTS's, run on `engine` with `tmpl` where
  // that is LAMMPS's.
  Result run_with(const std::string& engine, const fs::path& tmpl, const std::string& name,
                  std::vector<std::string> flags = {}) {
    std::vector<std::string> args{"generate", "-o", path(name).string(), "--blocks", "1", "--rows", "3"};
    if (engine == "liggghts") args.insert(args.end(), {"--template", tmpl.string()});
    args.insert(args.end(), flags.begin(), flags.end());
    const auto g = granstack(args);
    EXPECT_EQ(g.code, 0) << g.output;
    if (engine == "liggghts") return granstack({"run", path(name).string()});
    return granstack({"run", "--engine", "lammps", "--lammps-template", tmpl.string(), path(name).string()});
  }
  static nlohmann::json record(const fs::path& c) { return nlohmann::json::parse(read_bytes(c / "run.json")); }
  // The run was refused, saying `words`, and nothing of it can be reduced under the case's labels.
  void refused(const Result& r, const std::string& name, const std::string& words) {
    EXPECT_EQ(r.code, 1) << r.output;
    expect_contains(r, words);
    if (fs::exists(path(name) / "run.json")) {
      EXPECT_NE(record(path(name)).at("status"), "done");
    }
    EXPECT_NE(granstack({"reduce", path(name).string()}).code, 0);
  }
};

// Both templates end with the run: a command put before it runs before the run.
const std::string kRun = "{{run}}";

// N1: a time step the deck's lines do not show: through an include, an if, partition, or a fix that
// changes it while it runs.
TEST_F(WhatRan, ATimeStepTheLinesDoNotShowIsRefusedOnBothEngines) {
  std::ofstream(path("dt.txt")) << "timestep 1e-7\n";
  for (const std::string engine : {"liggghts", "lammps"}) {
    const auto include = "include " + path("dt.txt").string() + "\n" + kRun;
    auto r = run_with(engine, edited(engine, kRun, include, "inc"), "inc_" + engine);
    refused(r, "inc_" + engine, "dt.txt:1: 'timestep 1e-7' is not what granstack's deck runs for this case");
    expect_contains(r, "the run did not execute its case as the spec says");
    EXPECT_TRUE(record(path("inc_" + engine)).at("executed").contains("problems"));
    r = run_with(engine, edited(engine, kRun, "if \"1 > 0\" then \"timestep 1e-7\"\n{{run}}", "if"), "if_" + engine);
    refused(r, "if_" + engine, "'timestep 1e-7' is not what granstack's deck runs for this case");
    r = run_with(engine, edited(engine, kRun, "fix dtr all dt/reset 1 NULL NULL 1e-6\n{{run}}", "reset"),
                 "reset_" + engine);
    refused(r, "reset_" + engine, "is a command granstack's deck does not run (fix dt/reset)");
  }
  const auto r = run_with("liggghts", edited("liggghts", kRun, "partition yes 1 timestep 1e-7\n{{run}}", "part"), "part");
  refused(r, "part", "'partition yes 1 timestep 1e-7' cannot be followed");
}

// N2: the output sphere's group redefined after granstack's groups.
TEST_F(WhatRan, TheOutputSphereIsTheCasesOwnOnBothEngines) {
  for (const std::string engine : {"liggghts", "lammps"}) {
    const auto r = run_with(engine, edited(engine, "{{groups}}", "{{groups}}\ngroup output_sphere clear\ngroup output_sphere id 1",
                                           "group"),
                            "group_" + engine);
    refused(r, "group_" + engine, "'group output_sphere clear' redefines group output_sphere");
  }
}

// N4: nothing outside the case is written: a literal path is refused before the run; one the deck
// builds from a variable makes the program fail at that command, before it writes (Landlock).
TEST_F(WhatRan, NoRunWritesOutsideItsCase) {
  const auto user = path("USERFILE.txt");
  std::ofstream(user) << "mine";
  for (const std::string engine : {"liggghts", "lammps"}) {
    auto r = run_with(engine, edited(engine, kRun, "print \"x\" file " + user.string() + "\n{{run}}", "abs"),
                      "abs_" + engine);
    refused(r, "abs_" + engine, "writes " + user.string() + ", outside the case");
    EXPECT_FALSE(fs::exists(path("abs_" + engine) / "run.json")) << "refused before the run";
    r = run_with(engine,
                 edited(engine, kRun, "variable f string ../USERFILE.txt\nprint \"x\" file ${f}\n{{run}}", "var"),
                 "var_" + engine);
    EXPECT_EQ(read_bytes(user), "mine") << engine;
    if (!record(path("var_" + engine)).value("writes_confined", false)) {
      GTEST_SKIP() << "this kernel has no Landlock (Linux 5.13 and later): a write the deck builds at run time is "
                      "found only after it";
    }
    refused(r, "var_" + engine, "Cannot open print file ../USERFILE.txt");
    expect_contains(r, "granstack lets the program write only inside the case");
  }
}

// N5: physics a template adds is refused unless the spec lists it; then the run, reduce and table
// name it.
TEST_F(WhatRan, PhysicsATemplateAddsIsRefusedUnlessTheSpecListsIt) {
  const char* added[] = {"fix g2 all gravity 9.81 vector 0 0 -1", "fix visc all viscous 0.001", "fix f all freeze",
                         "displace_atoms all move 0 0 1e-9"};
  int k = 0;
  for (const std::string engine : {"liggghts", "lammps"}) {
    for (const auto* cmd : added) {
      const auto name = fmt::format("n5_{}_{}", engine, k++);
      const auto r = run_with(engine, edited(engine, kRun, std::string(cmd) + "\n{{run}}", name), name);
      refused(r, name, fmt::format("'{}' is a command granstack's deck does not run", cmd));
      expect_contains(r, "deck_additions");
    }
    const auto name = "none_" + engine;
    const auto r = run_with(engine, edited(engine, "fix             integr all nve/sphere", "# none", name), name);
    refused(r, name, "the deck never ran 'fix integr all nve/sphere'");
  }
  const auto r = run_with("liggghts", edited("liggghts", kRun, "fix visc all viscous 0.001\n{{run}}", "listed"),
                          "listed", {"--deck-additions", "fix viscous"});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto additions = record(path("listed")).at("executed").at("additions");
  ASSERT_EQ(additions.size(), 1u);
  EXPECT_NE(additions[0].get<std::string>().find("fix visc all viscous 0.001 (in.stack:"), std::string::npos) << additions;
  auto reduce = granstack({"reduce", path("listed").string()});
  EXPECT_EQ(reduce.code, 0) << reduce.output;
  expect_contains(reduce, "the deck of listed added what its spec's deck_additions lists: fix visc all viscous 0.001");
  const auto summary = nlohmann::json::parse(read_bytes(path("listed") / "reduce" / "summary.json"));
  EXPECT_EQ(summary.at("deck_additions").size(), 1u);
  // table: the case with the addition is a group of its own, named by it.
  ASSERT_EQ(granstack({"generate", "-o", path("plain").string(), "--blocks", "1", "--rows", "3"}).code, 0);
  ASSERT_EQ(granstack({"run", path("plain").string()}).code, 0);
  const auto table = granstack({"table", path("listed").string(), path("plain").string()});
  EXPECT_EQ(table.code, 0) << table.output;
  expect_contains(table, "| additions=fix viscous |");
  expect_contains(table, "| additions=none |");
}

// A deck run by hand in the case's folder is the case's run once adopted; one whose outputs do not
// show the case's deck, whole, is refused by name.
TEST_F(WhatRan, ADeckRunByHandIsAdoptedAndReducesAsGranstacksRun) {
  ASSERT_EQ(granstack({"generate", "-o", path("hand").string(), "--blocks", "2"}).code, 0);
  ASSERT_EQ(granstack({"generate", "-o", path("ours").string(), "--blocks", "2"}).code, 0);
  ASSERT_EQ(granstack({"run", path("ours").string()}).code, 0);
  os::StartOptions o;
  o.cwd = path("hand");
  o.output = path("hand") / "screen.txt";
  ASSERT_TRUE(os::run_open_mpi_program({"liggghts", "-in", "in.stack"}, o).ok());
  auto r = granstack({"reduce", path("hand").string()});
  EXPECT_NE(r.code, 0);
  expect_contains(r, "the case has not been run by granstack, but its log.liggghts says LIGGGHTS ran its deck");
  expect_contains(r, "'granstack adopt " + path("hand").string() + "'");
  r = granstack({"status", path("hand").string()});
  expect_contains(r, "1 pending case(s) hold a log of LIGGGHTS run outside granstack");
  r = granstack({"adopt", path("hand").string()});
  ASSERT_EQ(r.code, 0) << r.output;
  expect_contains(r, "adopted  " + path("hand").string());
  EXPECT_EQ(record(path("hand")).at("run_by"), "hand");
  r = granstack({"reduce", path("hand").string(), path("ours").string()});
  ASSERT_EQ(r.code, 0) << r.output;
  expect_contains(r, "liggghts (run by hand)");
  // Byte for byte the run granstack makes: the same physics, the same numbers.
  const auto a = nlohmann::json::parse(read_bytes(path("hand") / "reduce" / "summary.json"));
  const auto b = nlohmann::json::parse(read_bytes(path("ours") / "reduce" / "summary.json"));
  EXPECT_EQ(a.at("output_fraction"), b.at("output_fraction"));
  EXPECT_EQ(read_bytes(path("hand") / "dumps" / "dump.txt"), read_bytes(path("ours") / "dumps" / "dump.txt"));
  r = granstack({"status", path("hand").string()});
  EXPECT_EQ(r.code, 0) << r.output;
  expect_contains(r, "1 done");
  // A second adoption is refused without --force; a log cut short, or a dump from another case, never adopted.
  r = granstack({"adopt", path("hand").string()});
  expect_contains(r, "skipped");
  auto log = read_bytes(path("hand") / "log.liggghts");
  std::ofstream(path("hand") / "log.liggghts") << log.substr(0, log.find("Loop time"));
  r = granstack({"adopt", "--force", path("hand").string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "the run did not finish");
  std::ofstream(path("hand") / "log.liggghts") << log;
  fs::copy_file(path("ours") / "dumps" / "dump.txt", path("hand") / "dumps" / "dump.txt", fs::copy_options::overwrite_existing);
  ASSERT_EQ(granstack({"generate", "--force", "-o", path("ours").string(), "--blocks", "1"}).code, 0);
  ASSERT_EQ(granstack({"run", path("ours").string()}).code, 0);
  fs::copy_file(path("ours") / "dumps" / "dump.txt", path("hand") / "dumps" / "dump.txt", fs::copy_options::overwrite_existing);
  r = granstack({"adopt", "--force", path("hand").string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "dump.txt");
}

}  // namespace

namespace {

// Processes whose command line is exactly `words` (the probe a fake LAMMPS leaves behind).
int processes_running(const std::string& words) {
  int found = 0;
  for (const auto& p : fs::directory_iterator("/proc")) {
    std::ifstream in(p.path() / "cmdline", std::ios::binary);
    std::string cmd((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::replace(cmd.begin(), cmd.end(), '\0', ' ');
    found += cmd == words + " " ? 1 : 0;
  }
  return found;
}

// N6: a LAMMPS whose '-h' never returns holds neither run nor validate: the probe is killed after
// its time (GRANSTACK_PROBE_SECONDS), or at once when granstack is asked to stop, and nothing it
// started is left.
TEST_F(WhatRan, AProbeThatNeverAnswersIsKilledAndSaid) {
  const auto fake = path("lmp");
  std::ofstream(fake) << "#!/bin/sh\nexec sleep 987\n";
  fs::permissions(fake, fs::perms::owner_all);
  ASSERT_EQ(granstack({"generate", "-o", path("c").string(), "--blocks", "1"}).code, 0);
  environment_ = {"GRANSTACK_PROBE_SECONDS=1"};
  auto t0 = std::chrono::steady_clock::now();
  auto r = granstack({"run", "--engine", "lammps", "--lammps", fake.string(), path("c").string()}, {}, 30);
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "'" + fake.string() + " -h', asked which LAMMPS it is, did not end within 1 s (it was killed");
  r = granstack({"validate", "--engines", "lammps,refsim", "--lammps", fake.string(), path("c").string()}, {}, 30);
  EXPECT_NE(r.code, 0) << r.output;
  expect_contains(r, "did not end within 1 s");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 20.0);
  EXPECT_EQ(processes_running("sleep 987"), 0);
  // Without a bound of its own (20 s), a stop signal ends it at once.
  environment_.clear();
  t0 = std::chrono::steady_clock::now();
  const auto child = start({"run", "--engine", "lammps", "--lammps", fake.string(), path("c").string()});
  ASSERT_TRUE(eventually([&] { return processes_running("sleep 987") == 1; }, 10));
  ::kill(child.pid, SIGINT);
  r = finish(child, 10);
  EXPECT_EQ(r.code, 130) << r.output;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
  EXPECT_EQ(processes_running("sleep 987"), 0);
  EXPECT_FALSE(fs::exists(path("c") / "run.json"));
}

}  // namespace
