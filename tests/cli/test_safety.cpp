// Safety (issue #10), on the real program and the real LIGGGHTS: granstack never replaces what
// it did not make, never hands a path to a shell, never lets two runs share a case, stops its
// children when stopped, and never passes broken physics or a bad file off as a result. The
// program is started here from argument vectors too, so the odd paths reach it untouched.
#include "../support/granstack_test.hpp"

#include <granstack/os/process.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sys/stat.h>
#include <tuple>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace granstack;
using namespace granstack::test;

namespace {

class Safety : public test::GranstackTest {};

// 1. --force replaces only what granstack made.
TEST_F(Safety, ForceNeverReplacesWhatGranstackDidNotMake) {
  const auto project = path("project");
  fs::create_directories(project / "sub");
  std::ofstream(project / "thesis.tex") << "my thesis";
  // The working directory, and a parent of it.
  auto r = granstack({"generate", "-o", ".", "--force"}, project);
  EXPECT_EQ(r.code, 3) << r.output;
  expect_contains(r, "is the working directory or one of its parents");
  EXPECT_EQ(r.output.find("pass --force"), std::string::npos) << r.output;
  r = granstack({"generate", "-o", "..", "--force"}, project / "sub");
  EXPECT_EQ(r.code, 3) << r.output;
  r = granstack({"generate", "-o", project.string(), "--force"}, project / "sub");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_EQ(read_bytes(project / "thesis.tex"), "my thesis");
  // A regular file, the root, the home directory, a user's directory.
  r = granstack({"generate", "-o", (project / "thesis.tex").string(), "--force"});
  EXPECT_EQ(r.code, 3) << r.output;
  expect_contains(r, "is a file, not a directory granstack made");
  EXPECT_EQ(read_bytes(project / "thesis.tex"), "my thesis");
  r = granstack({"generate", "-o", "/", "--force"});
  EXPECT_EQ(r.code, 3) << r.output;
  expect_contains(r, "is the root directory");
  fs::create_directories(path("home"));
  ::setenv("HOME", path("home").c_str(), 1);
  r = granstack({"generate", "-o", path("home").string(), "--force"});
  EXPECT_EQ(r.code, 3) << r.output;
  expect_contains(r, "is your home directory");
  r = granstack({"generate", "-o", project.string() + "/sub", "--force"});
  EXPECT_EQ(r.code, 3) << r.output;
  expect_contains(r, "was not made by granstack");
  EXPECT_TRUE(fs::exists(project / "sub"));
  // A case granstack made is replaced with --force, and only then.
  ASSERT_EQ(granstack({"generate", "-o", path("case").string(), "--blocks", "1"}).code, 0);
  r = granstack({"generate", "-o", path("case").string(), "--blocks", "2"});
  EXPECT_EQ(r.code, 3);
  expect_contains(r, "pass --force");
  EXPECT_EQ(granstack({"generate", "-o", path("case").string(), "--blocks", "2", "--force"}).code, 0);
  // validate's copies: a user's directory where a copy would go is kept.
  fs::create_directories(path("case/validate/liggghts"));
  std::ofstream(path("case/validate/liggghts/notes.txt")) << "mine";
  r = granstack({"validate", path("case").string()});
  EXPECT_EQ(r.code, 3) << r.output;
  expect_contains(r, "was not made by granstack");
  EXPECT_EQ(read_bytes(path("case/validate/liggghts/notes.txt")), "mine");
}

// 2. No shell: quotes, $(), spaces and newlines in every path a user gives.
TEST_F(Safety, OddPathsReachEveryProgramUntouchedAndRunNoCommand) {
  // (Control characters, a newline among them, are refused outright: test_reliability.cpp.)
  const std::string odd = "it's \"odd\" $(touch PWNED) `touch PWNED2`; x | new line";
  const auto base = path(odd);
  fs::create_directories(base);
  std::ofstream(base / "spec '$(touch PWNED3)'.toml") << "blocks = 1\nrows = 4\n";
  const auto tmpl = base / "deck \"$(touch PWNED4)\".tmpl";
  fs::copy_file(fs::path(GRANSTACK_SOURCE_DIR) / "templates/in.granstack.tmpl", tmpl);
  const auto sweep = base / "sweep 'a' & b";
  auto r = granstack({"generate", "-o", sweep.string(), "--config", (base / "spec '$(touch PWNED3)'.toml").string(),
                      "--restitution", "1,0.9", "--template", tmpl.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  r = granstack({"run", "-j", "2", sweep.string()});
  ASSERT_EQ(r.code, 0) << r.output;
  r = granstack({"reduce", sweep.string()});
  EXPECT_EQ(r.code, 0) << r.output;
  r = granstack({"table", sweep.string(), "-o", (base / "table '$(touch PWNED5)'").string()});
  EXPECT_EQ(r.code, 0) << r.output;
  r = granstack({"plot", sweep.string(), "-o", (base / "plots \"$(touch PWNED6)\" > '").string()});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(base / "plots \"$(touch PWNED6)\" > '" / "energy_e0.9.png"));
  EXPECT_TRUE(fs::exists(base / "table '$(touch PWNED5)'" / "table.md"));
  r = granstack({"validate", (sweep / "e1").string()});
  EXPECT_EQ(r.code, 0) << r.output;
  for (const auto& e : fs::recursive_directory_iterator(dir_)) {
    EXPECT_EQ(e.path().filename().string().rfind("PWNED", 0), std::string::npos) << e.path();
  }
}

// 3. One run per case at a time; a stop signal stops LIGGGHTS and marks the case.
TEST_F(Safety, ACaseInUseIsRefusedAndAStopSignalEndsItsLiggghts) {
  const auto c = path("case");
  // About 10 s of LIGGGHTS: time to be refused and stopped.
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "4", "--dt", "3e-9"}).code, 0);
  for (const int sig : {SIGINT, SIGTERM}) {
    const auto first = start({"run", "--force", c.string()});
    ASSERT_TRUE(eventually([&] { return processes_in(c).size() == 1; }, 30)) << "LIGGGHTS did not start";
    auto second = granstack({"run", "--force", c.string()});
    EXPECT_EQ(second.code, 1) << second.output;
    expect_contains(second, "is in use by another granstack (granstack run by pid " + std::to_string(first.pid));
    second = granstack({"validate", c.string()});
    EXPECT_EQ(second.code, 1) << second.output;
    expect_contains(second, "is in use by another granstack");
    ::kill(first.pid, sig);
    const auto stopped = finish(first, 30);
    EXPECT_EQ(stopped.code, 128 + sig) << stopped.output;
    expect_contains(stopped, "STOPPED");
    EXPECT_EQ(status_of(c), "interrupted");
    EXPECT_TRUE(eventually([&] { return processes_in(c).empty(); }, 5)) << processes_in(c).front();
  }
  // SIGINT sent to LIGGGHTS itself: it quits early and writes a forced restart; granstack says
  // the run failed and removes the restart file. (The stopped run's output goes first, so that
  // its thermo lines are not taken for the new run's on a slow start.)
  fs::remove(c / "liggghts.out");
  const auto first = start({"run", "--force", c.string()});
  // Once its run has begun (LIGGGHTS drops a signal that comes during set-up).
  ASSERT_TRUE(eventually(
      [&] {
        const auto out = read_bytes(c / "liggghts.out");
        const auto header = out.find("    Step    Atoms");
        return header != std::string::npos && std::count(out.begin() + static_cast<long>(header), out.end(), '\n') >= 3;
      },
      30));
  ASSERT_EQ(processes_in(c).size(), 1u);
  ::kill(std::stoi(processes_in(c).front()), SIGINT);
  const auto r = finish(first, 60);
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "was sent SIGINT or SIGTERM directly");
  EXPECT_EQ(status_of(c), "failed");
  for (const auto& e : fs::directory_iterator(c)) {
    EXPECT_EQ(e.path().filename().string().rfind("restart_forced", 0), std::string::npos) << e.path();
  }
}

// 3. The same for a run on two MPI ranks: mpirun's ranks sit in process groups of their own,

// refsim stopped by a signal: it ends at once, marks the case, and every frame of its dump is
// whole (those it made before the signal are written, from the thread that writes them behind
// the steps as in line).
TEST_F(Safety, AStopSignalEndsARefsimRunWithEveryDumpFrameWhole) {
  const auto c = path("case");
  // About 5 s of refsim: 961 spheres at a tenth of the automatic time step, 800 frames.
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--top-columns", "8", "--dt", "1e-9"}).code, 0);
  const auto dump = c / "dumps" / "dump.txt";
  const auto run = start({"run", "--engine", "refsim", c.string()});
  ASSERT_TRUE(eventually(
      [&] {
        std::error_code ec;
        return status_of(c) == "running" && fs::file_size(dump, ec) > 1000000 && !ec;
      },
      60))
      << "refsim did not start writing";
  ::kill(run.pid, SIGINT);
  const auto stopped = finish(run, 30);
  EXPECT_EQ(stopped.code, 128 + SIGINT) << stopped.output;
  expect_contains(stopped, "STOPPED");
  EXPECT_EQ(status_of(c), "interrupted");
  const auto text = read_bytes(dump);
  std::size_t frames = 0;
  for (auto at = text.find("ITEM: TIMESTEP\n"); at != std::string::npos; ++frames) {
    const auto next = text.find("ITEM: TIMESTEP\n", at + 1);
    const std::string frame = text.substr(at, next == std::string::npos ? std::string::npos : next - at);
    const auto count_at = frame.find("ITEM: NUMBER OF ATOMS\n") + 22;
    const long atoms = std::stol(frame.substr(count_at, frame.find('\n', count_at) - count_at));
    const auto header = frame.find("ITEM: ATOMS ");
    ASSERT_NE(header, std::string::npos) << "frame " << frames;
    const auto first_line = frame.find('\n', header) + 1;
    const auto columns = std::count(frame.begin() + static_cast<long>(header), frame.begin() + static_cast<long>(first_line), ' ') - 2;
    std::istringstream lines(frame.substr(first_line));
    long whole = 0;
    for (std::string line; std::getline(lines, line);) {
      std::istringstream words(line);
      EXPECT_EQ(std::distance(std::istream_iterator<std::string>(words), std::istream_iterator<std::string>()), columns)
          << "frame " << frames << ", line " << whole;
      ++whole;
    }
    EXPECT_EQ(whole, atoms) << "frame " << frames;
    EXPECT_EQ(frame.back(), '\n') << "frame " << frames;
    at = next;
  }
  EXPECT_GT(frames, 2U);
  EXPECT_LT(frames, 800U) << "the run ended before the signal: nothing was stopped";
}

// and still none is left once granstack is stopped (SIGINT) or killed (SIGKILL).
TEST_F(Safety, AnMpiRunLeavesNoRankBehind) {
  const auto c = path("case");
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "4", "--dt", "3e-9"}).code, 0);
  for (const int sig : {SIGINT, SIGKILL}) {
    const auto run = start({"run", "--force", "--np", "2", c.string()});
    // mpirun and both ranks.
    ASSERT_TRUE(eventually([&] { return processes_in(c).size() == 3; }, 30)) << processes_in(c).size();
    ::kill(run.pid, sig);
    const auto r = finish(run, 30);
    if (sig == SIGINT) {
      EXPECT_EQ(r.code, 130) << r.output;
      EXPECT_EQ(status_of(c), "interrupted");
    }
    EXPECT_TRUE(eventually([&] { return processes_in(c).empty(); }, 3)) << processes_in(c).front();
  }
}

// 3. kill -9 of a sweep mid-way: no LIGGGHTS is left, a rerun at once redoes only the unfinished
// cases, and the results are those of an uninterrupted run, byte for byte.
TEST_F(Safety, ASweepKilledMidwayLeavesNoLiggghtsAndResumesToTheSameBytes) {
  // Cases of several seconds each, so that a LIGGGHTS left running would still be there.
  const std::vector<std::string> spec = {"--blocks", "3,4", "--restitution", "1,0.9", "--dt", "6e-9"};
  auto args = std::vector<std::string>{"generate", "-o", path("killed").string()};
  args.insert(args.end(), spec.begin(), spec.end());
  ASSERT_EQ(granstack(args).code, 0);
  args[2] = path("whole").string();
  ASSERT_EQ(granstack(args).code, 0);
  const std::vector<std::string> cases = {"nb3_e1", "nb3_e0.9", "nb4_e1", "nb4_e0.9"};
  const auto run = start({"run", "-j", "2", path("killed").string()});
  // Killed once a case is done and two run.
  ASSERT_TRUE(eventually(
      [&] {
        int done = 0;
        for (const auto& c : cases) done += status_of(path("killed") / c) == "done";
        return done >= 1 && processes_in(path("killed")).size() == 2;
      },
      120));
  ::kill(run.pid, SIGKILL);
  os::wait(run);
  EXPECT_TRUE(eventually([&] { return processes_in(path("killed")).empty(); }, 1)) << processes_in(path("killed")).front();
  int done_before = 0;
  for (const auto& c : cases) done_before += status_of(path("killed") / c) == "done";
  const auto rerun = granstack({"run", "-j", "2", path("killed").string()});
  ASSERT_EQ(rerun.code, 0) << rerun.output;
  int skipped = 0;
  for (auto at = rerun.output.find("skipped"); at != std::string::npos; at = rerun.output.find("skipped", at + 1)) ++skipped;
  EXPECT_EQ(skipped, done_before) << rerun.output;
  ASSERT_EQ(granstack({"run", "-j", "2", path("whole").string()}).code, 0);
  for (const auto& c : cases) {
    for (const char* f : {"dumps/dump.txt", "ke_series.txt"}) {
      EXPECT_EQ(read_bytes(path("killed") / c / f), read_bytes(path("whole") / c / f)) << c << " " << f;
    }
    ASSERT_EQ(granstack({"reduce", (path("killed") / c).string()}).code, 0);
    ASSERT_EQ(granstack({"reduce", (path("whole") / c).string()}).code, 0);
    for (const char* f : {"reduce/block_ke.csv", "reduce/energy_parts.csv"}) {
      EXPECT_EQ(read_bytes(path("killed") / c / f), read_bytes(path("whole") / c / f)) << c << " " << f;
    }
  }
}

// 4. Physics guards at generate.
TEST_F(Safety, GenerateRefusesUnphysicalOrRunawayCasesAndShowsTheCost) {
  struct Bad {
    std::vector<std::string> flags;
    std::string words;
  };
  const Bad bad[] = {
      {{"--dt", "1e-5", "--blocks", "2"}, "dt: 1e-05 s is more than 1/20 of the shortest Hertz contact time"},
      {{"--dt", "1e-20"}, "the run would take 1.02e+17 steps"},
      {{"--duration", "1e9"}, "duration: the run would take"},
      {{"--gravity", "1e30"}, "gravity: 1e+30 must be in [0, 1000]"},
      {{"--friction", "1e300"}, "friction: 1e+300 must be in [0, 10]"},
      {{"--bottom-radius", "1e308"}, "bottom_radius: 1e+308 must be in [1e-07, 1] m"},
      {{"--bottom-radius", "1e-300"}, "bottom_radius: 1e-300 must be in [1e-07, 1] m"},
      {{"--bottom-radius", "1e308,1e-300"}, "in the sweep case"},
      {{"--striker-speed", "200"}, "Hertz contact holds for small overlaps only"},
      {{"--blocks", "10", "--bottom-radius", "1e-5"}, "is large: its outputs would take about"},
  };
  for (const auto& b : bad) {
    std::vector<std::string> args{"generate", "-o", path("case").string()};
    args.insert(args.end(), b.flags.begin(), b.flags.end());
    const auto r = granstack(args);
    EXPECT_EQ(r.code, 2) << b.flags.front() << "\n" << r.output;
    expect_contains(r, b.words);
    EXPECT_EQ(r.output.find("json.exception"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("case"))) << b.flags.front();
  }
  // The cost is shown, and a large case is generated when the user confirms.
  auto r = granstack({"generate", "-o", path("case").string()});
  EXPECT_EQ(r.code, 0);
  expect_contains(r, "MB of dumps and series, about");
  r = granstack({"generate", "-o", path("large").string(), "--blocks", "10", "--bottom-radius", "1e-5", "--large"});
  EXPECT_EQ(r.code, 0) << r.output;
  expect_contains(r, "16369 spheres");
}

// 4. reduce: broken energy balance fails; an edited deck or manifest is caught.
TEST_F(Safety, ReduceFailsOnBrokenEnergyAndOnEditedInputs) {
  const auto c = path("case");
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "2"}).code, 0);
  ASSERT_EQ(granstack({"run", c.string()}).code, 0);
  ASSERT_EQ(granstack({"reduce", c.string()}).code, 0);
  const auto dump = read_bytes(c / "dumps/dump.txt");
  // Every velocity doubled: four times the kinetic energy, from an elastic case.
  std::istringstream in(dump);
  std::ostringstream out;
  std::string line;
  bool atoms = false;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM:", 0) == 0) {
      atoms = line.rfind("ITEM: ATOMS", 0) == 0;
      out << line << '\n';
      continue;
    }
    if (!atoms) {
      out << line << '\n';
      continue;
    }
    std::istringstream words(line);
    std::vector<std::string> w{std::istream_iterator<std::string>(words), std::istream_iterator<std::string>()};
    for (int k = 7; k <= 9; ++k) w[static_cast<std::size_t>(k)] = std::to_string(2 * std::stod(w[static_cast<std::size_t>(k)]));
    for (const auto& x : w) out << x << ' ';
    out << '\n';
  }
  std::ofstream(c / "dumps/dump.txt", std::ios::binary) << out.str();
  auto r = granstack({"reduce", c.string()});
  EXPECT_EQ(r.code, 6) << r.output;
  expect_contains(r, "against E_in");
  expect_contains(r, "this case conserves energy");
  std::ofstream(c / "dumps/dump.txt", std::ios::binary) << dump;
  // A deck whose time step was edited by hand (and a manifest).
  const auto deck = read_bytes(c / "in.stack");
  auto edited = deck;
  edited.replace(edited.find("timestep        "), 30, "timestep        1.2e-07\n#");
  std::ofstream(c / "in.stack", std::ios::binary) << edited;
  r = granstack({"reduce", c.string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "in.stack: the deck was edited after 'granstack generate'");
  r = granstack({"run", "--force", c.string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "the deck was edited after 'granstack generate'");
  std::ofstream(c / "in.stack", std::ios::binary) << deck;
  auto manifest = read_bytes(c / "manifest.json");
  const auto at = manifest.find("\"steps\": ");
  manifest.replace(at, manifest.find(',', at) - at, "\"steps\": 6500");
  std::ofstream(c / "manifest.json", std::ios::binary) << manifest;
  r = granstack({"reduce", c.string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "the manifest was edited");
}

// 5. Bad files: NaN or inf anywhere, a series cut, foreign, impossible or missing, pieces of a
// dump missing, and files that are not regular files.
TEST_F(Safety, ReduceRefusesBadFilesNamingWhereAndWhat) {
  const auto c = path("case");
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "2", "--rows", "4"}).code, 0);
  ASSERT_EQ(granstack({"run", c.string()}).code, 0);
  ASSERT_EQ(granstack({"generate", "-o", path("other").string(), "--blocks", "2", "--rows", "4", "--restitution", "0.9"}).code, 0);
  ASSERT_EQ(granstack({"run", path("other").string()}).code, 0);
  const auto dump = read_bytes(c / "dumps/dump.txt");
  const auto series = read_bytes(c / "ke_series.txt");
  auto with = [&](const fs::path& file, const std::string& content) {
    std::ofstream(file, std::ios::binary) << content;
    auto r = granstack({"reduce", c.string()}, {}, 30);
    std::ofstream(c / "dumps/dump.txt", std::ios::binary) << dump;
    std::ofstream(c / "ke_series.txt", std::ios::binary) << series;
    return r;
  };
  // A value of the second atom line of the 100th frame replaced: the 6th (y), the 8th (vx) or
  // the 16th (fz, a column reduce does not otherwise need).
  auto frame = dump.find("ITEM: TIMESTEP\n");
  for (int k = 1; k < 100; ++k) frame = dump.find("ITEM: TIMESTEP\n", frame + 1);
  ASSERT_NE(frame, std::string::npos);
  const std::string step = dump.substr(frame + 15, dump.find('\n', frame + 15) - frame - 15);
  auto replace_value = [&](int column, const std::string& value) {
    const auto atoms = dump.find("ITEM: ATOMS", frame);
    std::string d = dump;
    auto p = dump.find('\n', dump.find('\n', atoms) + 1) + 1;  // the second atom line
    for (int k = 1; k < column; ++k) p = d.find(' ', p) + 1;
    d.replace(p, d.find(' ', p) - p, value);
    return d;
  };
  for (const auto& [column, value, name] : {std::tuple{6, "nan", "y"}, std::tuple{16, "-inf", "fz"}, std::tuple{8, "inf", "vx"}}) {
    const auto r = with(c / "dumps/dump.txt", replace_value(column, value));
    EXPECT_EQ(r.code, 4) << r.output;
    expect_contains(r, "dumps/dump.txt:");
    expect_contains(r, "column '" + std::string(name) + "'");
    expect_contains(r, "step " + step);
  }
  auto r = with(c / "ke_series.txt", series.substr(0, series.size() / 4));
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "the series was cut or damaged");
  r = with(c / "ke_series.txt", read_bytes(path("other/ke_series.txt")));
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "the series is not this run's");
  auto big = series;
  const auto row = big.find('\n', big.find('\n', big.size() / 2) + 1) + 1;
  const auto second = big.find(' ', row) + 1;
  big.replace(second, big.find(' ', second) - second, "1e300");
  r = with(c / "ke_series.txt", big);
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "1e+300 J in column 'ke_trans_block1'");
  auto nan = series;
  nan.replace(second, nan.find(' ', second) - second, "nan");
  r = with(c / "ke_series.txt", nan);
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "nan in column 'ke_trans_block1'");
  fs::remove(c / "ke_series.txt");
  r = granstack({"reduce", c.string()});
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "ke_series.txt: missing");
  std::ofstream(c / "ke_series.txt", std::ios::binary) << series;
  // Not regular files: reduce must neither hang nor read forever.
  fs::remove(c / "dumps/dump.txt");
  ASSERT_EQ(::mkfifo((c / "dumps/dump.txt").c_str(), 0644), 0);
  r = granstack({"reduce", c.string()}, {}, 30);
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "is a FIFO");
  fs::remove(c / "dumps/dump.txt");
  fs::create_symlink("/dev/zero", c / "dumps/dump.txt");
  r = granstack({"reduce", c.string()}, {}, 30);
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "is a device");
  fs::remove(c / "dumps/dump.txt");
  std::ofstream(c / "dumps/dump.txt", std::ios::binary) << dump;
  EXPECT_EQ(granstack({"reduce", c.string()}).code, 0);
}

TEST_F(Safety, MissingPiecesOfAPerStepDumpAreErrors) {
  const auto c = path("case");
  ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "1", "--dump-files", "per_step"}).code, 0);
  ASSERT_EQ(granstack({"run", c.string()}).code, 0);
  ASSERT_EQ(granstack({"reduce", c.string()}).code, 0);
  std::vector<fs::path> pieces;
  for (const auto& e : fs::directory_iterator(c / "dumps")) pieces.push_back(e.path());
  std::sort(pieces.begin(), pieces.end(), [](const fs::path& a, const fs::path& b) {
    return std::stol(a.stem().extension().string().substr(1)) < std::stol(b.stem().extension().string().substr(1));
  });
  ASSERT_GT(pieces.size(), 10u);
  for (const auto& piece : {pieces.front(), pieces[pieces.size() / 2], pieces.back()}) {
    const auto bytes = read_bytes(piece);
    fs::remove(piece);
    const auto r = granstack({"reduce", c.string()});
    EXPECT_EQ(r.code, 4) << piece << "\n" << r.output;
    expect_contains(r, "frame");
    std::ofstream(piece, std::ios::binary) << bytes;
  }
}

// 6. Spec: refusals say what is wrong in words and leave nothing behind.
TEST_F(Safety, SpecRefusalsAreWordsAndLeaveNothing) {
  const std::vector<std::vector<std::string>> bad = {
      {"--custom-material", "steel:1:1:0.3"},
      {"--restitution-pair", "steel:teflon=0.8"},
      {"--friction-pair", "teflon:teflon=0.3"},
      {"--blocks", ""},
      {"--materials", ""},
      {"--restitution", "1,"},
  };
  const char* words[] = {"built-in material and cannot be redefined", "names a material this stack does not use",
                         "names a material this stack does not use", "blocks: an empty value",
                         "materials: an empty value", "restitution: an empty value"};
  for (std::size_t i = 0; i < bad.size(); ++i) {
    std::vector<std::string> args{"generate", "-o", path("case").string()};
    args.insert(args.end(), bad[i].begin(), bad[i].end());
    const auto r = granstack(args);
    EXPECT_EQ(r.code, 2) << bad[i].front() << "\n" << r.output;
    expect_contains(r, words[i]);
    EXPECT_FALSE(fs::exists(path("case")));
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), static_cast<long>(runs_));
}

// 6. Odd radius ratios: the output sphere lies on the impact path, so it leaves the bottom with
// energy (it stayed at rest, "not separated", when taken just right of the axis).
TEST_F(Safety, OddAndWiderRadiusRatiosGiveAnOutput) {
  for (const std::string ratio : {"3", "4"}) {
    const auto c = path("ratio" + ratio);
    ASSERT_EQ(granstack({"generate", "-o", c.string(), "--blocks", "2", "--radius-ratio", ratio}).code, 0);
    ASSERT_EQ(granstack({"run", "--engine", "refsim", c.string()}).code, 0);
    const auto r = granstack({"reduce", "--json", c.string()});
    ASSERT_EQ(r.code, 0) << r.output;
    expect_contains(r, "\"output_separated\":true");
    const auto at = r.output.find("\"output_fraction\":") + 18;
    const double fraction = std::stod(r.output.substr(at));
    EXPECT_GT(fraction, 0.005) << ratio;  // measured: 0.0450 (ratio 3), 0.0176 (ratio 4)
    EXPECT_LT(fraction, 0.5) << ratio;
  }
}

// 7. Outputs: table and plot never replace a user's files; cases with one name stay apart; a
// case whose reduce/ cannot be written is reduced elsewhere with -o.
TEST_F(Safety, OutputsNeverReplaceUsersFilesAndCaseNamesStayApart) {
  for (const char* group : {"a", "b"}) {
    ASSERT_EQ(granstack({"generate", "-o", path(group).string(), "--blocks", "1,2", "--rows", "4",
                         "--restitution", std::string(group) == "a" ? "1" : "0.9"}).code, 0);
    ASSERT_EQ(granstack({"run", path(group).string()}).code, 0);
  }
  fs::create_directories(path("mine"));
  std::ofstream(path("mine/table.md")) << "my table";
  std::ofstream(path("mine/decay.png")) << "my figure";
  for (const bool force : {false, true}) {
    std::vector<std::string> table{"table", path("a").string(), "-o", path("mine").string()};
    std::vector<std::string> plot{"plot", path("a").string(), "-o", path("mine").string()};
    if (force) {
      table.push_back("--force");
      plot.push_back("--force");
    }
    auto r = granstack(table);
    EXPECT_EQ(r.code, 3) << r.output;
    expect_contains(r, "was not made by granstack");
    r = granstack(plot);
    EXPECT_EQ(r.code, 3) << r.output;
  }
  EXPECT_EQ(read_bytes(path("mine/table.md")), "my table");
  EXPECT_EQ(read_bytes(path("mine/decay.png")), "my figure");
  // Into a directory of its own: again only with --force.
  ASSERT_EQ(granstack({"table", path("a").string(), "-o", path("t").string()}).code, 0);
  EXPECT_EQ(granstack({"table", path("a").string(), "-o", path("t").string()}).code, 3);
  EXPECT_EQ(granstack({"table", path("a").string(), "-o", path("t").string(), "--force"}).code, 0);
  // The same leaf name in two sweeps: two rows with their sweep, two figures.
  auto r = granstack({"reduce", (path("a") / "nb1").string(), (path("b") / "nb1").string()});
  ASSERT_EQ(r.code, 0) << r.output;
  expect_contains(r, "a/nb1 ");
  expect_contains(r, "b/nb1 ");
  // (and a relative output directory: the figures go where the user is, not where gnuplot runs)
  r = granstack({"plot", "a/nb1", "b/nb1", "-o", "p"});
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(path("p/energy_a_nb1.png")));
  EXPECT_TRUE(fs::exists(path("p/energy_b_nb1.png")));
  // A case whose reduce/ cannot be written (here a file stands in its place; a read-only case
  // fails the same way for a user who is not root): the error says so and -o reduces elsewhere.
  const auto c = path("a") / "nb2";
  fs::remove_all(c / "reduce");
  std::ofstream(c / "reduce") << "in the way";
  r = granstack({"reduce", c.string()});
  EXPECT_EQ(r.code, 7) << r.output;  // an I/O error (issue #22)
  expect_contains(r, "cannot write its results");
  expect_contains(r, "granstack reduce -o DIR");
  r = granstack({"reduce", c.string(), "-o", path("elsewhere").string()});
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(path("elsewhere/nb2/summary.json")));
  EXPECT_EQ(read_bytes(c / "reduce"), "in the way");
}

// A line per case as it ends, written at once: a log followed with tail -f shows each case
// when it finishes, not all of them at the end.
TEST_F(Safety, RunPrintsEachCaseAsItEnds) {
  ASSERT_EQ(granstack({"generate", "-o", path("quick").string(), "--blocks", "1"}).code, 0);
  ASSERT_EQ(granstack({"generate", "-o", path("slow").string(), "--blocks", "4", "--dt", "3e-9"}).code, 0);
  const auto run = start({"run", path("quick").string(), path("slow").string()});
  const auto log = logs_[run.pid];
  EXPECT_TRUE(eventually([&] { return read_bytes(log).find("done     " + path("quick").string()) != std::string::npos; }, 30));
  EXPECT_FALSE(os::poll(run).has_value()) << "the slow case should still be running";
  EXPECT_EQ(read_bytes(log).find("slow"), std::string::npos);
  const auto r = finish(run, 120);
  EXPECT_EQ(r.code, 0) << r.output;
  expect_contains(r, "done     " + path("slow").string());
}

// refsim takes its physics from the manifest, LIGGGHTS from the deck: a deck rendered from a
// template of the user's could say something else, so refsim and validate refuse it (before
// LIGGGHTS spends any time), while a template identical to granstack's own is accepted.
TEST_F(Safety, RefsimAndValidateRefuseADeckFromAnotherTemplate) {
  std::string tmpl = read_bytes(fs::path(GRANSTACK_SOURCE_DIR) / "templates/in.granstack.tmpl");
  std::ofstream(path("same.tmpl")) << tmpl;
  std::ofstream(path("mine.tmpl")) << tmpl << "# my own line\n";
  ASSERT_EQ(granstack({"generate", "-o", path("same").string(), "--blocks", "1", "--template", path("same.tmpl").string()}).code, 0);
  ASSERT_EQ(granstack({"generate", "-o", path("mine").string(), "--blocks", "1", "--template", path("mine.tmpl").string()}).code, 0);
  EXPECT_EQ(granstack({"run", "--engine", "refsim", path("same").string()}).code, 0);
  auto r = granstack({"run", "--engine", "refsim", path("mine").string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "is not the deck this granstack's template gives for this case (it was rendered from a --template of yours)");
  r = granstack({"validate", path("mine").string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "cannot be validated");
  EXPECT_FALSE(fs::exists(path("mine/validate")));
  EXPECT_EQ(granstack({"run", path("mine").string()}).code, 0);  // LIGGGHTS runs it as written
}

// A template of the user's that names its own contact model (an older one, written before
// granstack had others) would run Hertz under a manifest that says Hooke: every command that
// reads the case refuses it, naming both models, and nothing runs.
TEST_F(Safety, ADeckWhoseContactModelIsNotTheManifestsIsRefused) {
  std::string tmpl = read_bytes(fs::path(GRANSTACK_SOURCE_DIR) / "templates/in.granstack.tmpl");
  const auto at = tmpl.find("{{contact_model}}");
  ASSERT_NE(at, std::string::npos);
  tmpl.replace(at, std::string("{{contact_model}}").size(), "model hertz tangential history");
  std::ofstream(path("old.tmpl")) << tmpl;
  ASSERT_EQ(granstack({"generate", "-o", path("case").string(), "--blocks", "1", "--normal-model", "hooke", "--template",
                       path("old.tmpl").string()}).code, 0);
  const auto r = granstack({"run", path("case").string()});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "the deck's contact model is 'model hertz tangential history', the manifest's is 'model hooke "
                     "tangential history'");
  EXPECT_FALSE(fs::exists(path("case/log.liggghts")));
}

// --liggghts names a program as the user sees it from where they run granstack, not from the
// case directory LIGGGHTS starts in; a file that is not executable is named as such.
TEST_F(Safety, TheLiggghtsPathIsTheCallersAndIsChecked) {
  ASSERT_EQ(granstack({"generate", "-o", path("case").string(), "--blocks", "1"}).code, 0);
  fs::create_directories(path("bin"));
  fs::create_symlink(os::find_program("liggghts").value(), path("bin/my-liggghts"));
  auto r = granstack({"run", "--liggghts", "bin/my-liggghts", "case"});
  EXPECT_EQ(r.code, 0) << r.output;
  r = granstack({"run", "--force", "--liggghts", "/etc/passwd", "case"});
  EXPECT_EQ(r.code, 1) << r.output;
  expect_contains(r, "--liggghts /etc/passwd: not an executable file");
}

}  // namespace

