// Trust (issue #31): nothing is lost outside what a command names, and nothing is reduced under
// a case's labels that its own run did not write. Each test is a user's sequence of commands on
// the real program (refsim runs the cases: the faults lie in granstack's file handling, and the
// same code serves LIGGGHTS's runs), and each fails on the commit before its fix.
#include "../support/granstack_test.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <sys/statvfs.h>
#include <unistd.h>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace granstack;
using namespace granstack::test;

namespace {

class Trust : public test::GranstackTest {
 protected:
  double output_fraction(const std::string& name) {
    const auto r = granstack({"reduce", name});
    EXPECT_EQ(r.code, 0) << r.output;
    return nlohmann::json::parse(read_bytes(path(name) / "reduce" / "summary.json")).at("output_fraction").get<double>();
  }
};

// A '*' or '%' in a case's path is part of its name, never a dump pattern: refsim writes into
// the case it was given, and the finished case beside it keeps its dump.
TEST_F(Trust, WildcardsInACasePathAreCharacters) {
  generate_and_run("glob0", {"--blocks", "2"});
  const auto before = read_bytes(path("glob0") / "dumps" / "dump.txt");
  generate_and_run("glob*", {"--blocks", "1"});
  auto r = granstack({"run", "--engine", "refsim", "--force", "glob*"});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(read_bytes(path("glob0") / "dumps" / "dump.txt"), before) << "glob0's dump was written over";
  EXPECT_TRUE(fs::is_regular_file(path("glob*") / "dumps" / "dump.txt"));
  // Each reduces to its own physics: one steel block passes 0.3388 of E_in, two 0.1096.
  EXPECT_NEAR(output_fraction("glob*"), 0.33884, 1e-5);
  EXPECT_NEAR(output_fraction("glob0"), 0.10963, 1e-5);
  // A reproduction and a validation in such paths.
  r = granstack({"reproduce", "fig3", "--quick", "--engine", "refsim", "-j", "2", "-o", "rp%d*"});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::is_regular_file(path("rp%d*") / "fig3" / "nb1_e1" / "dumps" / "dump.bin"));
  r = granstack({"validate", "./glob*"});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(path("glob0") / "validate")) << "validate './glob*' wrote into glob0";
}

// generate --force replaces only a case or a sweep: a reproduction (with a user's notes and
// folder in it) is another command's, and is refused whole.
TEST_F(Trust, GenerateNeverReplacesAnotherCommandsDirectory) {
  auto r = granstack({"reproduce", "fig3", "--quick", "--engine", "refsim", "-j", "2", "-o", "paper"});
  ASSERT_EQ(r.code, 0) << r.output;
  std::ofstream(path("paper") / "NOTES.md") << "my notes";
  fs::create_directories(path("paper") / "mine");
  r = granstack({"generate", "-o", "paper", "--force", "--blocks", "1"});
  EXPECT_EQ(r.code, 3) << r.output;
  expect_contains(r, "was made by granstack reproduce, not by granstack generate");
  EXPECT_EQ(read_bytes(path("paper") / "NOTES.md"), "my notes");
  EXPECT_TRUE(fs::is_directory(path("paper") / "mine"));
  EXPECT_TRUE(fs::is_regular_file(path("paper") / "report.md"));
  // A table's folder is not a plot's to replace files in, nor a case's.
  generate_and_run("c", {"--blocks", "1"});
  r = granstack({"table", "c", "-o", "results"});
  ASSERT_EQ(r.code, 0) << r.output;
  r = granstack({"generate", "-o", "results", "--force", "--blocks", "1"});
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_TRUE(fs::is_regular_file(path("results") / "table.md"));
}

// run --force with dumps/ a link to scratch space: the earlier dump is set aside and replaced on
// scratch, through the case's own path; nothing outside dumps/ is touched.
TEST_F(Trust, RunAgainThroughALinkedDumpFolderTouchesNothingElse) {
  generate_and_run("case", {"--blocks", "1"});
  fs::create_directories(path("scratch"));
  fs::rename(path("case") / "dumps" / "dump.txt", path("scratch") / "dump.txt");
  fs::remove(path("case") / "dumps");
  fs::create_directory_symlink("../scratch", path("case") / "dumps");
  // Where a resolved relative path would have sent the set-aside dump.
  fs::create_directories(path("case") / "scratch");
  std::ofstream(path("case") / "scratch" / "dump.txt") << "a user's file";
  std::ofstream(path("scratch") / "notes.txt") << "my notes";
  const auto r = granstack({"run", "--engine", "refsim", "--force", "."}, path("case"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(read_bytes(path("case") / "scratch" / "dump.txt"), "a user's file");
  EXPECT_EQ(read_bytes(path("scratch") / "notes.txt"), "my notes");
  EXPECT_TRUE(fs::is_symlink(path("case") / "dumps"));
  EXPECT_FALSE(fs::exists(path("scratch") / ".granstack-earlier-run"));
  std::vector<std::string> in_scratch;
  for (const auto& e : fs::directory_iterator(path("scratch"))) in_scratch.push_back(e.path().filename().string());
  std::sort(in_scratch.begin(), in_scratch.end());
  EXPECT_EQ(in_scratch, (std::vector<std::string>{"dump.txt", "notes.txt"}));
  EXPECT_NEAR(output_fraction("case"), 0.33884, 1e-5);
}

// reduce digests a plain text dump from the pieces its threads parse: one digit changed in the
// middle of the dump (the file's size and its frames' shape unchanged, every number still a
// number) is refused as the whole file's digest is, before any result is written.
TEST_F(Trust, ADigitChangedInTheDumpIsCaughtWhileItIsRead) {
  generate_and_run("c", {"--blocks", "2"});
  const auto dump = path("c") / "dumps" / "dump.txt";
  auto text = read_bytes(dump);
  const auto at = text.find("ITEM: ATOMS", text.size() / 2);
  ASSERT_NE(at, std::string::npos);
  // The last digit of the first long number on the atom lines after it (a position's 17th digit:
  // a change far below any check on the physics).
  std::size_t start = text.find('\n', at) + 1, end = start;
  for (;; start = end + 1) {
    end = text.find_first_of(" \n", start);
    if (end - start >= 15) break;
  }
  const std::size_t digit = end - 1;
  ASSERT_TRUE(std::isdigit(static_cast<unsigned char>(text[digit])));
  text[digit] = text[digit] == '9' ? '8' : static_cast<char>(text[digit] + 1);
  std::ofstream(dump, std::ios::binary) << text;
  const auto r = granstack({"reduce", "c"});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "dump.txt is not what its run wrote (its XXH3-128 digest differs from run.json's");
  EXPECT_FALSE(fs::exists(path("c") / "reduce" / "summary.json"));
}

// Outputs copied in from a case with other physics are refused, not reduced under this case's
// labels (e = 1's dumps in an e = 0.9 case gave 0.1096, not 0.0583); status says so, as it does
// for a run.json copied from another case. A dump compressed after the run is still the run's.
TEST_F(Trust, OutputsFromAnotherCaseAreNeverReducedAsThisOne) {
  generate_and_run("e1", {"--blocks", "2"});
  generate_and_run("e09", {"--blocks", "2", "--restitution", "0.9"});
  EXPECT_NEAR(output_fraction("e09"), 0.05828, 1e-5);
  fs::copy_file(path("e1") / "dumps" / "dump.txt", path("e09") / "dumps" / "dump.txt", fs::copy_options::overwrite_existing);
  fs::copy_file(path("e1") / "ke_series.txt", path("e09") / "ke_series.txt", fs::copy_options::overwrite_existing);
  auto r = granstack({"reduce", "e09"});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "is not what its run wrote");
  r = granstack({"export", "e09"});
  EXPECT_EQ(r.code, 4) << r.output;
  EXPECT_FALSE(fs::exists(path("e09") / "paraview"));
  r = granstack({"status", "e1", "e09"});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "1 done");
  expect_contains(r, "1 changed since their run");
  // A run.json copied without its outputs, from another case.
  auto g = granstack({"generate", "-o", "c3", "--blocks", "1"});
  ASSERT_EQ(g.code, 0) << g.output;
  fs::copy_file(path("e1") / "run.json", path("c3") / "run.json");
  r = granstack({"status", "c3"});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "is the record of another case ('e1'");
  r = granstack({"reduce", "c3"});
  EXPECT_EQ(r.code, 4) << r.output;
  // A series removed after the run.
  fs::remove(path("e1") / "ke_series.txt");
  r = granstack({"status", "e1"});
  expect_contains(r, "which its run wrote, is missing");
  // Run again, then compressed by the user: the same content, the same result.
  r = granstack({"run", "--engine", "refsim", "--force", "e09"});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto gz = granstack::os::run({"gzip", (path("e09") / "dumps" / "dump.txt").string()}, {});
  ASSERT_EQ(gz.code, 0);
  EXPECT_NEAR(output_fraction("e09"), 0.05828, 1e-5);
  r = granstack({"status", "e09"});
  EXPECT_EQ(r.code, 0) << r.output;
}

// Concurrent generate --force into one directory with different specs: each writes its case
// whole and reports what it wrote (the 1-block case's 1080 steps are never called 6.8e-5 s of
// another), and the case left is one of them, whole.
TEST_F(Trust, ConcurrentGeneratesEachReportWhatTheyWrote) {
  std::map<std::string, std::string> alone;  // blocks -> the line generate prints for it alone
  const std::regex wrote("wrote case \\S+ (\\([^)]*\\))");
  for (const std::string blocks : {"1", "2", "3", "4"}) {
    const auto r = granstack({"generate", "-o", "alone" + blocks, "--blocks", blocks});
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, wrote)) << r.output;
    alone[blocks] = m[1];
  }
  auto first = granstack({"generate", "-o", "X", "--blocks", "1"});
  ASSERT_EQ(first.code, 0) << first.output;
  for (int round = 0; round < 3; ++round) {
    std::vector<std::pair<std::string, os::Child>> children;
    for (const std::string blocks : {"1", "2", "3", "4"}) {
      children.emplace_back(blocks, start({"generate", "-o", "X", "--force", "--blocks", blocks}));
    }
    for (auto& [blocks, child] : children) {
      const auto r = finish(child);
      EXPECT_EQ(r.code, 0) << r.output;
      std::smatch m;
      ASSERT_TRUE(std::regex_search(r.output, m, wrote)) << r.output;
      EXPECT_EQ(m[1].str(), alone[blocks]) << "the generate of " << blocks << " block(s) reported another case";
    }
    const auto manifest = nlohmann::json::parse(read_bytes(path("X") / "manifest.json"));
    const auto blocks = std::to_string(manifest.at("spec").at("blocks").get<int>());
    const auto solo = nlohmann::json::parse(read_bytes(path("alone" + blocks) / "manifest.json"));
    EXPECT_EQ(manifest.at("derived"), solo.at("derived"));
    EXPECT_EQ(manifest.at("spec"), solo.at("spec"));
  }
}

// A full disk leaves nothing half-written that blocks the next try: table -o writes its three
// files all or none (table.md stayed alone behind), and validate removes its half-made copy (its
// rerun was refused as "not made by granstack", exit 3).
TEST_F(Trust, AFullDiskLeavesNothingHalfWritten) {
  const auto disk = path("disk");
  const SmallDisk mounted(disk, "4m");
  if (!mounted.mounted()) GTEST_SKIP() << "a small file system to fill needs root and mount(2) (a tmpfs of 4 MB)";
  generate_and_run("case", {"--blocks", "1"});
  const auto c = disk / "case";
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "1"}).code, 0);
  // Fill the disk but two pages (tmpfs counts 4096-byte pages): the marker takes one, table.md's
  // temporary the other, and table.csv finds none.
  const auto fill = [&] {
    struct statvfs st {};
    ASSERT_EQ(::statvfs(disk.c_str(), &st), 0);
    const auto free_bytes = static_cast<std::size_t>(st.f_bavail) * st.f_frsize;
    std::ofstream(disk / "fill", std::ios::binary) << std::string(free_bytes - 2 * 4096, 'x');
  };
  fill();
  auto r = granstack({"table", "case", "-o", (disk / "table").string()});
  EXPECT_EQ(r.code, 7) << r.output;
  for (const char* f : {"table.md", "table.csv", "fits.csv", "table.md.tmp"}) {
    EXPECT_FALSE(fs::exists(disk / "table" / f)) << f << " was left behind";
  }
  r = granstack({"validate", c.string()});
  EXPECT_NE(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(c / "validate" / "liggghts")) << "validate left its half-made copy";
  fs::remove(disk / "fill");
  r = granstack({"validate", c.string()});
  EXPECT_EQ(r.code, 0) << r.output;
  r = granstack({"table", "case", "-o", (disk / "table").string()});
  EXPECT_EQ(r.code, 0) << r.output;
}

// The suite's own work (tests/support/scratch.hpp): a test that fails keeps its directory for
// its diagnosis, one that passes leaves none; seen on the two tests of a program of their own
// (tests/support/scratch_probe.cpp), one failing on purpose.
TEST(Scratch, AFailedTestKeepsItsDirectoryAndAPassedOneLeavesNone) {
  const auto work = fs::path(GRANSTACK_TEST_WORKDIR);
  const auto one = [&](const std::string& name) {
    fs::remove_all(work / ("Probe_" + name));
    os::StartOptions o;
    o.output = scratch(work / ("Scratch_" + name + ".out"));
    return os::run({"/usr/bin/env", "-u", "GRANSTACK_KEEP_TEST_WORK", GRANSTACK_SCRATCH_PROBE, "--gtest_filter=Probe." + name}, o)
        .code;
  };
  EXPECT_EQ(one("WritesAndFails"), 1);
  EXPECT_EQ(read_bytes(work / "Probe_WritesAndFails" / "evidence"), "what the failure left");
  fs::remove_all(work / "Probe_WritesAndFails");
  EXPECT_EQ(one("WritesAndPasses"), 0);
  EXPECT_FALSE(fs::exists(work / "Probe_WritesAndPasses"));
}

}  // namespace
