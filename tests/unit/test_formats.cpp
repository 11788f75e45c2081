// File formats: the data file and the manifest round-trip exactly; the dump, series and log
// readers accept what LIGGGHTS writes and name the problem in what it does not.
#include <granstack/formats/batches.hpp>
#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/data_file.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/log.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/stack.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>
#include <fcntl.h>
#include <sys/stat.h>

#include "../support/read_both_ways.hpp"

using namespace granstack;
namespace fs = std::filesystem;

namespace {

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("granstack_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const auto p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  fs::path dir_;
};

using DataFileTest = TempDir;

TEST_F(DataFileTest, RoundTripsEveryDoubleExactly) {
  model::StackSpec s;
  s.blocks = 3;
  s.top_columns = 4;
  s.bottom_radius = 0.7e-3;  // not a power of two: coordinates have long decimal expansions
  s.striker_speed = 0.3;
  s.materials = {"steel", "teflon", "steel"};
  const auto stack = model::Stack::build(s);
  const auto data = generator::data_file(stack, "roundtrip");
  const auto path = write("data.stack", formats::format_data_file(data));
  const auto back = formats::parse_data_file(path);
  EXPECT_EQ(back, data);
  ASSERT_EQ(back.atoms.size(), stack.spheres().size());
  EXPECT_EQ(back.atoms[0].vz, -0.3);
  EXPECT_EQ(back.atoms[5].density, 8000.0);
  EXPECT_EQ(back.atom_types, 4);
}

TEST_F(DataFileTest, MalformedFilesAreRejectedWithTheLine) {
  const auto path = write("bad.data", "title\n\n2 atoms\n1 atom types\n\nAtoms\n\n1 1 0.002 8000 0 0 0\n2 1 0.002 x 0 0 0\n");
  try {
    formats::parse_data_file(path);
    FAIL();
  } catch (const formats::FormatError& e) {
    EXPECT_EQ(e.line(), 9);
    EXPECT_NE(std::string(e.what()).find("'x' is not a number"), std::string::npos);
  }
  EXPECT_THROW(formats::parse_data_file(write("short.data", "t\n\n3 atoms\n1 atom types\n\nAtoms\n\n1 1 1 1 0 0 0\n")),
               formats::FormatError);
  EXPECT_THROW(formats::parse_data_file(write("empty.data", "")), formats::FormatError);
}

// A big file is parsed in pieces on several threads: the same atoms, and the same first error
// (a line-by-line reading's: the earliest failing line, a repeated id before a later bad line).
TEST_F(DataFileTest, PiecesOnSeveralThreadsGiveTheSameAtomsAndTheSameFirstError) {
  model::StackSpec s;
  s.geometry = model::Geometry::nested3d;
  s.blocks = 4;
  s.top_columns = 4;
  s.rows = 8;
  const auto data = generator::data_file(model::Stack::build(s), "pieces");
  ASSERT_GT(data.atoms.size(), 10000u);
  const auto text = formats::format_data_file(data);
  const auto path = write("data.stack", text);
  EXPECT_EQ(formats::parse_data_file(path, 4), data);
  // Ids in another order (not 1..N): looked up, not indexed.
  auto shuffled = data;
  std::reverse(shuffled.atoms.begin(), shuffled.atoms.end());
  EXPECT_EQ(formats::parse_data_file(write("reversed.stack", formats::format_data_file(shuffled)), 4), shuffled);
  const auto error = [&](const std::string& name, const std::string& bad_text, int threads) {
    try {
      formats::parse_data_file(write(name, bad_text), threads);
    } catch (const formats::FormatError& e) {
      return std::make_pair(e.line(), e.message());
    }
    return std::make_pair(0L, std::string("no error"));
  };
  // Line L of the file, counted from 1.
  const auto line_start = [&](const std::string& t, long line) {
    std::size_t at = 0;
    for (long k = 1; k < line; ++k) at = t.find('\n', at) + 1;
    return at;
  };
  auto bad = text;
  const auto late = line_start(bad, 9000);
  bad.replace(late, bad.find(' ', late) - late, "x1");  // a Velocities or Atoms id that is no number
  auto twice = bad;
  const auto early = line_start(twice, 5000);
  twice.replace(early, twice.find(' ', early) - early, "1");  // atom id 1 again
  for (const auto& [name, t] : {std::make_pair("bad", bad), std::make_pair("twice", twice)}) {
    const auto one = error(std::string(name) + "1", t, 1);
    EXPECT_NE(one.first, 0) << one.second;
    EXPECT_EQ(error(std::string(name) + "4", t, 4), one) << name;
  }
  EXPECT_EQ(error("twice1", twice, 1).second, "atom id 1 appears twice");
}

TEST(Manifest, SpecRoundTripsThroughJson) {
  model::StackSpec s;
  s.blocks = 3;
  s.materials = {"steel", "foam", "teflon"};
  s.custom_materials = {{"foam", 30.0, 2e6, 0.1, {}}};
  s.restitution = {0.9, {}};
  s.restitution.set("steel", "teflon", 0.8);
  s.friction.set("foam", "steel", 0.3);
  s.bottom = model::Boundary::wall;
  s.wall_material = "steel";
  s.gravity = 9.81;
  s.dt = 1e-8;
  s.dump_every = 10;
  s.dump_format = model::DumpFormat::binary;
  const auto j = formats::spec_to_json(s);
  EXPECT_EQ(formats::spec_from_json(nlohmann::json::parse(j.dump()), "test"), s);
  auto broken = j;
  broken.erase("rows");
  EXPECT_THROW(formats::spec_from_json(broken, "test"), formats::FormatError);
}

// The contact model is written only when it is not the study's, so the study's cases keep the
// manifests (and digests) they had; another model round-trips, and a wrong name is refused.
TEST(Manifest, TheContactModelIsWrittenWhenItIsNotTheStudys) {
  model::StackSpec s;
  const auto study = formats::spec_to_json(s);
  for (const char* key : {"normal_model", "tangential_model", "rolling_model", "rolling_friction", "characteristic_velocity"}) {
    EXPECT_FALSE(study.contains(key)) << key;
  }
  s.normal_model = model::NormalModel::hooke;
  s.tangential_model = model::TangentialModel::no_history;
  s.rolling_model = model::RollingModel::epsd2;
  s.rolling_friction = {0.05, {}};
  s.rolling_friction.set("steel", "steel", 0.1);
  s.characteristic_velocity = 0.7;
  const auto j = formats::spec_to_json(s);
  EXPECT_EQ(formats::spec_from_json(nlohmann::json::parse(j.dump()), "test"), s);
  auto broken = j;
  broken["normal_model"] = "hertzian";
  EXPECT_THROW(formats::spec_from_json(broken, "test"), formats::FormatError);
}

using DumpTest = TempDir;

const char* kFrame0 =
    "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS mm mm mm\n-1 1\n-1 1\n-1 1\n"
    "ITEM: ATOMS vx id type x \n0.5 2 1 1e-3 \n-0.25 1 1 -1e-3 \n";
const char* kFrame1 =
    "ITEM: TIMESTEP\n10\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS mm mm mm\n-1 1\n-1 1\n-1 1\n"
    "ITEM: ATOMS vx id type x \nnan 2 1 1e-3 \n-inf 1 1 -1e-3 \n";

TEST_F(DumpTest, ReadsFramesWithColumnsInAnyOrder) {
  formats::TextDumpReader reader(write("d.txt", std::string(kFrame0) + kFrame1));
  formats::DumpFrame f;
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(f.step, 0);
  EXPECT_EQ(f.box_flags, "mm mm mm");
  ASSERT_EQ(f.column("id"), 1);
  EXPECT_EQ(f.at(1, f.column("vx")), -0.25);
  EXPECT_EQ(f.at(0, f.column("x")), 1e-3);
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(f.step, 10);
  EXPECT_TRUE(std::isnan(f.at(0, 0)));  // what LIGGGHTS writes when a run blows up
  EXPECT_TRUE(std::isinf(f.at(1, 0)));
  EXPECT_FALSE(reader.next(f));
  EXPECT_EQ(reader.frames_read(), 2);
}

TEST_F(DumpTest, TruncatedLastFrameIsReportedApartFromTheCompleteOnes) {
  std::string text = std::string(kFrame0) + kFrame1;
  text.resize(text.size() - 12);
  formats::TextDumpReader reader(write("d.txt", text));
  formats::DumpFrame f;
  ASSERT_TRUE(reader.next(f));
  try {
    reader.next(f);
    FAIL();
  } catch (const formats::TruncatedError& e) {
    EXPECT_NE(std::string(e.what()).find("step 10"), std::string::npos) << e.what();
  }
}

TEST_F(DumpTest, MalformedInputNamesFileLineAndProblem) {
  auto expect_error = [&](const std::string& text, const std::string& words) {
    const auto path = write("bad.txt", text);
    try {
      formats::TextDumpReader reader(path);
      formats::DumpFrame f;
      while (reader.next(f)) {
      }
      ADD_FAILURE() << "no error for: " << words;
    } catch (const formats::FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expect_error("", "empty file");
  expect_error(std::string(kFrame1) + kFrame0, "timesteps go backwards");
  std::string bad_number = kFrame0;
  bad_number.replace(bad_number.find("0.5"), 3, "0.x");
  expect_error(bad_number, "'0.x' in column 'vx'");
  std::string short_row = kFrame0;
  short_row.replace(short_row.find("0.5 2"), 5, "2");
  expect_error(short_row, "has 3 values, the header names 4 columns");
  expect_error(std::string("\x01\x02\0\0garbage\n", 12), "expected 'ITEM: TIMESTEP'");
}

TEST_F(DumpTest, MissingColumnNamesTheDumpKeyword) {
  formats::TextDumpReader reader(write("d.txt", kFrame0));
  formats::DumpFrame f;
  ASSERT_TRUE(reader.next(f));
  try {
    formats::require_columns(f, {"id", "omegax", "radius"}, "d.txt");
    FAIL();
  } catch (const formats::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("add the keyword(s) 'omegax radius'"), std::string::npos) << e.what();
  }
}

// Regression inputs of the fuzz target (tests/fuzz/regressions): a header announcing a huge
// frame must not be trusted with memory.
TEST(DumpRegressions, HugeAtomCountsInHeadersAreRefusedWithoutAllocatingThem) {
  formats::DumpFrame f;
  try {
    formats::TextDumpReader text(GRANSTACK_FUZZ_REGRESSIONS "/huge_atom_count.txt");
    while (text.next(f)) {
    }
    FAIL();
  } catch (const formats::TruncatedError& e) {
    EXPECT_NE(std::string(e.what()).find("1 of 99999999999 atom lines"), std::string::npos) << e.what();
  }
  const std::vector<std::string> columns(16, "c");
  formats::BinaryDumpReader binary(GRANSTACK_FUZZ_REGRESSIONS "/huge_atom_count.bin", columns);
  EXPECT_THROW(while (binary.next(f)) {}, formats::FormatError);
}

// A data file whose Velocities come before its Atoms (found by the fuzz target) is refused by
// name, as LIGGGHTS's read_data refuses it, on one thread and on several.
// A zstd file whose checksum does not match (a fuzzer's input): the bytes before the error are
// the same whatever a reader asks for at a time (here none: zstd gives nothing of a frame whose
// checksum fails once it fits what is asked of zstd), and then the error comes, naming zstd.
TEST(DumpRegressions, ACorruptZstdFileGivesTheSameBytesBeforeItsErrorAtAnyReadSize) {
  const std::string path = GRANSTACK_FUZZ_REGRESSIONS "/corrupt_zstd_binary_read_as_text.zst";
  std::vector<std::string> seen;
  for (const std::size_t step : {std::size_t{7}, std::size_t{97}, std::size_t{4096}, std::size_t{1} << 18}) {
    auto source = formats::open_bytes(path);
    std::string bytes(step, '\0'), all;
    try {
      for (std::size_t n; (n = source->read(bytes.data(), step)) > 0;) all.append(bytes.data(), n);
      ADD_FAILURE() << "read to the end at " << step << " bytes a time";
    } catch (const formats::FormatError& e) {
      EXPECT_NE(std::string(e.what()).find("corrupt zstd data"), std::string::npos) << e.what();
    }
    std::printf("%zu bytes a read: %zu bytes before the error\n", step, all.size());
    seen.push_back(all);
  }
  for (const auto& s : seen) EXPECT_TRUE(s == seen.front());
}

TEST(DataFileRegressions, VelocitiesBeforeAtomsAreRefused) {
  for (const int threads : {1, 3}) {
    try {
      formats::parse_data_file(GRANSTACK_FUZZ_REGRESSIONS "/velocities_before_atoms.stack", threads);
      FAIL();
    } catch (const formats::FormatError& e) {
      EXPECT_NE(std::string(e.what()).find("a Velocities section before the Atoms section"), std::string::npos) << e.what();
    }
  }
}

// A dump of `frames` frames of `atoms` atoms as DumpWriter (and LIGGGHTS) writes it.
std::string dump_text(int frames, int atoms) {
  formats::DumpFrame f;
  f.atoms = atoms;
  f.box_flags = "mm mm mm";
  f.box = {-1, 1, -1, 1, -1, 1};
  f.columns = {"id", "type", "x", "z", "vx", "vz", "fx"};
  const auto path = fs::temp_directory_path() / ("granstack_dump_text_" + std::to_string(::getpid()));
  {
    formats::DumpWriter w(path.string(), false);
    for (int k = 0; k < frames; ++k) {
      f.step = 10L * k;
      f.values.clear();
      for (int a = 0; a < atoms; ++a) {
        for (double v : {a + 1.0, 1.0, 0.1 * a + 1e-17 * k, -0.3 * k, std::sin(a + k), 0.0, 1.0 / (a + k + 3.0)}) {
          f.values.push_back(v);
        }
      }
      w.write(f);
    }
  }
  const std::string text = formats::read_file(path);
  fs::remove(path);
  return text;
}

using BatchTest = TempDir;

// A frame small enough to sit in the stdio buffer is written out at the close: a full disk
// (/dev/full) must fail there, naming the file, not pass unseen.
TEST(DumpWriter, AWriteThatFailsAtTheCloseIsAnError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "this system has no /dev/full to fill";
  for (const auto& [binary, compressed] : {std::pair{false, false}, std::pair{true, false}, std::pair{true, true}}) {
    formats::DumpWriter w("/dev/full", binary, compressed);
    formats::DumpFrame f;
    f.atoms = 1;
    f.box_flags = "mm mm mm";
    f.box = {-1, 1, -1, 1, -1, 1};
    f.columns = {"id", "x"};
    f.values = {1, 0.5};
    w.write(f);  // 150 bytes: buffered
    try {
      w.close();
      ADD_FAILURE() << "closing a dump on /dev/full succeeded";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "/dev/full: cannot write: No space left on device");
    }
  }
}

// The frames of a dump written in shares (on threads, each share's atoms into a piece of their
// own) are the bytes written in one, however the shares fall from frame to frame: text copied
// from the frame before crosses the pieces that frame was written in.
TEST(DumpWriter, FramesWrittenInSharesAreTheBytesWrittenInOne) {
  const auto in_shares = [](std::vector<std::size_t> cuts) -> formats::ForShares {
    return [cuts](std::size_t count, const std::function<void(std::size_t, std::size_t)>& job) {
      std::vector<std::thread> threads;
      std::size_t begin = 0;
      for (const std::size_t cut : cuts) {
        const std::size_t end = std::min(count, cut);
        threads.emplace_back(job, begin, end);
        begin = end;
      }
      job(begin, count);
      for (auto& t : threads) t.join();
    };
  };
  // Cuts of 40 atoms: three shares, one (none), two uneven, an empty share, and back again.
  const std::vector<formats::ForShares> schedule{in_shares({13, 27}), {}, in_shares({5}), in_shares({0, 20, 20, 39}),
                                                 in_shares({13, 27}), in_shares({13, 27})};
  const auto write = [&](bool split) {
    const auto path = fs::temp_directory_path() / ("granstack_dump_shares_" + std::to_string(::getpid()));
    {
      formats::DumpWriter w(path.string(), false);
      formats::DumpFrame f;
      f.atoms = 40;
      f.box_flags = "mm mm mm";
      f.box = {-1, 1, -1, 1, -1, 1};
      f.columns = {"id", "type", "x", "vx", "fx"};
      for (std::size_t k = 0; k < schedule.size(); ++k) {
        f.step = static_cast<long>(k);
        f.values.clear();
        for (int a = 0; a < f.atoms; ++a) {  // x changes for every third atom, vx every other frame
          const double x = 0.1 * a + (a % 3 == 0 ? 1e-3 * static_cast<double>(k) : 0.0);
          for (double v : {a + 1.0, 1.0, x, std::sin(a + static_cast<double>(k / 2)), 1.0 / (a + static_cast<double>(k) + 3.0)}) f.values.push_back(v);
        }
        w.write(f, split ? schedule[k] : formats::ForShares());
      }
    }
    const std::string text = formats::read_file(path);
    fs::remove(path);
    return text;
  };
  const std::string whole = write(false);
  EXPECT_EQ(std::count(whole.begin(), whole.end(), '\n'), 6 * (9 + 40));
  const std::string split = write(true);
  EXPECT_TRUE(split == whole);
}

// The writer copies a value's text from the frame before when the value is the same to the bit;
// read back, every frame holds exactly the doubles written, -0.0 and the last bit of a changed
// value included, whichever frame they first appeared in.
TEST(DumpWriter, TextReusedFromTheFrameBeforeReadsBackToTheExactDoubles) {
  const auto path = fs::temp_directory_path() / ("granstack_dump_reuse_" + std::to_string(::getpid()));
  std::vector<std::vector<double>> written;
  {
    formats::DumpWriter w(path.string(), false);
    formats::DumpFrame f;
    f.atoms = 3;
    f.box_flags = "mm mm mm";
    f.box = {-1, 1, -1, 1, -1, 1};
    f.columns = {"id", "x", "vx"};
    const double x = 0.1;
    const std::vector<std::vector<double>> frames{{1, x, 0.0, 2, 1e-300, -0.0, 3, 5.0, 1.0 / 3.0},
                                                  {1, x, -0.0, 2, 1e-300, 0.0, 3, 5.0, 1.0 / 3.0},
                                                  {1, std::nextafter(x, 1.0), -0.0, 2, 2e-300, 0.0, 3, 5.0, 2.0 / 3.0},
                                                  {1, x, -0.0, 2, 2e-300, 0.0, 3, 5.0, 2.0 / 3.0}};
    for (std::size_t k = 0; k < frames.size(); ++k) {
      f.step = static_cast<long>(k);
      f.values = frames[k];
      w.write(f);
      written.push_back(frames[k]);
    }
  }
  formats::TextDumpReader reader(path.string());
  formats::DumpFrame f;
  std::size_t k = 0;
  while (reader.next(f)) {
    ASSERT_LT(k, written.size());
    ASSERT_EQ(f.values.size(), written[k].size());
    for (std::size_t i = 0; i < f.values.size(); ++i) {
      EXPECT_EQ(std::memcmp(&f.values[i], &written[k][i], sizeof(double)), 0) << "frame " << k << " value " << i;
    }
    ++k;
  }
  EXPECT_EQ(k, written.size());
  fs::remove(path);
}

// Pieces cut at frame boundaries and parsed apart give what reading the whole file gives, for
// any piece size, including the line numbers and words of every error.
TEST_F(BatchTest, BatchesGiveTheSameFramesAndErrorsAsReadingTheWholeFile) {
  const std::string good = dump_text(40, 17);
  auto check = [&](const std::string& name, const std::string& text, const std::string& expected_error) {
    const auto path = write(name, text);
    const auto whole = test_support::read_whole(path);
    if (expected_error.empty()) {
      EXPECT_EQ(whole.error, "") << name;
      EXPECT_EQ(whole.frames.size(), 40u) << name;
    } else {
      EXPECT_NE(whole.error.find(expected_error), std::string::npos) << name << ": " << whole.error;
    }
    for (const std::size_t bytes : {std::size_t{1}, std::size_t{500}, std::size_t{3000}, std::size_t{1} << 20}) {
      EXPECT_EQ(test_support::difference(whole, test_support::read_in_batches(path, bytes)), "") << name << ", " << bytes << " bytes";
    }
  };
  check("good.txt", good, "");
  std::string crlf;
  for (const char c : good) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  check("crlf.txt", crlf, "");
  // Frame 21 of 40 loses its last atom line: the next frame's header is read as one.
  const auto frame21 = good.find("ITEM: TIMESTEP\n210\n");
  std::string short_frame = good;
  const auto cut_end = short_frame.rfind('\n', frame21 - 1);
  short_frame.erase(short_frame.rfind('\n', cut_end - 1) + 1, cut_end - short_frame.rfind('\n', cut_end - 1));
  check("short_frame.txt", short_frame, "atom line 17 of the frame at step 200 has 2 values");
  std::string bad_number = good;
  bad_number.replace(good.find("\n5 1 ", frame21), 5, "\n5 x ");
  check("bad_number.txt", bad_number, "'x' in column 'type'");
  check("truncated.txt", good.substr(0, good.size() - 30), "file ends inside the frame at step 390");
  check("backwards.txt", good + dump_text(3, 17), "timestep 0 comes after 390");
  check("empty.txt", "", "empty file");
  check("blank.txt", "\n \n", "empty file");
  check("binary.txt", good.substr(0, 900) + std::string(3, '\0') + good.substr(900), "binary data where a text dump");
}

TEST_F(BatchTest, ACompressedDumpIsCutAndParsedTheSameWay) {
  const auto plain = write("dump.txt", dump_text(40, 17));
  ASSERT_EQ(std::system(("gzip -k " + plain).c_str()), 0);
  const auto whole = test_support::read_whole(plain);
  EXPECT_EQ(test_support::difference(whole, test_support::read_in_batches(plain + ".gz", 700)), "");
}

// A compressed binary dump is the plain writer's bytes as zstd frames: decompressed, the same
// file; read by the dump reader and in batches, the same frames; a file per step each its own
// stream; ended by the destructor (a run cut short), still a whole stream.
TEST_F(BatchTest, ACompressedBinaryDumpIsThePlainBytesAsAZstdStream) {
  formats::TextDumpReader text(write("dump.txt", dump_text(40, 17)));
  std::vector<formats::DumpFrame> frames;
  for (formats::DumpFrame f; text.next(f);) frames.push_back(f);
  const auto plain = (dir_ / "plain.bin").string(), packed = (dir_ / "packed.bin").string();
  const auto unclosed = (dir_ / "unclosed.bin").string();
  fs::create_directories(dir_ / "steps");
  {
    formats::DumpWriter a(plain, true), b(packed, true, true), c(unclosed, true, true);
    formats::DumpWriter steps((dir_ / "steps" / "dump*.bin").string(), true, true);
    for (const auto& f : frames) {
      a.write(f);
      b.write(f);
      c.write(f);
      steps.write(f);
    }
    a.close();
    b.close();
    steps.close();
  }  // c: by its destructor
  const auto decompressed = [](const std::string& path) {
    auto source = formats::open_bytes(path);
    EXPECT_STREQ(source->kind(), "zstd") << path;
    std::string out(1 << 16, '\0'), all;
    for (std::size_t n; (n = source->read(out.data(), out.size())) > 0;) all.append(out.data(), n);
    return all;
  };
  const std::string bytes = formats::read_file(plain);
  ASSERT_EQ(bytes.size(), 40u * (44 + 6 * 8 + 3 * 4 + 17 * 7 * 8));  // header, box, three counts, values
  EXPECT_TRUE(decompressed(packed) == bytes);
  EXPECT_TRUE(decompressed(unclosed) == bytes);
  EXPECT_LT(fs::file_size(packed), bytes.size() / 2);  // two of the seven columns are constant
  const std::vector<std::string> columns{"id", "type", "x", "z", "vx", "vz", "fx"};
  formats::BinaryDumpReader reader(packed, columns);
  formats::FrameBatchSource source(packed, true, columns, {}, 3000);
  formats::FrameBatch batch;
  std::size_t k = 0;
  formats::DumpFrame f;
  while (source.take(batch)) {
    source.parse(batch);
    source.settle(batch);
    ASSERT_FALSE(batch.error);
    for (const auto& b : batch.frames) {
      ASSERT_LT(k, frames.size());
      ASSERT_TRUE(reader.next(f));
      EXPECT_EQ(f.values, frames[k].values);
      EXPECT_EQ(b.values, frames[k].values);
      EXPECT_EQ(b.step, frames[k++].step);
    }
  }
  EXPECT_EQ(k, frames.size());
  for (const auto& g : frames) {
    const auto one = (dir_ / "steps" / fmt::format("dump{}.bin", g.step)).string();
    formats::BinaryDumpReader r(one, columns);
    ASSERT_TRUE(r.next(f)) << one;
    EXPECT_EQ(f.values, g.values) << one;
    EXPECT_FALSE(r.next(f)) << one;
  }
}

// A binary dump: headers read in turn, values read (pread) by whichever thread parses the batch;
// batches stay near the size asked for, whatever the number of frames.
TEST_F(BatchTest, BinaryBatchesHoldAFewFramesAndTheSameValues) {
  const auto text_path = write("dump.txt", dump_text(40, 17));
  const auto bin_path = (dir_ / "dump.bin").string();
  {
    formats::TextDumpReader text(text_path);
    formats::DumpWriter writer(bin_path, true);
    formats::DumpFrame f;
    while (text.next(f)) writer.write(f);
  }
  const std::vector<std::string> columns{"id", "type", "x", "z", "vx", "vz", "fx"};
  formats::BinaryDumpReader whole(bin_path, columns);
  formats::FrameBatchSource source(bin_path, true, columns, {}, 3000);  // a frame is 17 x 7 x 8 = 952 bytes
  formats::FrameBatch batch;
  formats::DumpFrame f;
  std::size_t frames = 0, largest = 0;
  while (source.take(batch)) {
    source.parse(batch);
    source.settle(batch);
    ASSERT_FALSE(batch.error);
    largest = std::max(largest, batch.frames.size());
    for (const auto& b : batch.frames) {
      ASSERT_TRUE(whole.next(f));
      EXPECT_EQ(b.step, f.step);
      EXPECT_EQ(b.values, f.values);
      EXPECT_TRUE(b.deferred.empty());
      ++frames;
    }
  }
  EXPECT_EQ(frames, 40u);
  EXPECT_EQ(largest, 4u);  // the fewest frames reaching 3000 bytes
  // Cut short inside the values of frame 39: the 38 frames before it, then the truncation.
  std::filesystem::resize_file(bin_path, std::filesystem::file_size(bin_path) - 1500);
  formats::FrameBatchSource cut(bin_path, true, columns, {}, 3000);
  frames = 0;
  std::string error;
  while (error.empty() && cut.take(batch)) {
    cut.parse(batch);
    cut.settle(batch);
    frames += batch.frames.size();
    try {
      if (batch.error) std::rethrow_exception(batch.error);
    } catch (const formats::TruncatedError& e) {
      error = e.what();
    }
  }
  EXPECT_EQ(frames, 38u);
  EXPECT_NE(error.find("the run was cut short"), std::string::npos) << error;
}

// xxh128_content remembers what it read (a run digests its outputs and reproduce's reduce checks
// them seconds later), but never past a change: the same size and modification time with other
// bytes, a file renamed over it, or a change right after a reading (within the kernel clock's tick)
// each give the new content's digest.
TEST_F(BatchTest, AFileDigestedBeforeIsReadAgainOnceItChanges) {
  const auto of = [](const std::string& bytes) {
    formats::Xxh128 h;
    h.update(bytes.data(), bytes.size());
    return h.hex();
  };
  const auto overwrite = [](const std::string& path, const std::string& bytes) {
    struct stat before {};
    ASSERT_EQ(::stat(path.c_str(), &before), 0);
    std::fstream(path, std::ios::in | std::ios::out | std::ios::binary) << bytes;
    const timespec times[2] = {before.st_atim, before.st_mtim};
    ASSERT_EQ(::utimensat(AT_FDCWD, path.c_str(), times, 0), 0);  // the size and mtime it had
  };
  const std::string a(8192, 'a'), b(8192, 'b'), c(8192, 'c');
  const auto path = write("settled.bin", a);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(formats::xxh128_content(path), of(a));
  EXPECT_EQ(formats::xxh128_content(path), of(a));
  overwrite(path, b);
  EXPECT_EQ(formats::xxh128_content(path), of(b));
  const auto other = write("other.bin", c);
  fs::rename(other, path);
  EXPECT_EQ(formats::xxh128_content(path), of(c));
  const auto fresh = write("fresh.bin", a);
  EXPECT_EQ(formats::xxh128_content(fresh), of(a));
  overwrite(fresh, b);
  EXPECT_EQ(formats::xxh128_content(fresh), of(b));
}

// A plain text dump cut into pieces is digested from the pieces as they are settled, in order:
// the XXH3-128 of the whole file (reduce checks run.json's digest with it instead of reading the
// file twice). A file that grew after it was opened, or a dump not cut into plain pieces, gives
// none, and the caller digests the file itself.
TEST_F(BatchTest, ADumpReadInPiecesIsDigestedAsAWhole) {
  const auto plain = write("dump.txt", dump_text(40, 17));
  auto digest_by_pieces = [&](formats::FrameBatchSource& source, const std::function<void()>& after_first = {}) {
    formats::FrameBatch batch;
    long pieces = 0;
    while (source.take(batch)) {
      source.parse(batch);
      source.settle(batch);
      EXPECT_FALSE(batch.error);
      if (++pieces == 1 && after_first) after_first();
    }
    EXPECT_GT(pieces, 5);  // the test is of many pieces
    return source.content_xxh128();
  };
  formats::FrameBatchSource source(plain, false, {}, {}, 2000);
  ASSERT_TRUE(source.digest_content());
  EXPECT_EQ(digest_by_pieces(source), formats::xxh128_content(plain));
  formats::FrameBatchSource grown(plain, false, {}, {}, 2000);
  ASSERT_TRUE(grown.digest_content());
  EXPECT_EQ(digest_by_pieces(grown, [&] { std::ofstream(plain, std::ios::app) << "\n"; }), std::nullopt);
  const auto gz = plain + ".gz";
  ASSERT_EQ(std::system(("gzip -k " + plain).c_str()), 0);
  formats::FrameBatchSource compressed(gz, false, {}, {}, 2000);
  EXPECT_FALSE(compressed.digest_content());
}

// A piece's frames are handed on one by one as they are parsed (reduce analyses each while its
// values are in the cache): frame k when it is whole and frame k + 1 not yet begun; a false
// answer ends the parsing there, the frames up to it kept and no error of the parser's.
TEST_F(BatchTest, APiecesFramesAreHandedOnAsTheyAreParsed) {
  const auto path = write("dump.txt", dump_text(6, 5));
  formats::FrameBatchSource source(path, false, {});
  formats::FrameBatch batch;
  ASSERT_TRUE(source.take(batch));
  std::vector<long> steps;
  source.parse(batch, [&](std::size_t k) {
    EXPECT_EQ(batch.frames.size(), k + 1);  // frame k + 1 not begun
    EXPECT_EQ(batch.frames[k].values.size(), 5u * 7u);
    steps.push_back(batch.frames[k].step);
    return true;
  });
  ASSERT_FALSE(batch.error);
  EXPECT_EQ(steps, (std::vector<long>{0, 10, 20, 30, 40, 50}));
  formats::FrameBatchSource again(path, false, {});
  ASSERT_TRUE(again.take(batch));
  steps.clear();
  again.parse(batch, [&](std::size_t k) {
    steps.push_back(batch.frames[k].step);
    return k < 2;
  });
  EXPECT_FALSE(batch.error);
  EXPECT_EQ(steps, (std::vector<long>{0, 10, 20}));
  ASSERT_EQ(batch.frames.size(), 3u);
  EXPECT_EQ(batch.frames[2].step, 20);
}

// Only the named columns are converted; the others are checked to be there and left 0.
TEST_F(BatchTest, ColumnsNotAskedForAreLeftUnparsed) {
  formats::FrameBatchSource source(write("dump.txt", dump_text(3, 5)), false, {}, {"id", "x"});
  formats::FrameBatch batch;
  ASSERT_TRUE(source.take(batch));
  source.parse(batch);
  ASSERT_FALSE(batch.error);
  ASSERT_EQ(batch.frames.size(), 3u);
  const auto& f = batch.frames[2];
  EXPECT_EQ(f.at(4, f.column("id")), 5.0);
  EXPECT_DOUBLE_EQ(f.at(4, f.column("x")), 0.4);
  EXPECT_EQ(f.at(4, f.column("vx")), 0.0);
}

// A piece's reader takes the tokens an atom's line shares with its line in the frame before, at
// its start and at its end, from that frame. A middle token that grew or shrank moves the shared
// end: the values stay the exact ones, and a line whose shared end does not line up with its
// tokens (one token more or fewer before it) is the same error as when read whole.
TEST_F(BatchTest, TheEndOfALineItsLastFrameEndedWithIsTakenOnlyWhereItsTokensLineUp) {
  const std::string header = "ITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n-1 1\n-1 1\n-1 1\n"
                             "ITEM: ATOMS id type x z vx vz fx fy fz\n";
  const auto dump = [&](const std::vector<std::string>& first_atom) {
    std::string text;
    for (std::size_t k = 0; k < first_atom.size(); ++k) {
      text += "ITEM: TIMESTEP\n" + std::to_string(10 * k) + "\n" + header + first_atom[k] + "\n2 1 0.5 0.75 0 0 7 8 9\n";
    }
    return text;
  };
  const std::vector<std::string> grows{"1 1 0.5 0.25 0 0 7 8 9", "1 1 0.5 0.125 0 0 7 8 9", "1 1 0.5 2 0 0 7 8 9",
                                       "1 1 0.5 2 -1e-300 0 7 8 9", "1 1 0.5 2 -1e-300 0 7 8 9"};
  const auto path = write("grows.txt", dump(grows));
  const auto whole = test_support::read_whole(path);
  ASSERT_EQ(whole.error, "");
  const auto batches = test_support::read_in_batches(path, std::size_t{1} << 20);
  EXPECT_EQ(test_support::difference(whole, batches), "");
  ASSERT_EQ(batches.frames.size(), grows.size());
  const std::vector<std::vector<double>> z_vx{{0.25, 0.0}, {0.125, 0.0}, {2.0, 0.0}, {2.0, -1e-300}, {2.0, -1e-300}};
  for (std::size_t k = 0; k < grows.size(); ++k) {
    const auto& f = batches.frames[k];
    EXPECT_EQ(f.at(0, f.column("z")), z_vx[k][0]) << "frame " << k;
    EXPECT_EQ(f.at(0, f.column("vx")), z_vx[k][1]) << "frame " << k;
    EXPECT_EQ(f.at(0, f.column("fz")), 9.0) << "frame " << k;
    EXPECT_EQ(f.at(1, f.column("z")), 0.75) << "frame " << k;
  }
  for (const auto& [name, line, error] :
       {std::tuple{"one_more.txt", "1 1 0.5 2 5 0 0 7 8 9", "has 10 values"},
        std::tuple{"one_fewer.txt", "1 1 0.5 0 0 7 8 9", "has 8 values"},
        std::tuple{"joined.txt", "1 1 0.5 20 0 7 8 9", "has 8 values"},
        std::tuple{"word.txt", "1 1 0.5 2 x 0 7 8 9", "'x' in column 'vx'"}}) {
    auto bad = grows;
    bad[3] = line;
    const auto bad_path = write(name, dump(bad));
    const auto bad_whole = test_support::read_whole(bad_path);
    EXPECT_NE(bad_whole.error.find(error), std::string::npos) << name << ": " << bad_whole.error;
    EXPECT_EQ(test_support::difference(bad_whole, test_support::read_in_batches(bad_path, std::size_t{1} << 20)), "") << name;
  }
}

// The text reader vouches for a frame's values being finite (reduce then skips its own check)
// only where it parsed each or took it from a frame it vouched for: an inf, parsed or repeated
// from the frame before, leaves the frame to the check.
TEST_F(BatchTest, AFrameIsVouchedFiniteOnlyWhenEveryValueItHoldsWasCheckedFinite) {
  const std::string header = "ITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n-1 1\n-1 1\n-1 1\nITEM: ATOMS id x vx\n";
  std::string text;
  const std::vector<std::string> lines{"1 0.5 2", "1 0.5 inf", "1 0.5 inf", "1 0.25 inf", "1 0.25 1e999", "1 0.25 3"};
  for (std::size_t k = 0; k < lines.size(); ++k) text += "ITEM: TIMESTEP\n" + std::to_string(k) + "\n" + header + lines[k] + "\n";
  const auto path = write("inf.txt", text);
  // Read whole, no line is compared with the frame before: the last frame is vouched for again.
  const auto whole = test_support::read_whole(path);
  ASSERT_EQ(whole.error, "");
  ASSERT_EQ(whole.frames.size(), lines.size());
  const std::vector<bool> finite{true, false, false, false, false, true};
  for (std::size_t k = 0; k < lines.size(); ++k) {
    EXPECT_EQ(whole.frames[k].finite, finite[k]) << "frame " << k;
    EXPECT_EQ(std::isfinite(whole.frames[k].at(0, 2)), finite[k]) << "frame " << k;
  }
  // In one piece the last frame's line is compared with the frame before, which was not vouched
  // for: neither is it.
  const auto piece = test_support::read_in_batches(path, std::size_t{1} << 20);
  ASSERT_EQ(piece.frames.size(), lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k) EXPECT_EQ(piece.frames[k].finite, k == 0) << "frame " << k;
}

using SeriesTest = TempDir;

TEST_F(SeriesTest, ReadsNamedColumnsAndDropsACutLastRow) {
  const auto s = formats::read_series(write("s.txt", "# step ke_a ke_b\n1 1.5 2\n2 3 4.25\n3 7"));
  ASSERT_EQ(s.rows.size(), 2u);
  EXPECT_EQ(s.column("ke_b"), 2);
  EXPECT_EQ(s.rows[1][2], 4.25);
  EXPECT_THROW(formats::read_series(write("t.txt", "# step a\n1 2 3\n2 3\n")), formats::FormatError);
}

TEST(LogScanner, FindsVersionProgressErrorsAndLoopTime) {
  formats::LogScanner log;
  log.add_text(
      "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, compiled 2022-01-26-19:42:32 by buildd, git commit unknown)\n"
      "    Step    Atoms         KinEng            CPU \n       0        3 1.675e-05 0 \n    1000        3 1.6e-05 0.1 \n"
      "WARNING: time-step is 17.9 % of rayleigh time (./src/fix_check_timestep_gran.cpp:200)\n"
      "Loop time of 1.7712 on 2 procs for 20000 steps with 1024 atoms, finish time Sat Nov 21 23:29:31 2026\n"
      "ERROR: Pair granular with shear history requires newton pair off (./src/pair_gran.cpp:260)\n");
  EXPECT_EQ(log.version(), "LIGGGHTS-PUBLIC 3.8.0, compiled 2022-01-26-19:42:32 by buildd, git commit unknown");
  EXPECT_EQ(log.last_step(), 1000);
  ASSERT_EQ(log.warnings().size(), 1u);
  ASSERT_EQ(log.errors().size(), 1u);
  EXPECT_NE(log.errors()[0].find("newton pair off"), std::string::npos);
  ASSERT_TRUE(log.loop_time());
  EXPECT_EQ(log.loop_time()->seconds, 1.7712);
  EXPECT_EQ(log.loop_time()->procs, 2);
  EXPECT_EQ(log.loop_time()->steps, 20000);
  EXPECT_EQ(log.loop_time()->atoms, 1024);
  // A deck that stops at the blow's end runs a dump interval at a time: its runs are summed.
  log.add_line("Loop time of 0.25 on 2 procs for 8 steps with 1024 atoms, finish time Sat Nov 21 23:29:32 2026");
  EXPECT_EQ(log.loop_time()->seconds, 1.7712 + 0.25);
  EXPECT_EQ(log.loop_time()->steps, 20008);
  EXPECT_FALSE(log.lost_atoms());
  log.add_line("ERROR: Lost atoms: original 241 current 240 (./src/thermo.cpp:442)");
  EXPECT_TRUE(log.lost_atoms());
}

TEST(LogScanner, ReadsTheProcessorGridAndTheAtomsPerRank) {
  formats::LogScanner log;
  log.add_text("  4 by 4 by 1 MPI processor grid\nNlocal:    6120.06 ave 7812 max 4644 min\nHistogram: 4 0 0 0 8 0 0 0 0 4\n"
               "Nghost:    7614.19 ave 11952 max 4140 min\nHistogram: 4 0 0 8 0 0 0 0 0 4\n");
  ASSERT_TRUE(log.processor_grid());
  EXPECT_EQ(*log.processor_grid(), (std::array<int, 3>{4, 4, 1}));
  ASSERT_TRUE(log.owned_per_rank() && log.ghosts_per_rank());
  EXPECT_EQ(log.owned_per_rank()->mean, 6120.06);
  EXPECT_EQ(log.owned_per_rank()->max, 7812);
  EXPECT_EQ(log.owned_per_rank()->min, 4644);
  EXPECT_EQ(log.ghosts_per_rank()->mean, 7614.19);
  EXPECT_EQ(log.ghosts_per_rank()->max, 11952);
}

TEST(LogScanner, QuotesTheFirstAndLastLinesOfTextWithoutBlanksOrRules) {
  formats::LogScanner log;
  log.add_text("-----------\nA call to mkdir was unable\n\n  Directory: /x\n");
  EXPECT_EQ(log.head(), (std::vector<std::string>{"A call to mkdir was unable", "  Directory: /x"}));
  EXPECT_EQ(log.tail(), log.head());
  for (int k = 0; k < 20; ++k) log.add_line(fmt::format("line {}", k));
  ASSERT_EQ(log.head().size(), formats::LogScanner::kQuoteLines);
  EXPECT_EQ(log.head()[1], "  Directory: /x");
  const auto tail = log.tail();
  ASSERT_EQ(tail.size(), formats::LogScanner::kQuoteLines);
  EXPECT_EQ(tail.front(), fmt::format("line {}", 20 - formats::LogScanner::kQuoteLines));
  EXPECT_EQ(tail.back(), "line 19");
}

}  // namespace
