// LIGGGHTS's text `dump custom`: frames read line by line, numbers parsed in place, and a token
// that repeats the previous frame's taken from it.
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>

#include "tokens.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unistd.h>

namespace granstack::formats {

TextDumpReader::TextDumpReader(const std::string& path) : reader_(path) {}

TextDumpReader::TextDumpReader(std::string_view piece, const std::string& path, bool first,
                               std::optional<std::string> next_line)
    : reader_(piece, path), first_(first), last_(!next_line), next_line_(next_line.value_or("")),
      in_memory_(true) {}

TextDumpReader::TextDumpReader(std::unique_ptr<ByteSource> source, const std::string& path, bool first)
    : reader_(std::move(source), path), first_(first) {}

void TextDumpReader::convert_only(std::vector<std::string> columns) {
  wanted_ = std::move(columns);
  convert_.clear();  // worked out again from the next header
}

using tokens::common_prefix;
using tokens::common_suffix;
using tokens::same_token;
using tokens::skip_word;
using tokens::token_length;

FormatError TextDumpReader::fail(const std::string& msg) const {
  if (reader_.saw_nul()) {
    return FormatError(reader_.path(), line_number(), "binary data where a text dump was expected (" + msg + ")");
  }
  return FormatError(reader_.path(), line_number(), msg);
}

// A line inside a frame. A piece of a file that is not its end is followed by the next frame's
// 'ITEM: TIMESTEP' line: a frame that runs into it meets that line here, and fails as it would
// reading the whole file.
bool TextDumpReader::in_frame(std::string_view& line) {
  if (reader_.next(line)) return true;
  if (last_ || next_frame_seen_) return false;
  next_frame_seen_ = true;
  line = next_line_;
  return true;
}

void TextDumpReader::expect_item(std::string_view& line, std::string_view item, long step) {
  if (!in_frame(line)) {
    throw TruncatedError(reader_.path(), line_number(), fmt::format("file ends inside the frame at step {} (no '{}')", step, item));
  }
  if (line.substr(0, item.size()) != item) {
    throw fail(fmt::format("expected '{}' in the frame at step {}, found '{}'", item, step, line.substr(0, 60)));
  }
}

bool TextDumpReader::next(DumpFrame& f) {
  step_read_ = -1;
  std::string_view line;
  if (!read_header(f, line)) return false;
  choose_conversions(f);
  read_atoms(f);
  last_step_ = f.step;
  ++frames_;
  return true;
}

// The frame's header, up to its 'ITEM: ATOMS' line (left in `line`).
bool TextDumpReader::read_header(DumpFrame& f, std::string_view& line) {
  const auto& path = reader_.path();
  // Skip blank lines between frames; a clean end of file ends the dump.
  do {
    if (!reader_.next(line)) {
      if (frames_ == 0 && first_) throw fail("empty file: no frame (a dump starts with 'ITEM: TIMESTEP')");
      return false;
    }
  } while (line.find_first_not_of(" \t") == std::string_view::npos);
  if (line.substr(0, 14) != "ITEM: TIMESTEP") {
    throw fail(fmt::format("expected 'ITEM: TIMESTEP', found '{}'", line.substr(0, 60)));
  }
  f.first_line = reader_.line_number();
  if (!in_frame(line)) throw TruncatedError(path, line_number(), "file ends after 'ITEM: TIMESTEP'");
  if (!parse_long(line, f.step) || f.step < 0) throw fail(fmt::format("'{}' is not a timestep", line.substr(0, 60)));
  step_read_ = f.step;
  nul_by_step_ = reader_.saw_nul();
  if (f.step < last_step_) {
    throw fail(fmt::format("timestep {} comes after {}: timesteps go backwards (two runs appended to one file?)", f.step,
                           last_step_));
  }
  expect_item(line, "ITEM: NUMBER OF ATOMS", f.step);
  if (!in_frame(line)) throw TruncatedError(path, line_number(), "file ends in the frame header");
  if (!parse_long(line, f.atoms) || f.atoms < 0) throw fail(fmt::format("'{}' is not an atom count", line.substr(0, 60)));
  expect_item(line, "ITEM: BOX BOUNDS", f.step);
  f.box_flags = std::string(line.substr(16));
  while (!f.box_flags.empty() && f.box_flags.front() == ' ') f.box_flags.erase(0, 1);
  for (int axis = 0; axis < 3; ++axis) {
    if (!in_frame(line)) throw TruncatedError(path, line_number(), "file ends in the box bounds");
    split_words(line, words_);
    if (words_.size() < 2 || !parse_double(words_[0], f.box[static_cast<std::size_t>(2 * axis)]) ||
        !parse_double(words_[1], f.box[static_cast<std::size_t>(2 * axis + 1)])) {
      throw fail("a box-bounds line has two numbers");
    }
  }
  expect_item(line, "ITEM: ATOMS", f.step);
  split_words(line.substr(11), words_);
  if (words_.empty()) throw fail("'ITEM: ATOMS' names no column");
  if (frames_ == 0 || words_.size() != f.columns.size() || !std::equal(words_.begin(), words_.end(), f.columns.begin())) {
    f.columns.assign(words_.begin(), words_.end());
    convert_.clear();
  }
  return true;
}

// Which columns are converted to numbers (convert_only), worked out again for a new header.
void TextDumpReader::choose_conversions(DumpFrame& f) {
  const std::size_t ncol = f.columns.size();
  if (convert_.size() != ncol) {
    convert_.assign(ncol, 1);
    for (std::size_t c = 0; c < ncol && !wanted_.empty(); ++c) {
      convert_[c] = std::find(wanted_.begin(), wanted_.end(), f.columns[c]) != wanted_.end() ? 1 : 0;
    }
  }
  convert_all_ = std::find(convert_.begin(), convert_.end(), 0) == convert_.end();
}

namespace {

// The first column, after c, whose token and the blank before it lie in the `suffix` bytes an
// atom's line shares at its end with its line in the frame before (ncol when there is none).
std::size_t repeated_end(const RepeatedTokens::Previous& before, std::size_t c, std::size_t ncol, std::size_t suffix) {
  std::size_t stop = ncol;
  while (stop > c + 1 && before.line.size() - before.starts[stop - 1] < suffix) --stop;
  return stop;
}

// Columns c.. of a line of `size` bytes, taken from the frame before: their values, and where
// their tokens start (as far from the line's end as there).
void take_repeated_end(const RepeatedTokens::Previous& before, std::size_t c, std::size_t ncol, std::size_t size, double* out,
                       std::uint32_t* starts) {
  std::memcpy(out + c, before.values + c, (ncol - c) * sizeof(double));
  if (starts == nullptr) return;
  const auto shift = static_cast<std::uint32_t>(before.line.size() - size);
  for (std::size_t k = c; k < ncol; ++k) starts[k] = before.starts[k] - shift;
}

}  // namespace

void TextDumpReader::read_atoms(DumpFrame& f) {
  const std::size_t ncol = f.columns.size();
  // The header's count is not trusted with memory: the frame grows as its lines arrive (and the
  // storage of the previous frame is reused without clearing it).
  const std::size_t expected = static_cast<std::size_t>(f.atoms) * ncol;
  if (f.values.size() > expected) f.values.resize(expected);
  repeats_.begin_frame(f, in_memory_);
  const bool convert_all = convert_all_;
  // Whether every value is finite: each parsed one is checked, the others are the previous
  // frame's (finite if it was).
  bool finite = !repeats_.reusing() || previous_finite_;
  std::string_view line;
  for (long a = 0; a < f.atoms; ++a) {
    if (!in_frame(line)) {
      throw TruncatedError(reader_.path(), line_number(),
                           fmt::format("file ends inside the frame at step {}: {} of {} atom lines", f.step, a, f.atoms));
    }
    const auto atom = static_cast<std::size_t>(a);
    const std::size_t base = atom * ncol;
    if (f.values.size() < base + ncol) f.values.resize(std::min(expected, std::max(base + ncol, 2 * f.values.size())));
    double* out = f.values.data() + base;
    const auto before = repeats_.previous(atom, line, reader_.data_end());
    std::uint32_t* starts = repeats_.starts(atom, static_cast<std::size_t>(f.atoms));
    // The columns wholly inside the bytes both lines begin with (id, type, radius, mass and often
    // the position) repeat: taken in one go; an atom at rest repeats its whole line. The rest
    // are parsed, token by token.
    std::size_t c = 0, stop = ncol;
    const char* p = line.data();
    const char* end = line.data() + line.size();
    const char* suffix_start = nullptr;  // where column `stop` starts, when the columns from it on repeat
    if (before.values != nullptr) {
      const std::size_t shorter = std::min(line.size(), before.line.size());
      const std::size_t common = common_prefix(line.data(), before.line.data(), shorter);
      if (common == line.size() && common == before.line.size()) {
        c = ncol;
        p = line.data() + line.size();
      } else {
        while (c + 1 < ncol && before.starts[c + 1] <= common) ++c;
        p = line.data() + (c > 0 ? before.starts[c] : 0);
        // The columns wholly inside the bytes both lines end with, with the blank before them,
        // repeat too: the columns up to them are parsed, and must end where they begin.
        stop = repeated_end(before, c, ncol, common_suffix(end, before.line.data() + before.line.size(), shorter - common));
        if (stop < ncol) suffix_start = end - (before.line.size() - before.starts[stop]);
      }
      std::memcpy(out, before.values, c * sizeof(double));
      std::memcpy(starts, before.starts, c * sizeof(std::uint32_t));
    }
    const bool cached = before.values != nullptr;
    for (; c < ncol && p != nullptr; ++c) {
      if (c == stop) {
        while (p < suffix_start && (*p == ' ' || *p == '\t')) ++p;
        if (p == suffix_start) {
          take_repeated_end(before, c, ncol, line.size(), out, starts);
          c = ncol;
          p = end;
          break;
        }
      }
      if (cached && *p == ' ' && p[1] > ' ') {
        ++p;  // the one space LIGGGHTS writes between numbers (the bytes ahead may be read: see previous())
      } else {
        while (p < end && (*p == ' ' || *p == '\t')) ++p;
      }
      if (starts != nullptr) starts[c] = static_cast<std::uint32_t>(p - line.data());
      if (cached) {
        const std::size_t same = same_token(p, before.line.data() + before.starts[c]);
        if (same > 0) {
          out[c] = before.values[c];
          p += same;
          continue;
        }
      }
      if (convert_all || convert_[c] != 0) {
        if (p + 1 < end && p[0] == '0' && (p[1] == ' ' || p[1] == '\t')) {  // the commonest number
          out[c] = 0.0;
          ++p;
          continue;
        }
        p = parse_next_double(p, end, out[c]);
        finite = finite && std::isfinite(out[c]);
        continue;
      }
      // Not converted, but checked to be a finite number: its first character past a sign is a
      // digit or a point (nan, inf and words are not).
      const char* q = p < end && (*p == '-' || *p == '+') ? p + 1 : p;
      if (q < end && !(*q >= '0' && *q <= '9') && *q != '.') not_finite(f, a, c, p, end);
      const std::size_t length = cached ? token_length(p) : 0;
      p = length > 0 && p + length <= end ? p + length : skip_word(p, end);
      out[c] = 0.0;
    }
    while (p != nullptr && p < end && (*p == ' ' || *p == '\t')) ++p;
    if (p == nullptr || p != end) bad_row(f, a, line);
    repeats_.keep(atom, line);
  }
  repeats_.end_frame(f);
  f.finite = finite;
  previous_finite_ = finite;
}

void TextDumpReader::not_finite(const DumpFrame& f, long a, std::size_t c, const char* p, const char* end) {
  const char* q = p < end && (*p == '-' || *p == '+') ? p + 1 : p;
  while (q < end && *q != ' ' && *q != '\t') ++q;
  throw fail(fmt::format("'{}' in column '{}' (atom line {} of the frame at step {}) is not a finite number",
                         std::string_view(p, static_cast<std::size_t>(std::min<long>(q - p, 40))), f.columns[c], a + 1,
                         f.step));
}

void TextDumpReader::bad_row(const DumpFrame& f, long a, std::string_view line) {
  const std::size_t ncol = f.columns.size();
  split_words(line, words_);
  if (words_.size() != ncol) {
    bad_row_message(f, a, fmt::format("atom line {} of the frame at step {} has {} values, the header names {} columns", a + 1,
                                      f.step, words_.size(), ncol));
  }
  for (std::size_t k = 0; k < ncol; ++k) {
    double ignored = 0.0;
    if (!parse_double(words_[k], ignored)) {
      bad_row_message(f, a, fmt::format("'{}' in column '{}' (frame at step {}) is not a number", words_[k].substr(0, 40),
                                        f.columns[k], f.step));
    }
  }
  bad_row_message(f, a, fmt::format("atom line {} of the frame at step {} is not a row of numbers", a + 1, f.step));
}

// A bad last line of the file is a run killed while writing: truncation, not corruption.
void TextDumpReader::bad_row_message(const DumpFrame& f, long a, const std::string& msg) {
  FormatError error = fail(msg);
  std::string_view rest;
  if (last_ && !reader_.next(rest)) {
    throw TruncatedError(reader_.path(), error.line(),
                         fmt::format("file ends inside the frame at step {}: atom line {} of {} is cut short", f.step, a + 1,
                                     f.atoms));
  }
  throw error;
}

}  // namespace granstack::formats
