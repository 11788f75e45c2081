// libFuzzer target: every reader of LIGGGHTS output (text and binary dumps, in-situ series,
// data files) on arbitrary bytes. Each may refuse the input with a FormatError; any other
// exception, a crash, a hang or a sanitizer report is a bug.
#include <granstack/formats/data_file.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/series.hpp>

#include "../support/read_both_ways.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace {
const std::vector<std::string> kColumns{"id", "type", "radius", "mass", "x", "y", "z", "vx", "vy", "vz",
                                        "omegax", "omegay", "omegaz", "fx", "fy", "fz"};

template <typename Fn>
void expect_clean(Fn&& fn) {
  try {
    fn();
  } catch (const granstack::formats::FormatError&) {
    // A refusal with a message: what bad input must get.
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The input as a file (TMPDIR: run_fuzz.sh's work folder), removed when the fuzzer ends normally;
  // a crash leaves it beside its crash-* input.
  static const struct Scratch {
    std::string path = (std::filesystem::temp_directory_path() / ("granstack-fuzz-" + std::to_string(::getpid()))).string();
    ~Scratch() { std::remove(path.c_str()); }
  } scratch;
  const std::string& path = scratch.path;
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  using namespace granstack::formats;
  DumpFrame frame;
  expect_clean([&] {
    TextDumpReader reader(path);
    while (reader.next(frame)) {
    }
  });
  // Read in batches (cut every few bytes, parsed apart), the same frames and the same error.
  const auto whole = granstack::test_support::read_whole(path);
  for (const std::size_t batch : {std::size_t{7}, std::size_t{97}, std::size_t{4096}}) {
    const auto diff = granstack::test_support::difference(whole, granstack::test_support::read_in_batches(path, batch));
    if (!diff.empty()) {
      std::fprintf(stderr, "batched reading (%zu bytes) differs: %s\n", batch, diff.c_str());
      std::abort();
    }
  }
  expect_clean([&] {
    BinaryDumpReader reader(path, kColumns);
    while (reader.next(frame)) {
    }
  });
  expect_clean([&] { read_series(path); });
  expect_clean([&] { parse_data_file(path); });
  return 0;
}
