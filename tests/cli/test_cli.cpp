// The granstack program as a user meets it: exit codes, messages that name the problem and
// the fix, nothing written or lost on bad input, and bad dump files on real LIGGGHTS output.
#include "../support/scratch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string output;  // stdout and stderr
};

// Runs a shell command, capturing stdout and stderr.
Result shell(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  Result r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

Result granstack(const std::string& args) { return shell(std::string(GRANSTACK_EXE) + " " + args); }

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = granstack::test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / ("cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

void expect_contains(const Result& r, const std::string& words) {
  EXPECT_NE(r.output.find(words), std::string::npos) << "missing '" << words << "' in:\n" << r.output;
}

std::string read_bytes(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Replaces the case's dump with `content` and reduces the case.
Result reduce_with_dump(const std::string& case_dir, const std::string& dump, const std::string& content) {
  std::ofstream(dump, std::ios::binary) << content;
  return granstack("reduce " + case_dir);
}

TEST_F(Cli, InvalidSpecsExitWith2NameTheFieldAndWriteNothing) {
  struct Bad {
    std::string flags;
    std::string words;
  };
  const Bad cases[] = {
      {"--blocks 0", "blocks: 0 must be a whole number from 1 to 16"},
      {"--restitution 1.5", "restitution: 1.5 must be in (0.05, 1]"},
      {"--restitution 1,0.01", "restitution: 0.01 must be in (0.05, 1] (in the sweep case e0.01)"},
      {"--top-columns 3", "top_columns: 3 must be an even number"},
      {"--materials steel,wood --blocks 2", "unknown material 'wood'"},
      {"--bottom floor", "bottom: 'floor' is not 'free' or 'wall'"},
      {"--dt -1", "dt: -1 must be > 0"},
      {"--blocks two", "blocks: 'two' is not a number"},
      {"--custom-material foam:1:2", "is not NAME:DENSITY:YOUNGS_MODULUS:POISSON_RATIO"},
      {"--restitution-pair steel=0.5", "is not MATERIAL_A:MATERIAL_B=VALUE"},
      {"--geometry cube", "geometry: 'cube' is not 'strip', 'nested3d' or 'panels'"},
      // Blocks of 4 x 4 to 1024 x 1024 columns of 8 layers: refused with the memory it would take.
      {"--geometry nested3d --blocks 9 --top-columns 4", "this stack would have 1.12e+07 spheres, more than the 4000000"},
      {"--geometry nested3d --blocks 9 --top-columns 4", "refsim alone would need about 16.8 GB"},
      // The container's fields belong to the container; in range there.
      {"--panels 3", "panels: applies to geometry = panels only (this spec's geometry is strip)"},
      {"--geometry nested3d --separator walls", "separator: applies to geometry = panels only"},
      {"--matrix-material steel", "matrix_material: applies to geometry = panels only"},
      {"--impact-panel 2", "impact_panel: applies to geometry = panels only"},
      {"--geometry panels", "panels: 0 must be in [2, 64]"},
      {"--geometry panels --panels 3 --impact-panel 4", "impact_panel: 4 must be in [1, 3]"},
      {"--geometry panels --panels 3 --impact-panel -2", "or 'all' (a striker on every panel)"},
      {"--geometry panels --panels 3 --impact-panel all --striker-radius-ratio 2", "strikers wider than the top spheres"},
      {"--geometry panels --panels 3 --separator foam", "separator: 'foam' is not 'matrix', 'walls' or 'none'"},
      {"--geometry panels --panels 3 --matrix-material cork", "matrix_material: unknown material 'cork'"},
      {"--geometry panels --panels 3 --separator walls --matrix-material steel",
       "matrix_material: applies to separator = matrix only (this spec's separator is walls)"},
      {"--geometry panels --panels 3 --gravity", "gravity: the matrix's chains hang between the panels"},
      // A run that stops at the blow's end (#32): no end with gravity, no duration of its own, a cap that can end a blow.
      {"--stop impact", "stop: 'impact' is not 'duration' or 'blow_end'"},
      {"--stop blow_end --gravity", "stop: with gravity the stack comes to rest on its support"},
      {"--stop blow_end --duration 1e-3", "duration: a run that stops at the blow's end lasts until then"},
      {"--stop blow_end --cap-durations 1.5", "cap_durations: 1.5 must be in [2, 1000]"},
      {"--cap-durations 40", "cap_durations: caps a run that stops at the blow's end: give it with stop = 'blow_end'"},
      // Its cost is its cap's, and the message says so and how to lower it.
      {"--geometry nested3d --blocks 4 --top-columns 4 --stop blow_end",
       "if it runs to its cap of 20 automatic durations (it stops at its blow's end, often far sooner"},
  };
  for (const auto& c : cases) {
    const auto r = granstack("generate -o " + path("case") + " " + c.flags);
    EXPECT_EQ(r.code, 2) << c.flags << "\n" << r.output;
    expect_contains(r, c.words);
    EXPECT_FALSE(fs::exists(path("case"))) << c.flags;
  }
  EXPECT_TRUE(fs::is_empty(dir_));  // not even a temporary directory is left
}

TEST_F(Cli, SpecFileErrorsNameFileLineAndField) {
  std::ofstream(path("typo.toml")) << "blocks = 2\nrestitushun = 0.9\n";
  auto r = granstack("generate -o " + path("case") + " --config " + path("typo.toml"));
  EXPECT_EQ(r.code, 2);
  expect_contains(r, "restitushun: unknown field");
  expect_contains(r, "line 2");
  std::ofstream(path("syntax.toml")) << "blocks = [1, 2\n";
  r = granstack("generate -o " + path("case") + " --config " + path("syntax.toml"));
  EXPECT_EQ(r.code, 2);
  expect_contains(r, "syntax.toml:");
  expect_contains(r, "TOML syntax error");
  EXPECT_FALSE(fs::exists(path("case")));
}

TEST_F(Cli, FlagsOverrideTheSpecFile) {
  std::ofstream(path("spec.toml")) << "blocks = 3\nrestitution = 0.9\n";
  const auto r = granstack("generate -o " + path("case") + " --config " + path("spec.toml") + " --blocks 1");
  ASSERT_EQ(r.code, 0) << r.output;
  expect_contains(r, "17 spheres");
  const std::string text = read_bytes(path("case/manifest.json"));
  EXPECT_NE(text.find("\"restitution\": 0.9"), std::string::npos);
  EXPECT_NE(text.find("\"--blocks\""), std::string::npos);  // the exact command line is recorded
}

TEST_F(Cli, AnExistingCaseIsKeptUnlessForced) {
  ASSERT_EQ(granstack("generate -o " + path("case") + " --blocks 1").code, 0);
  std::ofstream(path("case/notes.txt")) << "mine";
  const auto r = granstack("generate -o " + path("case") + " --blocks 2");
  EXPECT_EQ(r.code, 3);
  expect_contains(r, "pass --force");
  EXPECT_TRUE(fs::exists(path("case/notes.txt")));
  // --force replaces only what granstack wrote: the user's notes are named, and kept.
  const auto forced = granstack("generate -o " + path("case") + " --blocks 2 --force");
  EXPECT_EQ(forced.code, 3);
  expect_contains(forced, "notes.txt");
  EXPECT_TRUE(fs::exists(path("case/notes.txt")));
  fs::remove(path("case/notes.txt"));
  EXPECT_EQ(granstack("generate -o " + path("case") + " --blocks 2 --force").code, 0);
}

// decompose says each grid's loads of a case and which one run --np takes; a --grid whose
// product is not --np is refused before anything runs.
TEST_F(Cli, DecomposeSaysTheGridsAndABadGridIsRefusedBeforeAnyRun) {
  auto r = granstack("decompose " + dir_.string());
  EXPECT_EQ(r.code, 4);
  expect_contains(r, "holds no manifest.json: it is not a case directory; make one with 'granstack generate -o DIR'");
  ASSERT_EQ(granstack("generate -o " + path("nest") + " --geometry nested3d --blocks 2 --top-columns 4 --rows 4").code, 0);
  r = granstack("decompose " + path("nest") + " --np 4 8 --grids 2");
  EXPECT_EQ(r.code, 0) << r.output;
  expect_contains(r, "<- run --np chooses");
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 7) << r.output;  // title, header, 2 x 2 grids, note
  for (const auto* grid : {"2,2", "2,2,2", "0,4,1", "2x2x1x1", "a,b,c"}) {
    r = granstack("run --np 4 --grid " + std::string(grid) + " " + path("nest"));
    EXPECT_EQ(r.code, 2) << grid << ": " << r.output;
    expect_contains(r, "whose product is --np (4)");
  }
  EXPECT_FALSE(fs::exists(path("nest") + "/run.json"));
}

TEST_F(Cli, ReduceAndRunRefuseWhatIsNotACaseOrNotRun) {
  auto r = granstack("reduce " + dir_.string());
  EXPECT_EQ(r.code, 4);
  expect_contains(r, "it is not a case directory");
  ASSERT_EQ(granstack("generate -o " + path("case") + " --blocks 1").code, 0);
  r = granstack("reduce " + path("case"));
  EXPECT_EQ(r.code, 1);
  expect_contains(r, "has not been run; run 'granstack run");
  r = granstack("run " + path("case") + " --liggghts /nonexistent/liggghts");
  EXPECT_EQ(r.code, 1);
  expect_contains(r, "--liggghts /nonexistent/liggghts: not an executable file");
  r = granstack("run " + path("case") + " --liggghts /etc/passwd");
  EXPECT_EQ(r.code, 1);
  expect_contains(r, "--liggghts /etc/passwd: not an executable file");
  r = granstack("run " + path("case") + " --liggghts no-such-liggghts");
  EXPECT_EQ(r.code, 1);
  expect_contains(r, "is not on PATH: install it with scripts/setup.sh");
  r = granstack("run --np 0 " + path("case"));
  EXPECT_EQ(r.code, 2);
  r = granstack("--version");
  EXPECT_EQ(r.code, 0);
  expect_contains(r, "granstack 0.1.0");
}

// Bad dump files, made from a real LIGGGHTS run.
TEST_F(Cli, BadDumpFilesGiveClearErrors) {
  ASSERT_EQ(granstack("generate -o " + path("case") + " --blocks 1").code, 0);
  ASSERT_EQ(granstack("run " + path("case")).code, 0);
  const auto dump = path("case/dumps/dump.txt");
  const std::string text = read_bytes(dump);
  auto with_dump = [&](const std::string& content) { return reduce_with_dump(path("case"), dump, content); };
  // Cut in the middle of the last frame: the run finished, so a frame missing is damage.
  auto r = with_dump(text.substr(0, text.size() - 700));
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "file ends inside the frame at step");
  expect_contains(r, "the dump holds 216 complete frames of the 217 the run wrote");
  // An atom missing from a frame (lost, or another case's dump).
  const auto atoms_line = text.find("ITEM: NUMBER OF ATOMS\n17\n");
  ASSERT_NE(atoms_line, std::string::npos);
  std::string fewer = text;
  fewer.replace(atoms_line, 25, "ITEM: NUMBER OF ATOMS\n16\n");
  fewer.erase(fewer.find("\n17 ", atoms_line) + 1, fewer.find('\n', fewer.find("\n17 ", atoms_line) + 1) - fewer.find("\n17 ", atoms_line));
  r = with_dump(fewer);
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "has 16 atoms, the case has 17 spheres");
  // ... and the file cut short too, in the same piece: each frame is analysed as the next is
  // parsed, and the frame that cannot be analysed, earlier in the file, is the error.
  r = with_dump(fewer.substr(0, fewer.size() - 700));
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "has 16 atoms, the case has 17 spheres");
  // Random bytes, an empty file, and a NaN.
  r = with_dump(std::string("\x7f\x45\x4c\x46\x02\x01\x01\0\0\0garbage", 17));
  EXPECT_EQ(r.code, 4);
  expect_contains(r, "binary data where a text dump was expected");
  r = with_dump("");
  EXPECT_EQ(r.code, 4);
  expect_contains(r, "empty file");
  fs::remove(dump);
  r = granstack("reduce " + path("case"));
  EXPECT_EQ(r.code, 4);
  expect_contains(r, "dumps/dump.txt: is missing");
}

// validate on the small stacks, elastic, damped, frictional, with walls and gravity, strips,
// 3D nests (walls on four sides) and containers (a matrix; rigid separators; a striker on every
// panel): they agree to
// round-off (at most 4.0e-16 measured; gated at 1e-14) and so at the default tolerance; a
// tolerance below round-off fails with its own exit code.
TEST_F(Cli, ValidateFindsLiggghtsAndRefsimAgreeToRoundOffOnSmallStacks) {
  struct Set {
    const char* dir;
    const char* flags;
    std::size_t cases;
  };
  const Set sets[] = {
      {"sweep", "--blocks 1,2 --restitution 1,0.9 --friction 0,0.25", 8},
      {"walls", "--blocks 1,2 --restitution 0.9 --friction 0.25 --bottom wall --sides wall --gravity", 2},
      {"nests", "--geometry nested3d --blocks 1,2 --rows 3 --restitution 1,0.9 --friction 0,0.25 --sides wall --bottom wall "
                "--gravity", 8},
      {"containers", "--geometry panels --panels 3 --blocks 1,2 --rows 3 --restitution 1,0.9 --friction 0,0.25", 8},
      {"separators", "--geometry panels --panels 2 --blocks 2 --rows 3 --restitution 0.9 --friction 0.25 --separator walls "
                     "--sides wall --bottom wall --gravity", 1},
      {"struck", "--geometry panels --panels 3 --blocks 2 --rows 3 --impact-panel all --restitution 0.9 --friction 0.25", 1},
  };
  for (const auto& set : sets) {
    const std::string dir = set.dir;
    ASSERT_EQ(granstack("generate -o " + path(dir) + " " + set.flags).code, 0) << dir;
    const auto r = granstack("validate -j 2 --tolerance 1e-14 " + path(dir));
    EXPECT_EQ(r.code, 0) << r.output;
    std::size_t agree = 0;
    for (auto pos = r.output.find("\nagree: "); pos != std::string::npos; pos = r.output.find("\nagree: ", pos + 1)) ++agree;
    EXPECT_EQ(agree, set.cases) << r.output;
    expect_contains(r, "the tolerance 1e-14");
    EXPECT_EQ(r.output.find("OVER"), std::string::npos) << r.output;
  }
  const auto strict = granstack("validate --tolerance 1e-30 " + path("sweep") + "/nb2_e0.9_mu0.25");
  EXPECT_EQ(strict.code, 5) << strict.output;
  expect_contains(strict, "DISAGREE: largest difference");
}

TEST_F(Cli, TableAndPlotsFromARealSweep) {
  ASSERT_EQ(granstack("generate -o " + path("sweep") + " --blocks 1,2,3 --restitution 1,0.9 --rows 4").code, 0);
  ASSERT_EQ(granstack("run -j 2 " + path("sweep")).code, 0);
  auto r = granstack("table " + path("sweep") + " -o " + path("table"));
  EXPECT_EQ(r.code, 0) << r.output;
  expect_contains(r, "| N_B | e=1 | e=0.9 |");
  expect_contains(r, "| e=0.9 | 3 |");
  for (const char* f : {"table/table.md", "table/table.csv", "table/fits.csv"}) EXPECT_TRUE(fs::exists(path(f))) << f;
  for (const char* format : {"png", "svg"}) {
    r = granstack(std::string("plot ") + path("sweep") + " -o " + path(format) + " --format " + format);
    ASSERT_EQ(r.code, 0) << r.output;
    for (const std::string& name : {std::string("decay"), std::string("energy_nb3_e0.9")}) {
      for (const std::string& ext : {std::string(".") + format, std::string(".gp"), std::string(".dat")}) {
        EXPECT_TRUE(fs::exists(path(format) + "/" + name + ext)) << name << ext;
      }
    }
  }
  std::ifstream png(path("png/decay.png"), std::ios::binary);
  std::string magic(8, '\0');
  png.read(magic.data(), 8);
  EXPECT_EQ(magic, std::string("\x89PNG\r\n\x1a\n", 8));
  const std::string text = read_bytes(path("svg/decay.svg"));
  EXPECT_NE(text.find("<svg"), std::string::npos);
  // The figures' scripts: a one-block title in the singular, keys that cover no curve, group
  // names printed as they are (no subscripts from '_'), head room above a curve reaching 1.
  const auto one = read_bytes(path("png/energy_nb1_e1.gp"));
  EXPECT_NE(one.find("Kinetic energy per block\\n1 block, e = 1, μ = 0"), std::string::npos) << one;
  EXPECT_NE(one.find("set key outside right top"), std::string::npos);
  EXPECT_NE(one.find("set offsets 0, 0, graph 0.08, 0"), std::string::npos);
  const auto decay = read_bytes(path("png/decay.gp"));
  EXPECT_NE(decay.find("set key below"), std::string::npos);
  EXPECT_NE(decay.find("title 'e=0.9' noenhanced"), std::string::npos) << decay;
}

TEST_F(Cli, ProgressShowsOnATerminalAndStaysQuietOtherwise) {
  // A run long enough for several progress updates (about a second).
  ASSERT_EQ(granstack("generate -o " + path("case") + " --blocks 4 --dt 2e-8").code, 0);
  // script(1) gives the program a terminal.
  const auto tty = shell("script -qec '" + std::string(GRANSTACK_EXE) + " run " + path("case") + "' /dev/null");
  EXPECT_EQ(tty.code, 0) << tty.output;
  expect_contains(tty, "run: 0/1 cases finished | case step ");
  expect_contains(tty, "ETA");
  const auto piped = granstack("run --force " + path("case"));
  EXPECT_EQ(piped.code, 0);
  EXPECT_EQ(piped.output.find("ETA"), std::string::npos) << piped.output;
  EXPECT_EQ(piped.output.find('\r'), std::string::npos);
}

// Users compress dumps with gzip or zstd; reduce reads them (found as dump.txt.gz / .zst) and
// gives exactly the uncompressed result.
TEST_F(Cli, CompressedDumpsReduceToTheSameResult) {
  for (const std::string format : {"text", "binary"}) {
    const auto dir = path("case_" + format);
    ASSERT_EQ(granstack("generate -o " + dir + " --blocks 2 --dump-format " + format).code, 0);
    ASSERT_EQ(granstack("run " + dir).code, 0);
    const auto plain = granstack("reduce --json " + dir);
    ASSERT_EQ(plain.code, 0) << plain.output;
    const auto dump = dir + (format == "text" ? "/dumps/dump.txt" : "/dumps/dump.bin");
    for (const std::string tool : {"gzip", "zstd -q"}) {
      ASSERT_EQ(shell(tool + " -k " + dump).code, 0);
      fs::rename(dump, dump + ".orig");
      const auto packed = granstack("reduce --json " + dir);
      EXPECT_EQ(packed.code, 0) << packed.output;
      EXPECT_EQ(packed.output, plain.output) << tool;
      fs::rename(dump + ".orig", dump);
      fs::remove(dump + ".gz");
      fs::remove(dump + ".zst");
    }
  }
  // A gzip file cut short: an error naming the cut frame and the frames missing.
  const auto dump = path("case_text/dumps/dump.txt");
  ASSERT_EQ(shell("gzip -c " + dump + " | head -c 100000 > " + dump + ".gz").code, 0);
  fs::rename(dump, dump + ".orig");
  auto r = granstack("reduce " + path("case_text"));
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "file ends inside the frame at step");
  expect_contains(r, "complete frames of the");
  // Damaged compressed data: a clear error.
  ASSERT_EQ(shell("gzip -c " + dump + ".orig > " + dump + ".gz && printf 'garbage!garbage!' | dd of=" + dump +
                  ".gz bs=1 seek=5000 conv=notrunc status=none").code,
            0);
  r = granstack("reduce " + path("case_text"));
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "corrupt gzip data");
}

// LIGGGHTS's '*' (a file per step) and '%' (a file per MPI rank) dumps, from real runs on two
// ranks, reduce to exactly the single file's result; refsim writes the same layouts.
TEST_F(Cli, PerStepAndPerRankDumpsReduceToTheSingleFilesResult) {
  std::map<std::string, std::string> fraction;
  for (const std::string files : {"single", "per_step", "per_rank"}) {
    const auto dir = path(files);
    ASSERT_EQ(granstack("generate -o " + dir + " --blocks 2 --dump-files " + files).code, 0);
    const auto run = granstack("run --np 2 " + dir);
    ASSERT_EQ(run.code, 0) << run.output;
    const auto r = granstack("reduce --json " + dir);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("\"warnings\":[]"), std::string::npos) << files << r.output.substr(0, 400);
    const auto at = r.output.find("\"output_fraction\":");
    fraction[files] = r.output.substr(at, r.output.find(',', at) - at);
  }
  EXPECT_EQ(fraction["per_step"], fraction["single"]);
  EXPECT_EQ(fraction["per_rank"], fraction["single"]);
  EXPECT_GT(std::distance(fs::directory_iterator(path("per_step/dumps")), fs::directory_iterator()), 100);
  EXPECT_TRUE(fs::exists(path("per_rank/dumps/dump.1.txt")));
  const auto v = granstack("validate " + path("per_step"));
  EXPECT_EQ(v.code, 0) << v.output;
  // A rank's file missing its last piece: an error, since the run wrote it.
  ASSERT_EQ(shell("head -n -30 " + path("per_rank/dumps/dump.1.txt") + " > " + path("cut.txt") + " && mv " + path("cut.txt") +
                  " " + path("per_rank/dumps/dump.1.txt")).code,
            0);
  const auto cut = granstack("reduce " + path("per_rank"));
  EXPECT_EQ(cut.code, 4) << cut.output;
  expect_contains(cut, "complete frames of the");
}

TEST_F(Cli, BadBinaryDumpsGiveClearErrors) {
  ASSERT_EQ(granstack("generate -o " + path("case") + " --blocks 1 --dump-format binary").code, 0);
  ASSERT_EQ(granstack("run " + path("case")).code, 0);
  const auto dump = path("case/dumps/dump.bin");
  const std::string bytes = read_bytes(dump);
  auto with_dump = [&](const std::string& content) { return reduce_with_dump(path("case"), dump, content); };
  auto r = with_dump(bytes.substr(0, bytes.size() - 1000));
  EXPECT_EQ(r.code, 4) << r.output;
  expect_contains(r, "file ends inside frame");
  expect_contains(r, "complete frames of the");
  r = with_dump("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n17\n");
  EXPECT_EQ(r.code, 4);
  expect_contains(r, "this is a text dump, not a binary one");
  std::string corrupt = bytes;
  corrupt[9] = '\x7f';  // the atom count's high bytes
  corrupt[13] = '\x7f';
  r = with_dump(corrupt);
  EXPECT_EQ(r.code, 4);
  expect_contains(r, "impossible header");
  r = with_dump(std::string(40, '\xff'));
  EXPECT_EQ(r.code, 4);
}

}  // namespace
