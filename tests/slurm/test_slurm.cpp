// granstack submit and status on a real one-node SLURM (scripts/slurm-local.sh, started by the
// ctest fixture slurm.start; SLURM_CONF points at it). Every check reads the cases' output
// files, never only the jobs' states: a misconfigured node reports COMPLETED with no output.
#include "../support/program.hpp"
#include "../support/scratch.hpp"

#include <granstack/os/process.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using namespace granstack;

namespace {

using Result = test::ProgramResult;
using test::read_bytes;

fs::path work(const std::string& name) {
  const auto d = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / "slurm_tests" / name);
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

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
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

// Three cases of several seconds each in SWEEP, submitted one task at a time; the job ids.
std::vector<std::string> submit_three_slow_cases(const fs::path& sweep) {
  EXPECT_EQ(granstack({"generate", "-o", sweep.string(), "--blocks", "3", "--restitution", "1,0.9,0.8", "--dt", "4e-9"}).code, 0);
  const auto s = granstack({"submit", sweep.string(), "--max-parallel", "1"});
  EXPECT_EQ(s.code, 0) << s.output;
  return job_ids(s.output);
}

// Waits (at most a minute) until the case's LIGGGHTS is stepping.
void wait_until_stepping(const fs::path& c) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until && read_bytes(c / "liggghts.out").find("    Step    Atoms") == std::string::npos) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

// The lines of the test cluster's controller log that name job ID (for failure messages).
std::string controller_log_of(const std::string& id) {
  std::istringstream log(read_bytes(fs::path(std::getenv("SLURM_CONF")).parent_path() / "log" / "slurmctld.log"));
  std::string out;
  for (std::string line; std::getline(log, line);) {
    if (line.find("JobId=" + id) != std::string::npos) out += line + "\n";
  }
  return out;
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
  const auto ids = submit_three_slow_cases(sweep);
  ASSERT_EQ(ids.size(), 1u);
  // Cancel task 0 once its LIGGGHTS is at work.
  const auto first = sweep / "e1";
  wait_until_stepping(first);
  ASSERT_EQ(run({"scancel", ids[0] + "_0"}).code, 0);
  ASSERT_TRUE(wait_for(ids));
  EXPECT_EQ(run_record(first).value("status", ""), "interrupted");
  expect_done_with_output(sweep / "e0.9");
  expect_done_with_output(sweep / "e0.8");
  auto st = granstack({"status", sweep.string()});
  EXPECT_EQ(st.code, 1) << st.output;
  EXPECT_NE(st.output.find("3 cases: 2 done, 0 failed, 0 running, 1 interrupted, 0 pending"), std::string::npos) << st.output;
  EXPECT_NE(st.output.find("interrupted  " + first.string()), std::string::npos) << st.output;
  // A cancel is told from a time limit (#26.11).
  EXPECT_NE(st.output.find("(SLURM: task " + ids[0] + "_0 CANCELLED)"), std::string::npos) << st.output;
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
  const auto s = granstack({"submit", (d / "two").string(), "--np", "2", "--nodes", "1"});
  ASSERT_EQ(s.code, 0) << s.output;
  ASSERT_TRUE(wait_for(job_ids(s.output)));
  expect_done_with_output(d / "two");
  const auto record = run_record(d / "two");
  EXPECT_EQ(record.value("ranks", 0), 2);
  // The script asks for the nodes; mpirun spread the ranks over the allocation it names, on the
  // grid granstack chose, and LIGGGHTS took that grid.
  EXPECT_NE(read_bytes(d / "two" / "slurm" / "submit-1" / "array-1.sbatch").find("#SBATCH --nodes=1\n#SBATCH --ntasks=2\n"),
            std::string::npos);
  EXPECT_FALSE(record.value("slurm_nodes", std::string()).empty()) << record.dump();
  EXPECT_EQ(record.at("decomposition").at("liggghts").at("grid"), record.at("decomposition").at("grid"));
  ASSERT_EQ(granstack({"run", (d / "one").string()}).code, 0);
  auto fraction = [&](const char* name) {
    const auto r = granstack({"reduce", "--json", (d / name).string()});
    return nlohmann::json::parse(r.output.substr(r.output.find('{'))).at("output_fraction").get<double>();
  };
  // Two ranks sum forces in another order: round-off, as tests/liggghts measures (1e-9).
  EXPECT_NEAR(fraction("two"), fraction("one"), 1e-9 * fraction("one"));
}

// The LAMMPS engine as an array task on two ranks: the task runs lmp through mpirun inside the
// allocation, and the case agrees with refsim by LAMMPS's rules as a local LAMMPS run does.
TEST(Slurm, ALammpsCaseRunsAsAnArrayTaskOnTwoRanks) {
  const auto d = work("lammps");
  const auto c = d / "damped";
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "2", "--rows", "4", "--restitution", "0.9"}).code, 0);
  const auto s = granstack({"submit", c.string(), "--engine", "lammps", "--np", "2", "--nodes", "1"});
  ASSERT_EQ(s.code, 0) << s.output;
  ASSERT_TRUE(wait_for(job_ids(s.output)));
  expect_done_with_output(c);
  const auto record = run_record(c);
  EXPECT_EQ(record.value("engine", ""), "lammps");
  EXPECT_EQ(record.value("ranks", 0), 2);
  EXPECT_NE(record.value("lammps_version", "").find("2021"), std::string::npos) << record.dump();
  const auto twin = d / "refsim";
  ASSERT_EQ(granstack({"generate", "-o", twin.string(), "--blocks", "2", "--rows", "4", "--restitution", "0.9"}).code, 0);
  ASSERT_EQ(granstack({"run", "--engine", "refsim", "--contact-rules", "lammps", twin.string()}).code, 0);
  auto fraction = [&](const fs::path& dir) {
    const auto r = granstack({"reduce", "--json", dir.string()});
    return nlohmann::json::parse(r.output.substr(r.output.find('{'))).at("output_fraction").get<double>();
  };
  // Two ranks sum forces in another order: round-off (1e-9, as for LIGGGHTS above).
  EXPECT_NEAR(fraction(c), fraction(twin), 1e-9 * fraction(twin));
}

// A case bigger than one node: this cluster has one, so SLURM refuses two, in its own words,
// and nothing is left submitted; more nodes than ranks is refused before SLURM is asked.
TEST(Slurm, MoreNodesThanTheClusterHasAreRefusedBySlurmAndMoreThanRanksByGranstack) {
  const auto d = work("nodes");
  ASSERT_EQ(granstack({"generate", "-o", (d / "big").string()}).code, 0);
  const auto two = granstack({"submit", (d / "big").string(), "--np", "2", "--nodes", "2"});
  EXPECT_EQ(two.code, 1) << two.output;
  EXPECT_NE(two.output.find("node"), std::string::npos) << two.output;
  EXPECT_FALSE(fs::exists(d / "big" / "slurm" / "submissions.json"));
  const auto three = granstack({"submit", (d / "big").string(), "--np", "2", "--nodes", "3"});
  EXPECT_EQ(three.code, 2) << three.output;
  EXPECT_NE(three.output.find("--nodes 3 with --np 2"), std::string::npos) << three.output;
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

// What `scontrol show job` says of a job (FIELD=value), for its first task.
std::string job_field(const std::string& id, const std::string& field) {
  const auto r = run({"scontrol", "-o", "show", "job", id});
  const auto at = r.output.find(" " + field + "=");
  if (at == std::string::npos) return "";
  const auto start = at + field.size() + 2;
  return r.output.substr(start, r.output.find(' ', start) - start);
}

std::string submission_records(const fs::path& target) { return read_bytes(target / "slurm" / "submissions.json"); }

// #26.1: a submission refused part-way (here the gather, by the partition's time limit) leaves
// the arrays SLURM accepted running and recorded.
TEST(Slurm, ASubmissionRefusedPartWayRecordsTheArraysItStarted) {
  const auto d = work("partway");
  const auto sweep = d / "sweep";
  ASSERT_EQ(granstack({"generate", "-o", sweep.string(), "--blocks", "1", "--restitution", "1,0.9"}).code, 0);
  const auto r = granstack({"submit", sweep.string(), "--partition", "short", "--gather"});
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("sbatch refused"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("array(s) SLURM accepted before"), std::string::npos) << r.output;
  const auto ids = job_ids(r.output);
  ASSERT_EQ(ids.size(), 1u) << r.output;
  EXPECT_NE(submission_records(sweep).find("\"job_id\": \"" + ids[0] + "\""), std::string::npos) << submission_records(sweep);
  ASSERT_TRUE(wait_for(ids));
  expect_done_with_output(sweep / "e1");
  expect_done_with_output(sweep / "e0.9");
  const auto st = granstack({"status", sweep.string()});
  EXPECT_NE(st.output.find("last submission: job " + ids[0]), std::string::npos) << st.output;
}

// #26.2, 3: a case run by a local `run` is running, not killed; cases queued are not submitted twice.
TEST(Slurm, StatusTrustsTheLockAndQueuedCasesAreNotSubmittedTwice) {
  const auto d = work("queued");
  const auto sweep = d / "sweep";
  const auto ids = submit_three_slow_cases(sweep);
  auto again = granstack({"submit", sweep.string()});
  EXPECT_EQ(again.code, 0) << again.output;
  EXPECT_NE(again.output.find("skipped 3 case(s) already queued or running"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("nothing to submit"), std::string::npos) << again.output;
  ASSERT_EQ(run({"scancel", ids.at(0)}).code, 0);
  ASSERT_TRUE(wait_for(ids));
  // A case of the submitted sweep run on the login node: its lock says it runs.
  const auto local = sweep / "e0.8";
  std::vector<std::string> argv{GRANSTACK_EXE, "run", "--force", local.string()};
  os::StartOptions o;
  o.output = d / "local_run.out";
  const auto child = os::start(argv, o);
  wait_until_stepping(local);
  const auto st = granstack({"status", sweep.string()});
  EXPECT_NE(st.output.find(", 1 running"), std::string::npos) << st.output;
  EXPECT_EQ(st.output.find("interrupted  " + local.string()), std::string::npos) << st.output;
  os::wait(child);
}

// #26.2: a controller that does not answer is said, within seconds.
TEST(Slurm, StatusSaysWhenTheControllerDoesNotAnswer) {
  const auto d = work("nocontroller");
  ASSERT_EQ(granstack({"generate", "-o", (d / "case").string(), "--blocks", "1"}).code, 0);
  const auto s = granstack({"submit", (d / "case").string()});
  ASSERT_EQ(s.code, 0) << s.output;
  ASSERT_TRUE(wait_for(job_ids(s.output)));
  auto conf = read_bytes(std::getenv("SLURM_CONF"));
  conf.replace(conf.find("SlurmctldPort=6917"), 18, "SlurmctldPort=6999");
  std::ofstream(d / "dead.conf") << conf;
  const auto t0 = std::chrono::steady_clock::now();
  const auto st = granstack({"status", (d / "case").string()}, {"SLURM_CONF=" + (d / "dead.conf").string()});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 15.0);
  EXPECT_NE(st.output.find("note: the queue could not be read"), std::string::npos) << st.output;
  EXPECT_NE(st.output.find("1 cases: 1 done"), std::string::npos) << st.output;
}

// #26.4: a task that dies before granstack starts (here its script finds no `sed`) is failed,
// with its log named.
TEST(Slurm, ATaskThatNeverRanItsCaseIsFailedWithItsLogNamed) {
  const auto d = work("deadtask");
  ASSERT_EQ(granstack({"generate", "-o", (d / "case").string(), "--blocks", "1"}).code, 0);
  const auto s = granstack({"submit", (d / "case").string(), "--sbatch-arg=--export=ALL,PATH=/nonexistent"});
  ASSERT_EQ(s.code, 0) << s.output;
  const auto ids = job_ids(s.output);
  ASSERT_TRUE(wait_for(ids));
  const auto st = granstack({"status", (d / "case").string()});
  EXPECT_EQ(st.code, 1) << st.output;
  EXPECT_NE(st.output.find("0 done, 1 failed"), std::string::npos) << st.output;
  EXPECT_NE(st.output.find("its SLURM task " + ids[0] + "_0 ended FAILED before granstack ran the case"), std::string::npos)
      << st.output;
  EXPECT_NE(st.output.find("task-" + ids[0] + "_0.out"), std::string::npos) << st.output;
  EXPECT_TRUE(fs::exists(d / "case" / "slurm" / "submit-1" / ("task-" + ids[0] + "_0.out")));
}

// #26.5, 6, 7: each array's time is its longest task's, --max-parallel is shared by the arrays,
// and the gather keeps its dependency beside the user's and follows --time.
TEST(Slurm, TimesThrottlesAndDependenciesHoldAcrossArrays) {
  const auto d = work("arrays");
  const auto mixed = d / "mixed";
  // A 6-block case estimated at 4.6 min of LIGGGHTS (14 min a task), beside a 1-block one.
  ASSERT_EQ(granstack({"generate", "-o", mixed.string(), "--blocks", "1,6", "--top-columns", "8", "--rows", "16"}).code, 0);
  auto r = granstack({"submit", "--dry-run", (mixed / "nb6").string()});
  const std::regex time_line("#SBATCH --time=([0-9:]+)");
  std::smatch m;
  const auto alone = read_bytes(mixed / "nb6" / "slurm" / "dry-run" / "array-1.sbatch");
  ASSERT_TRUE(std::regex_search(alone, m, time_line)) << alone;
  const std::string six_blocks = m[1];
  EXPECT_NE(six_blocks, "00:05:00");
  r = granstack({"submit", "--dry-run", mixed.string(), "--cases-per-task", "1"});
  const auto both = read_bytes(mixed / "slurm" / "dry-run" / "array-1.sbatch");
  ASSERT_TRUE(std::regex_search(both, m, time_line)) << both;
  EXPECT_EQ(m[1], six_blocks);  // the 1-block case first no longer sets it
  EXPECT_FALSE(fs::exists(mixed / "slurm" / "submit-1"));  // dry runs spend no numbered folder
  // Six one-case tasks: two arrays (MaxArraySize 4); --max-parallel 3 shared as 2 + 1.
  const auto sweep = d / "sweep";
  ASSERT_EQ(granstack({"generate", "-o", sweep.string(), "--blocks", "1", "--restitution", "1,0.99,0.98,0.97,0.96,0.95"}).code, 0);
  r = granstack({"submit", "--dry-run", sweep.string(), "--max-parallel", "3"});
  EXPECT_NE(read_bytes(sweep / "slurm" / "dry-run" / "array-1.sbatch").find("--array=0-3%2"), std::string::npos);
  EXPECT_NE(read_bytes(sweep / "slurm" / "dry-run" / "array-2.sbatch").find("--array=0-1%1"), std::string::npos);
  // Held by the user's dependency on a held job: the second array waits for the first, and the
  // gather for both arrays and the user's job.
  const auto hold = run({"sbatch", "--parsable", "--hold", "--output=/dev/null", "--wrap", "true"});
  ASSERT_EQ(hold.code, 0) << hold.output;
  const auto held = lines_of(hold.output).back();
  r = granstack({"submit", sweep.string(), "--max-parallel", "1", "--gather", "--time", "00:07:00",
                 "--sbatch-arg=--dependency=afterok:" + held});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto ids = job_ids(r.output);
  ASSERT_EQ(ids.size(), 3u) << r.output;
  EXPECT_NE(job_field(ids[1], "Dependency").find("afterany:" + ids[0]), std::string::npos) << job_field(ids[1], "Dependency");
  const auto gather = job_field(ids[2], "Dependency");
  EXPECT_NE(gather.find("afterany:" + ids[0]), std::string::npos) << gather;
  EXPECT_NE(gather.find("afterok:" + held), std::string::npos) << gather;
  EXPECT_EQ(job_field(ids[2], "TimeLimit"), "00:07:00");
  EXPECT_EQ(job_field(ids[0], "JobName"), "granstack-sweep");
  run({"scancel", held, ids[0], ids[1], ids[2]});
  ASSERT_TRUE(wait_for({held, ids[0], ids[1], ids[2]}));
}

// #26.8: '#', '%', quotes and blanks in the sweep's path reach each task's own log; a backslash
// is refused before anything is written.
TEST(Slurm, OddCharactersInTheSweepPathKeepEachTasksLog) {
  const auto d = work("odd") / "a#b%c 'q\" e";
  const auto sweep = d / "sweep";
  ASSERT_EQ(granstack({"generate", "-o", sweep.string(), "--blocks", "1", "--restitution", "1,0.9"}).code, 0);
  const auto s = granstack({"submit", sweep.string()});
  ASSERT_EQ(s.code, 0) << s.output;
  const auto ids = job_ids(s.output);
  ASSERT_TRUE(wait_for(ids));
  for (const auto* task : {"_0.out", "_1.out"}) {
    EXPECT_TRUE(fs::exists(sweep / "slurm" / "submit-1" / ("task-" + ids[0] + task))) << task;
  }
  expect_done_with_output(sweep / "e1");
  expect_done_with_output(sweep / "e0.9");
  const auto back = work("odd") / "back\\slash";
  ASSERT_EQ(granstack({"generate", "-o", back.string(), "--blocks", "1"}).code, 0);
  const auto r = granstack({"submit", back.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("holds a backslash"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(back / "slurm"));
}

// #26.10, 11: a damaged record is reported and set aside; a refused submission leaves no folder;
// a requeued task appends to its log.
TEST(Slurm, ADamagedRecordIsSaidAndARequeueKeepsTheFirstLog) {
  const auto d = work("damaged");
  const auto c = d / "case";
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "3", "--dt", "4e-9"}).code, 0);
  fs::create_directories(c / "slurm");
  std::ofstream(c / "slurm" / "submissions.json") << "[{\"directory\": ";
  auto st = granstack({"status", c.string()});
  EXPECT_EQ(st.code, 0) << st.output;
  EXPECT_NE(st.output.find("submissions.json is damaged"), std::string::npos) << st.output;
  EXPECT_NE(st.output.find("1 cases: 0 done, 0 failed, 0 running, 0 interrupted, 1 pending"), std::string::npos) << st.output;
  auto r = granstack({"submit", c.string(), "--partition", "nosuch"});
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_FALSE(fs::exists(c / "slurm" / "submit-1"));
  r = granstack({"submit", "--force", c.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("moved aside"), std::string::npos) << r.output;
  EXPECT_NO_THROW(nlohmann::json::parse(submission_records(c)));
  const auto ids = job_ids(r.output);
  wait_until_stepping(c);
  const auto task = ids.at(0) + "_0";
  ASSERT_EQ(run({"scontrol", "requeue", task}).code, 0);
  // SLURM holds a requeued job back two minutes, until the first attempt's revoked credential has
  // expired. The test lets it go earlier, but not within the second of the requeue: slurmd
  // compares credentials at one-second resolution, and a launch in that second fails with "Job
  // credential revoked" (seen once in CI, and once in 7 local runs). It releases the task should a
  // failed launch have held it, and waits for the second attempt to finish the case. The job's
  // record is kept for the failure message.
  std::this_thread::sleep_for(std::chrono::milliseconds(2100));
  std::string job;
  const auto rerun_until = std::chrono::steady_clock::now() + std::chrono::seconds(200);
  while (std::chrono::steady_clock::now() < rerun_until &&
         !(fs::exists(c / "run.json") && run_record(c).value("status", "") == "done")) {
    job = run({"scontrol", "-o", "show", "job", task}).output;
    if (job.find("JobState=PENDING") != std::string::npos) {
      if (job.find("held") != std::string::npos || job.find("Priority=0 ") != std::string::npos) run({"scontrol", "release", task});
      run({"scontrol", "update", "JobId=" + task, "StartTime=now"});
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  EXPECT_TRUE(wait_for(ids, 60)) << job;
  SCOPED_TRACE("the task's last record: " + job + "\nthe controller's log of it:\n" + controller_log_of(ids[0]));
  ASSERT_TRUE(wait_for(ids, 60));
  expect_done_with_output(c);
  const auto log = read_bytes(c / "slurm" / "submit-1" / ("task-" + ids[0] + "_0.out"));
  EXPECT_NE(log.find("STOPPED"), std::string::npos) << log;  // the first attempt, kept
  EXPECT_NE(log.find("done "), std::string::npos) << log;
}

}  // namespace

namespace {
// The evaluations table of a design store as (digest, peak wall force, crush) text, sorted.
std::string evaluations_of(const fs::path& store) {
  const auto r = run({"python3", "-c",
                      "import sqlite3, sys; c = sqlite3.connect(sys.argv[1]); "
                      "print('\\n'.join(f'{d} {f!r} {s!r}' for d, f, s in c.execute('select digest, peak_wall_force, "
                      "crush from evaluations where searched = 1 order by digest')))",
                      store.string()});
  EXPECT_EQ(r.code, 0) << r.output;
  return r.output;
}

// granstack design run --slurm: each generation's new designs go out as a job array (submit's),
// the search waits for them, and a task cancelled before it ran is submitted again; the store
// ends exactly as a local search's (the same designs, the same peak forces and crushes to the bit:
// reduce of a refsim case is the in-situ value).
TEST(Slurm, ADesignSearchRunsItsBatchesAsArraysAndSurvivesACancelledTask) {
  if (!os::find_program("python3")) GTEST_SKIP() << "python3 is not installed (the store is read with its sqlite3)";
  const auto d = work("design");
  // The generational search: a generation's designs at once.
  const auto space = d / "generational.toml";
  std::ofstream(space) << read_bytes(fs::path(GRANSTACK_TEST_DATA) / "design" / "small_space.toml")
                       << "evaluation = \"generational\"\n";
  os::StartOptions o;
  o.output = d / "search.log";
  const auto child = os::start({GRANSTACK_EXE, "design", "run", space.string(), "-o", (d / "slurm").string(), "--generations",
                                "1", "--slurm", "--max-parallel", "1", "--poll", "0.2"},
                               o);
  ASSERT_EQ(child.error, "");
  // Cancel the last task of the first batch's first array (the test cluster's MaxArraySize of 4
  // splits a batch of more designs over several, said as 'jobs'), while it waits its turn.
  std::string cancelled;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (cancelled.empty() && std::chrono::steady_clock::now() < until) {
    const auto log = read_bytes(d / "search.log");
    const std::regex id("submitted ([0-9]+) case\\(s\\) as SLURM jobs? ([0-9]+)");
    std::smatch m;
    if (std::regex_search(log, m, id)) {
      cancelled = m[2].str() + "_" + std::to_string(std::min(std::stoi(m[1].str()), 4) - 1);
      ASSERT_EQ(run({"scancel", cancelled}).code, 0);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_FALSE(cancelled.empty()) << read_bytes(d / "search.log");
  const auto end = os::wait(child);
  const auto log = read_bytes(d / "search.log");
  ASSERT_TRUE(end.ok()) << log;
  EXPECT_NE(log.find("submitted again 1 case(s)"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(d / "slurm" / "batches" / "b1")) << "a finished batch's cases are removed";
  // The same search on this machine.
  const auto local = granstack({"design", "run", space.string(), "-o", (d / "local").string(), "--generations", "1", "-j", "2"});
  ASSERT_EQ(local.code, 0) << local.output;
  const auto a = evaluations_of(d / "slurm" / "design.sqlite"), b = evaluations_of(d / "local" / "design.sqlite");
  EXPECT_EQ(a, b);
  EXPECT_GE(std::count(a.begin(), a.end(), '\n'), 8);
}

// granstack design run --slurm on an asynchronous search: each design in flight is a job array
// of its scenarios, the next starts as soon as one finishes, and the store ends exactly as the
// same search's on this machine (one design in flight on both, so the same designs in the same
// order; reduce of a refsim case is the in-situ value); nothing of the search is left queued.
TEST(Slurm, AnAsynchronousDesignSearchRunsEachDesignAsAnArrayAndEqualsALocalOne) {
  if (!os::find_program("python3")) GTEST_SKIP() << "python3 is not installed (the store is read with its sqlite3)";
  const auto d = work("design_async");
  const auto space = d / "space.toml";
  std::ofstream(space) << read_bytes(fs::path(GRANSTACK_TEST_DATA) / "design" / "small_space.toml");
  const auto r = granstack({"design", "run", space.string(), "-o", (d / "slurm").string(), "--max-designs", "6", "-j", "1",
                            "--slurm", "--poll", "0.1"});
  ASSERT_EQ(r.code, 0) << r.output;
  const auto ids = job_ids(r.output);
  EXPECT_GE(ids.size(), 6u) << r.output;  // a job per design, probes included
  EXPECT_TRUE(wait_for(ids, 5)) << "jobs of the search are still queued";
  // SLURM runs every design in full (the shortcuts settle a design in situ, between and during its
  // runs): the local search it equals is one without them.
  const auto in_full = d / "in_full.toml";
  std::ofstream(in_full) << read_bytes(space) << "shortcuts = false\n";
  const auto local = granstack({"design", "run", in_full.string(), "-o", (d / "local").string(), "--max-designs", "6", "-j", "1"});
  ASSERT_EQ(local.code, 0) << local.output;
  const auto a = evaluations_of(d / "slurm" / "design.sqlite"), b = evaluations_of(d / "local" / "design.sqlite");
  EXPECT_EQ(a, b);
  EXPECT_GE(std::count(a.begin(), a.end(), '\n'), 5);
  // Two in flight and a time limit: the search ends with designs running; their arrays are
  // cancelled, and the search ends as any does (exit 0).
  const auto limited = granstack({"design", "run", space.string(), "-o", (d / "limited").string(), "-j", "2",
                                  "--time-limit", "2", "--slurm", "--poll", "0.1"});
  ASSERT_EQ(limited.code, 0) << limited.output;
  EXPECT_TRUE(wait_for(job_ids(limited.output), 5)) << "jobs of the search are still queued:\n" << limited.output;
}

}  // namespace
