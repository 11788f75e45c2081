// Messages that say what happened and what to do (issue #65 item 7: N7-N14, M7-M19): each test
// is what a careful new user tried, on the real program, and the words it now answers with; each
// failed on the commit before.
#include "../support/granstack_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

using namespace granstack;
using namespace granstack::test;

namespace {

class Messages : public GranstackTest {
 protected:
  // A one-block case run on refsim.
  fs::path ran(const std::string& name) {
    generate_and_run(name, {"--blocks", "1"});
    return path(name);
  }
  static void set_status(const fs::path& c, const std::string& status) {
    auto j = nlohmann::json::parse(read_bytes(c / "run.json"));
    j["status"] = status;
    j["error"] = "the run's own failure";
    std::ofstream(c / "run.json") << j.dump(2);
  }
};

// N8: a template that runs the case twice is said to, not to have run too few steps; a template
// without the series is refused naming it.
TEST_F(Messages, ADeckThatRunsTwiceOrWritesNoSeriesIsSaidSo) {
  auto text = read_bytes(fs::path(GRANSTACK_SOURCE_DIR) / "templates/in.granstack.tmpl");
  std::ofstream(path("twice.tmpl")) << text << "{{run}}\n";
  ASSERT_EQ(granstack({"generate", "-o", "twice", "--blocks", "1", "--template", "twice.tmpl"}).code, 0);
  auto r = granstack({"run", "twice"});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "times: the case runs its");
  EXPECT_EQ(r.output.find("ended without finishing"), std::string::npos) << r.output;
  text.replace(text.find("{{energy_series}}"), 17, "");
  std::ofstream(path("noseries.tmpl")) << text;
  ASSERT_EQ(granstack({"generate", "-o", "noseries", "--blocks", "1", "--template", "noseries.tmpl"}).code, 0);
  r = granstack({"run", "noseries"});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "the deck never ran 'compute kt1 block1 ke', which granstack's deck runs for this case");
  EXPECT_EQ(status_of(path("noseries")), "failed");
}

// M7, M12: export and table of a case whose run failed or goes on say so, not that a digest is
// missing, and not in reduce's words.
TEST_F(Messages, ExportAndTableOfARunNotFinishedSayWhy) {
  const auto c = ran("c");
  set_status(c, "failed");
  auto r = granstack({"export", c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "the run failed (the run's own failure)");
  EXPECT_FALSE(fs::exists(c / "paraview"));
  set_status(c, "running");
  r = granstack({"table", c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "its run was killed before it finished");
  EXPECT_EQ(r.output.find("reduce it"), std::string::npos) << r.output;
  r = granstack({"export", c.string()});
  expect_contains(r, "its run was killed before it finished");
}

// N14: an option the command does not have is named, not taken for a case path.
TEST_F(Messages, AnOptionTheCommandLacksIsNamed) {
  const auto c = ran("c");
  auto r = granstack({"reduce", "--engine", "liggghts", c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "'--engine' is not an option of 'granstack reduce' (its options: --help, --json, --threads");
  EXPECT_EQ(r.output.find("Directory does not exist"), std::string::npos) << r.output;
  r = granstack({"design", "status", "--np", "2", c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "'--np' is not an option of 'granstack design status'");
  // Values that look like options stay values.
  r = granstack({"generate", "-o", "g", "--blocks", "1", "--dt", "-1e-8"});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "dt");
  EXPECT_EQ(r.output.find("is not an option"), std::string::npos) << r.output;
}

// M15, N10: a dump compressed by a program granstack does not read, and a named pipe where the
// dump was, are said as what they are.
TEST_F(Messages, ADumpItCannotReadIsSaidAsWhatItIs) {
  const auto c = ran("c");
  const auto dump = c / "dumps" / "dump.txt";
  ASSERT_TRUE(fs::exists(dump));
  fs::rename(dump, dump.string() + ".xz");
  auto r = granstack({"reduce", c.string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "dump.txt.xz is there, compressed with xz, which granstack does not read");
  r = granstack({"status", c.string()});
  expect_contains(r, "compressed with xz");
  fs::remove(dump.string() + ".xz");
  ASSERT_EQ(::mkfifo(dump.c_str(), 0644), 0);
  r = granstack({"status", c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "is a FIFO (named pipe): granstack reads only regular files");
}

// M16, M17: directories that are not cases are named for what they are; a damaged sweep index
// says so in words.
TEST_F(Messages, WhatIsNotACaseIsNamedForWhatItIs) {
  fs::create_directories(path("odd"));
  std::ofstream(path("odd") / "manifest.json") << "{}";
  auto r = granstack({"status", path("odd").string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "1 damaged");
  expect_contains(r, "not a granstack manifest");
  ASSERT_EQ(granstack({"generate", "-o", "sweep", "--blocks", "1,2", "--rows", "3"}).code, 0);
  r = granstack({"decompose", path("sweep").string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "is a sweep's directory (granstack generate of several cases): name one of its cases, e.g. ");
  std::ofstream(path("sweep") / "sweep.json") << "{\"cases\": [";
  r = granstack({"run", path("sweep").string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "sweep.json: is damaged (");
  EXPECT_EQ(r.output.find("json.exception"), std::string::npos) << r.output;
}

// M9: more frames appended to a dump are said to be appended, not missing.
TEST_F(Messages, AFrameAppendedToADumpIsSaidToBeAppended) {
  ASSERT_EQ(granstack({"generate", "-o", "c", "--blocks", "1", "--dump-format", "text"}).code, 0);
  ASSERT_EQ(granstack({"run", "--engine", "refsim", "c"}).code, 0);
  const auto dump = path("c") / "dumps" / "dump.txt";
  auto text = read_bytes(dump);
  auto last = text.substr(text.rfind("ITEM: TIMESTEP"));
  const auto step = std::stol(last.substr(15, last.find('\n', 15) - 15));
  last.replace(15, last.find('\n', 15) - 15, std::to_string(step + 5));
  std::ofstream(dump, std::ios::app) << last;
  const auto r = granstack({"reduce", "c"});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "comes after the run's last frame");
  expect_contains(r, "more were added to its dump");
}

// N11: submit asks SLURM for no ranks or nodes refsim would not use (--np and --nodes are the
// options of the engines that run an MPI program).
TEST_F(Messages, SubmitOfRefsimOnRanksIsRefused) {
  const auto c = ran("c");
  const auto r = granstack({"submit", "--engine", "refsim", "--np", "4", "--dry-run", c.string()});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "--np is for liggghts or lammps and none runs here (refsim)");
  const auto nodes = granstack({"submit", "--engine", "refsim", "--nodes", "2", "--np", "2", "--dry-run", c.string()});
  EXPECT_EQ(nodes.code, 2) << nodes.output;
  expect_contains(nodes, "is for liggghts or lammps and none runs here (refsim)");
}

// A protected plate on a mount runs on LIGGGHTS (a mesh moved with an atom of the plate's mass)
// and refsim; LAMMPS, whose deck has a rigid wall, refuses it in run and validate before touching
// anything, naming the engines that carry it. validate takes it on its default two.
TEST_F(Messages, APlateCaseIsRefusedWhereTheEngineHasNoPlate) {
  ASSERT_EQ(granstack({"generate", "-o", "p", "--blocks", "1", "--rows", "2", "--bottom", "wall", "--plate-mass", "0.01"}).code, 0);
  const auto r = granstack({"run", "--engine", "lammps", "p"});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "plate_mass: a protected plate on a mount runs on liggghts or refsim (--engine liggghts)");
  auto v = granstack({"validate", "--engines", "lammps,refsim", "p"});
  EXPECT_NE(v.code, 0) << v.output;
  expect_contains(v, "lammps cannot run it: plate_mass");
  EXPECT_FALSE(fs::exists(path("p") / "validate"));
  EXPECT_FALSE(fs::exists(path("p") / "run.json"));
  v = granstack({"validate", "p"});
  EXPECT_EQ(v.code, 0) << v.output;
  expect_contains(v, "agree: largest difference");
}

// M18: an interrupted validate says it was stopped, before comparing.
TEST_F(Messages, AnInterruptedValidateSaysSo) {
  ASSERT_EQ(granstack({"generate", "-o", "big", "--blocks", "4", "--rows", "16"}).code, 0);
  const auto child = start({"validate", "big"});
  ASSERT_TRUE(eventually([&] { return fs::exists(path("big") / "validate" / "liggghts" / "log.liggghts"); }, 30));
  ::kill(child.pid, SIGINT);
  const auto r = finish(child, 60);
  EXPECT_EQ(r.code, 130) << r.output;
  expect_contains(r, "validate: stopped by signal 2 before the engines were compared");
}

// M10, M11, M13, N7: the design search's numbers and settings.
TEST_F(Messages, DesignRunsSettingsSayWhatTheyMean) {
  const auto small = small_space();
  auto r = granstack({"design", "run", "small.toml", "-o", "d", "--generations", "1.5"});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "'1.5' is not a whole number");
  r = granstack({"design", "run", "small.toml", "-o", "d", "--generations", "1", "--no-report"});
  ASSERT_EQ(r.code, 0) << r.output;
  r = granstack({"design", "run", "small.toml", "-o", "d", "--generations", "0", "--no-report"});
  EXPECT_EQ(r.code, 0) << r.output;
  expect_contains(r, "the store is at generation 1 already, beyond the 0 asked for: nothing to run");
  // M11: a store whose first write did not finish (a full disk as its search began: here, empty)
  // is said to be so, and begun anew by the run its message advises.
  fs::create_directories(path("full"));
  std::ofstream(path("full") / "design.sqlite").close();
  r = granstack({"design", "status", "full"});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "its search's first write did not finish");
  EXPECT_EQ(r.output.find("not a granstack design store"), std::string::npos) << r.output;
  r = granstack({"design", "run", "small.toml", "-o", "full", "--max-designs", "2", "--no-report"});
  EXPECT_EQ(r.code, 0) << r.output;
  auto text = small;
  text.replace(text.find("objectives = ["), 14, "objectives = \"peak_wall_force\"\nx = [");
  std::ofstream(path("str.toml")) << text;
  r = granstack({"design", "run", "str.toml", "-o", "e"});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "objectives = 'peak_wall_force': a list of two or more of");
  EXPECT_EQ(r.output.find("objectives is missing"), std::string::npos) << r.output;
}

// N12: the other reproduction named by --against ran none of this one's statements: said, not
// counted as "0 of N change".
TEST_F(Messages, AnAgainstThatComparedNothingSaysSo) {
  auto r = granstack({"reproduce", "--quick", "eq3", "--engine", "refsim", "-o", "eq3"});
  ASSERT_EQ(r.code, 0) << r.output;
  r = granstack({"reproduce", "--quick", "scale", "--engine", "liggghts", "--against", "eq3", "-o", "scale", "-j", "2"});
  ASSERT_EQ(r.code, 0) << r.output;
  expect_contains(r, "none of the");
  expect_contains(r, "statements was run there (its report holds other experiments): nothing was compared");
  // reproduce's options for an engine that does not run are refused, as run's are (N13).
  r = granstack({"reproduce", "--quick", "eq3", "-o", "eq3", "--lammps", "/bin/false"});
  EXPECT_EQ(r.code, 2) << r.output;
  expect_contains(r, "--lammps is for lammps and none runs here (refsim)");
}

}  // namespace
