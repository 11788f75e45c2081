#pragma once
// A text dump read whole by TextDumpReader and in batches by FrameBatchSource (cut at frame
// boundaries, parsed apart, settled in order): both ways must give the same frames and the same
// error, word for word and line for line. Shared by the unit tests and the fuzz target.
#include <granstack/formats/batches.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>

#include <cstring>
#include <string>
#include <vector>

namespace granstack::test_support {

struct ReadOutcome {
  std::vector<formats::DumpFrame> frames;
  std::string error;  // what() of the FormatError that ended the reading, or empty
  bool truncated = false;
};

inline void record_error(ReadOutcome& out) {
  try {
    throw;
  } catch (const formats::TruncatedError& e) {
    out.error = e.what();
    out.truncated = true;
  } catch (const formats::FormatError& e) {
    out.error = e.what();
  }
}

inline ReadOutcome read_whole(const std::string& path) {
  ReadOutcome out;
  try {
    formats::TextDumpReader reader(path);
    formats::DumpFrame f;
    while (reader.next(f)) out.frames.push_back(f);
  } catch (const formats::FormatError&) {
    record_error(out);
  }
  return out;
}

inline ReadOutcome read_in_batches(const std::string& path, std::size_t batch_bytes) {
  ReadOutcome out;
  try {
    formats::FrameBatchSource source(path, false, {}, {}, batch_bytes);
    formats::FrameBatch batch;
    while (source.take(batch)) {
      source.parse(batch);
      source.settle(batch);
      out.frames.insert(out.frames.end(), batch.frames.begin(), batch.frames.end());
      if (batch.error) std::rethrow_exception(batch.error);
    }
  } catch (const formats::FormatError&) {
    record_error(out);
  }
  return out;
}

// Empty when both ways agree; otherwise what differs.
inline std::string difference(const ReadOutcome& a, const ReadOutcome& b) {
  if (a.error != b.error || a.truncated != b.truncated) {
    return "errors differ: '" + a.error + "' (truncated " + std::to_string(a.truncated) + ") against '" + b.error +
           "' (truncated " + std::to_string(b.truncated) + ")";
  }
  if (a.frames.size() != b.frames.size()) {
    return "frame counts differ: " + std::to_string(a.frames.size()) + " against " + std::to_string(b.frames.size());
  }
  for (std::size_t k = 0; k < a.frames.size(); ++k) {
    const auto& x = a.frames[k];
    const auto& y = b.frames[k];
    const bool same = x.step == y.step && x.atoms == y.atoms && x.box_flags == y.box_flags && x.box == y.box &&
                      x.columns == y.columns && x.first_line == y.first_line && x.values.size() == y.values.size() &&
                      (x.values.empty() || std::memcmp(x.values.data(), y.values.data(), x.values.size() * sizeof(double)) == 0);
    if (!same) return "frame " + std::to_string(k) + " differs (step " + std::to_string(x.step) + ")";
  }
  return "";
}

}  // namespace granstack::test_support
