// refsim's outputs written behind the steps (a thread of their own) against written in line:
// the same bytes, and a write that fails fails the run, naming the file, on either path.
#include <granstack/formats/dump.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/refsim/case_run.hpp>

#include <fmt/format.h>
#include "../support/scratch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "write_behind.hpp"

namespace fs = std::filesystem;
using namespace granstack;
using refsim::detail::WriteBehind;

namespace {

fs::path work_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / (std::string(info->test_suite_name()) + "." + info->name()));
}

std::string generate(const std::string& name, const model::StackSpec& spec) {
  generator::GenerateOptions o;
  o.output = work_dir() / name;
  o.force = true;
  generator::generate({{name, spec}}, o);
  return o.output.string();
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every file a run wrote (dumps and series), by its path within the case.
std::vector<std::pair<std::string, std::string>> outputs(const std::string& dir) {
  const auto m = formats::read_manifest(dir);
  std::vector<std::pair<std::string, std::string>> files;
  const fs::path dumps = (fs::path(dir) / m.files.dump).parent_path();
  for (const auto& e : fs::directory_iterator(dumps)) files.emplace_back(fs::relative(e.path(), dir).string(), bytes(e.path()));
  std::sort(files.begin(), files.end());
  files.emplace_back(m.files.series, bytes(fs::path(dir) / m.files.series));
  return files;
}

// Every output step is there: a series line every series_every steps (from the first) and a dump
// frame every dump_every (from step 0), to the last step.
void expect_complete(const std::string& dir, const model::StackSpec& spec) {
  const auto res = model::resolve(model::Stack::build(spec));
  const auto m = formats::read_manifest(dir);
  const auto series = formats::read_series((fs::path(dir) / m.files.series).string());
  ASSERT_EQ(series.rows.size(), static_cast<std::size_t>(res.steps / res.series_every)) << dir;  // as fix print: not step 0
  for (std::size_t k = 0; k < series.rows.size(); ++k) {
    ASSERT_EQ(series.rows[k].at(0), static_cast<double>(static_cast<long>(k + 1) * res.series_every)) << dir;
  }
  const auto frames = static_cast<std::size_t>(res.steps / res.dump_every + 1);
  const fs::path dumps = (fs::path(dir) / m.files.dump).parent_path();
  if (spec.dump_files == model::DumpFiles::per_step) {
    EXPECT_EQ(static_cast<std::size_t>(std::distance(fs::directory_iterator(dumps), fs::directory_iterator())), frames);
  } else if (spec.dump_format == model::DumpFormat::text) {
    const std::string text = bytes(fs::path(dir) / m.files.dump);
    std::size_t count = 0;
    for (auto at = text.find("ITEM: TIMESTEP"); at != std::string::npos; at = text.find("ITEM: TIMESTEP", at + 1)) ++count;
    EXPECT_EQ(count, frames) << dir;
    EXPECT_NE(text.find(fmt::format("ITEM: TIMESTEP\n{}\n", res.steps)), std::string::npos) << dir;
  }
}

refsim::RunStats run(const std::string& dir, bool behind, int threads = 1) {
  refsim::RunOptions o;
  o.write_behind = behind;
  o.threads = threads;
  return refsim::run_case(dir, o);
}

}  // namespace

TEST(WriteBehind, RunsTheJobsInTheirOrderOnAThreadOfItsOwn) {
  for (const bool threaded : {false, true}) {
    std::vector<int> done;
    std::vector<std::thread::id> on;
    {
      WriteBehind out(threaded, 3);
      for (int k = 0; k < 2000; ++k) {
        out.submit([&, k] {
          done.push_back(k);
          on.push_back(std::this_thread::get_id());
        });
      }
      out.finish();
      ASSERT_EQ(done.size(), 2000U);
      for (int k = 0; k < 2000; ++k) ASSERT_EQ(done[static_cast<std::size_t>(k)], k);
    }
    for (const auto id : on) EXPECT_EQ(id == std::this_thread::get_id(), !threaded);
  }
}

TEST(WriteBehind, AFailedJobsErrorReachesTheCallerAndTheJobsAfterItNeverRun) {
  for (const bool threaded : {false, true}) {
    std::atomic<int> ran{0};
    std::atomic<bool> after{false};
    std::string caught;
    try {
      WriteBehind out(threaded, 2);
      for (int k = 0; k < 100; ++k) {
        out.submit([&, k] {
          if (k > 3) after = true;
          if (k == 3) throw std::runtime_error("dump.txt: cannot write: No space left on device");
          ++ran;
        });
      }
      out.finish();
    } catch (const std::runtime_error& e) {
      caught = e.what();
    }
    EXPECT_EQ(caught, "dump.txt: cannot write: No space left on device") << threaded;
    EXPECT_EQ(ran, 3) << threaded;
    EXPECT_FALSE(after) << threaded;
  }
}

TEST(WriteBehind, EndingWaitsForTheJobsGiven) {
  std::atomic<int> ran{0};
  {
    WriteBehind out(true, 8);
    for (int k = 0; k < 6; ++k) {
      out.submit([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        ++ran;
      });
    }
  }  // as when a signal ends the run: the frames made are written
  EXPECT_EQ(ran, 6);
}

// Text and binary dumps, one file and a file per step, with and without friction: every output
// step written, and every byte of every dump and of the series as the in-line writer gives them.
TEST(Outputs, WritingBehindTheStepsGivesTheSameBytes) {
  struct Case {
    const char* name;
    model::DumpFormat format;
    model::DumpFiles files;
    double restitution, friction;
  };
  for (const auto& c : {Case{"text", model::DumpFormat::text, model::DumpFiles::single, 1.0, 0.0},
                        Case{"binary_damped", model::DumpFormat::binary, model::DumpFiles::single, 0.9, 0.25},
                        Case{"per_step_damped", model::DumpFormat::text, model::DumpFiles::per_step, 0.9, 0.25}}) {
    model::StackSpec spec;
    spec.blocks = 2;
    spec.dump_format = c.format;
    spec.dump_files = c.files;
    spec.restitution.value = c.restitution;
    spec.friction.value = c.friction;
    const auto in_line = generate(std::string(c.name) + "_in_line", spec);
    const auto behind = generate(std::string(c.name) + "_behind", spec);
    // In line on three threads: each frame's text formatted in three shares of its atoms.
    const auto shared = generate(std::string(c.name) + "_in_line_3_threads", spec);
    EXPECT_FALSE(run(in_line, false).write_behind);
    EXPECT_TRUE(run(behind, true).write_behind);
    EXPECT_FALSE(run(shared, false, 3).write_behind);
    expect_complete(in_line, spec);
    expect_complete(behind, spec);
    const auto a = outputs(in_line), b = outputs(behind);
    EXPECT_TRUE(outputs(shared) == a) << c.name;
    ASSERT_EQ(a.size(), b.size()) << c.name;
    EXPECT_GT(a.size(), c.files == model::DumpFiles::per_step ? 100U : 1U) << c.name;
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_EQ(a[k].first, b[k].first) << c.name;
      EXPECT_GT(a[k].second.size(), 100U) << c.name << " " << a[k].first;
      EXPECT_TRUE(a[k].second == b[k].second) << c.name << ": " << a[k].first << " differs";
    }
  }
}

// refsim writes its binary dump as a zstd stream (LIGGGHTS's layout inside), smaller than its
// frames' bytes and holding, frame by frame, the doubles of the same run's text dump.
TEST(Outputs, ABinaryDumpIsAZstdStreamOfTheTextDumpsDoubles) {
  model::StackSpec spec;
  spec.blocks = 2;
  spec.restitution.value = 0.95;
  const auto text_dir = generate("text", spec);
  spec.dump_format = model::DumpFormat::binary;
  const auto binary_dir = generate("binary", spec);
  run(text_dir, true);
  run(binary_dir, true);
  const auto m = formats::read_manifest(binary_dir);
  const auto path = (fs::path(binary_dir) / m.files.dump).string();
  EXPECT_EQ(bytes(path).substr(0, 4), std::string("\x28\xb5\x2f\xfd", 4));
  formats::TextDumpReader text((fs::path(text_dir) / formats::read_manifest(text_dir).files.dump).string());
  formats::BinaryDumpReader binary(path, m.files.dump_columns);
  formats::DumpFrame t, b;
  std::size_t frames = 0, values = 0;
  while (text.next(t)) {
    ASSERT_TRUE(binary.next(b)) << "frame " << frames;
    EXPECT_EQ(b.step, t.step);
    EXPECT_TRUE(b.values == t.values) << "step " << t.step;
    ++frames;
    values += b.values.size();
  }
  EXPECT_FALSE(binary.next(b));
  const auto res = model::resolve(model::Stack::build(spec));
  EXPECT_EQ(frames, static_cast<std::size_t>(res.steps / res.dump_every + 1));
  const std::size_t header = 44 + 6 * 8 + 3 * 4;  // LIGGGHTS's header, the box, three counts
  EXPECT_LT(fs::file_size(path), frames * header + values * sizeof(double)) << "compressed";
}

// A dump or series that cannot be written (here /dev/full: every write fails with ENOSPC) fails
// the run with the file's name and the system's reason, on either path: from the writing
// thread the error reaches the run at its next frame or at its end.
TEST(Outputs, AFullDiskFailsTheRunNamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "this system has no /dev/full to fill";
  model::StackSpec spec;
  spec.blocks = 1;
  for (const bool behind : {false, true}) {
    for (const bool series : {false, true}) {
      const auto dir = generate(fmt::format("full_{}_{}", behind ? "behind" : "in_line", series ? "series" : "dump"), spec);
      const auto m = formats::read_manifest(dir);
      const fs::path target = fs::path(dir) / (series ? m.files.series : m.files.dump);
      fs::create_directories(target.parent_path());
      fs::create_symlink("/dev/full", target);
      try {
        run(dir, behind);
        ADD_FAILURE() << "a run into /dev/full succeeded";
      } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(target.filename().string()), std::string::npos) << what;
        EXPECT_NE(what.find("No space left on device"), std::string::npos) << what;
      }
    }
  }
}
