// granstack submit and status on a real one-node SLURM (scripts/slurm-local.sh, started by the
// ctest fixture slurm.start; SLURM_CONF points at it). Every check reads the cases' output
// files, never only the jobs' states: a misconfigured node reports COMPLETED with no output.
#include "../support/program.hpp"

#include <granstack/os/process.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

namespace fs = std::filesystem;
using namespace granstack;

namespace {

using Result = test::ProgramResult;
using test::read_bytes;

fs::path work(const std::string& name) {
  const auto d = fs::path(GRANSTACK_TEST_WORKDIR) / "slurm_tests" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

Result run(std::vector<std::string> argv, const std::vector<std::string>& env = {}) {
  return test::run_program(std::move(argv), fs::path(GRANSTACK_TEST_WORKDIR) / "slurm_tests" / "last_output.txt", env);
}

Result granstack(std::vector<std::string> args, const std::vector<std::string>& env = {}) {
  args.insert(args.begin(), GRANSTACK_EXE);
  return run(args, env);
}

std::vector<std::string> job_ids(const std::string& submit_output) {
  std::vector<std::string> ids;
  const std::regex job("job ([0-9]+)");
  for (auto it = std::sregex_iterator(submit_output.begin(), submit_output.end(), job); it != std::sregex_iterator(); ++it) {
    ids.push_back((*it)[1]);
  }
  return ids;
}

// Waits until none of the jobs is in the queue.
bool wait_for(const std::vector<std::string>& ids, double seconds = 120) {
  std::string list;
  for (const auto& id : ids) list += (list.empty() ? "" : ",") + id;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    const auto q = run({"squeue", "-h", "-j", list});
    if (q.code == 0 && q.output.find_first_not_of(" \n") == std::string::npos) return true;
    if (q.code != 0 && q.output.find("Invalid job id") != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  return false;
}

nlohmann::json run_record(const fs::path& c) { return nlohmann::json::parse(read_bytes(c / "run.json")); }

// The case ran to its end: run.json says done and the dump holds the final frame.
void expect_done_with_output(const fs::path& c) {
  ASSERT_TRUE(fs::exists(c / "run.json")) << c;
  EXPECT_EQ(run_record(c).value("status", ""), "done") << c;
  const auto steps = nlohmann::json::parse(read_bytes(c / "manifest.json")).at("derived").at("steps").get<long>();
  EXPECT_NE(read_bytes(c / "dumps" / "dump.txt").find("ITEM: TIMESTEP\n" + std::to_string(steps) + "\n"), std::string::npos) << c;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (auto p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

TEST(Slurm, AGatheredSweepGivesTheLocalTableByteForByte) {
  const auto d = work("gather");
  for (const auto* name : {"cluster", "local"}) {
    ASSERT_EQ(granstack({"generate", "-o", (d / name).string(), "--blocks", "1,2,3", "--restitution", "1,0.9"}).code, 0);
  }
  const auto s = granstack({"submit", (d / "cluster").string(), "--cases-per-task", "2", "--gather"});
  ASSERT_EQ(s.code, 0) << s.output;
  EXPECT_NE(s.output.find("submitted 6 cases in 3 tasks of up to 2 (1 array"), std::string::npos) << s.output;
  const auto ids = job_ids(s.output);
  ASSERT_EQ(ids.size(), 2u) << s.output;  // the array and the gather job
  ASSERT_TRUE(wait_for(ids));
  for (const auto& e : fs::directory_iterator(d / "cluster")) {
    if (fs::exists(e.path() / "manifest.json")) expect_done_with_output(e.path());
  }
  ASSERT_EQ(granstack({"run", "-j", "2", (d / "local").string()}).code, 0);
  ASSERT_EQ(granstack({"table", (d / "local").string(), "-o", (d / "local_table").string()}).code, 0);
  const auto gathered = d / "cluster" / "slurm" / "submit-1" / "table";
  ASSERT_TRUE(fs::exists(gathered / "table.md")) << read_bytes(d / "cluster" / "slurm" / "submit-1" / "gather.out");
  EXPECT_EQ(read_bytes(gathered / "table.md"), read_bytes(d / "local_table" / "table.md"));
  EXPECT_EQ(read_bytes(gathered / "fits.csv"), read_bytes(d / "local_table" / "fits.csv"));
  // table.csv names each case's directory; with that the only difference, the bytes agree.
  EXPECT_EQ(replace_all(read_bytes(gathered / "table.csv"), (d / "cluster").string(), "SWEEP"),
            replace_all(read_bytes(d / "local_table" / "table.csv"), (d / "local").string(), "SWEEP"));
  const auto st = granstack({"status", (d / "cluster").string()});
  EXPECT_EQ(st.code, 0) << st.output;
  EXPECT_NE(st.output.find("6 cases: 6 done, 0 failed, 0 running, 0 interrupted, 0 pending"), std::string::npos) << st.output;
}

TEST(Slurm, ACancelledTaskIsInterruptedAndAResubmitRunsOnlyWhatDidNotFinish) {
  const auto d = work("cancel");
  const auto sweep = d / "sweep";
  // Three cases of several seconds each, one task at a time.
  ASSERT_EQ(granstack({"generate", "-o", sweep.string(), "--blocks", "3", "--restitution", "1,0.9,0.8", "--dt", "4e-9"}).code, 0);
  const auto s = granstack({"submit", sweep.string(), "--max-parallel", "1"});
  ASSERT_EQ(s.code, 0) << s.output;
  const auto ids = job_ids(s.output);
  ASSERT_EQ(ids.size(), 1u);
  // Cancel task 0 once its LIGGGHTS is at work.
  const auto first = sweep / "e1";
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until && read_bytes(first / "liggghts.out").find("    Step    Atoms") == std::string::npos) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(run({"scancel", ids[0] + "_0"}).code, 0);
  ASSERT_TRUE(wait_for(ids));
  EXPECT_EQ(run_record(first).value("status", ""), "interrupted");
  expect_done_with_output(sweep / "e0.9");
  expect_done_with_output(sweep / "e0.8");
  auto st = granstack({"status", sweep.string()});
  EXPECT_EQ(st.code, 1) << st.output;
  EXPECT_NE(st.output.find("3 cases: 2 done, 0 failed, 0 running, 1 interrupted, 0 pending"), std::string::npos) << st.output;
  EXPECT_NE(st.output.find("interrupted  " + first.string()), std::string::npos) << st.output;
  const auto before = fs::last_write_time(sweep / "e0.9" / "run.json");
  const auto again = granstack({"submit", sweep.string()});
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_NE(again.output.find("submitted 1 cases"), std::string::npos) << again.output;
  ASSERT_TRUE(wait_for(job_ids(again.output)));
  expect_done_with_output(first);
  EXPECT_EQ(fs::last_write_time(sweep / "e0.9" / "run.json"), before);  // not run again
  st = granstack({"status", sweep.string()});
  EXPECT_NE(st.output.find("3 cases: 3 done"), std::string::npos) << st.output;
}

TEST(Slurm, TwoMpiRanksInsideAnAllocationGiveWhatOneRankGives) {
  const auto d = work("mpi");
  for (const auto* name : {"two", "one"}) ASSERT_EQ(granstack({"generate", "-o", (d / name).string()}).code, 0);
  const auto s = granstack({"submit", (d / "two").string(), "--np", "2"});
  ASSERT_EQ(s.code, 0) << s.output;
  ASSERT_TRUE(wait_for(job_ids(s.output)));
  expect_done_with_output(d / "two");
  EXPECT_EQ(run_record(d / "two").value("ranks", 0), 2);
  ASSERT_EQ(granstack({"run", (d / "one").string()}).code, 0);
  auto fraction = [&](const char* name) {
    const auto r = granstack({"reduce", "--json", (d / name).string()});
    return nlohmann::json::parse(r.output.substr(r.output.find('{'))).at("output_fraction").get<double>();
  };
  // Two ranks sum forces in another order: round-off, as tests/liggghts measures (1e-9).
  EXPECT_NEAR(fraction("two"), fraction("one"), 1e-9 * fraction("one"));
}

TEST(Slurm, MissingSbatchAndAnUnknownPartitionAreSaidAndNothingIsSubmitted) {
  const auto d = work("bad");
  ASSERT_EQ(granstack({"generate", "-o", (d / "case").string()}).code, 0);
  auto r = granstack({"submit", (d / "case").string()}, {"PATH=/nonexistent"});
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("sbatch is not on PATH: install SLURM's client commands (Debian package slurm-client)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(d / "case" / "slurm"));
  r = granstack({"submit", (d / "case").string(), "--partition", "nosuch"});
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("sbatch refused"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("invalid partition"), std::string::npos) << r.output;  // SLURM's own words
  EXPECT_FALSE(fs::exists(d / "case" / "run.json"));
}

}  // namespace
