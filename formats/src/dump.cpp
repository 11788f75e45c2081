#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>

#include <fmt/format.h>

#include <cmath>

namespace granstack::formats {

int DumpFrame::column(std::string_view name) const {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i);
  }
  return -1;
}

TextDumpReader::TextDumpReader(const std::string& path) : reader_(path) {}

bool TextDumpReader::next(DumpFrame& f) {
  std::string_view line;
  const auto& path = reader_.path();
  auto fail = [&](const std::string& msg) {
    if (reader_.saw_nul()) {
      return FormatError(path, reader_.line_number(), "binary data where a text dump was expected (" + msg + ")");
    }
    return FormatError(path, reader_.line_number(), msg);
  };
  auto step_text = [&] { return fmt::format("frame at step {}", f.step); };
  auto expect_item = [&](std::string_view item) {
    if (!reader_.next(line)) {
      throw TruncatedError(path, reader_.line_number(), fmt::format("file ends inside the {} (no '{}')", step_text(), item));
    }
    if (line.substr(0, item.size()) != item) {
      throw fail(fmt::format("expected '{}' in the {}, found '{}'", item, step_text(), line.substr(0, 60)));
    }
  };

  // Skip blank lines between frames; a clean end of file ends the dump.
  do {
    if (!reader_.next(line)) {
      if (frames_ == 0) throw fail("empty file: no frame (a dump starts with 'ITEM: TIMESTEP')");
      return false;
    }
  } while (line.find_first_not_of(" \t") == std::string_view::npos);
  if (line.substr(0, 14) != "ITEM: TIMESTEP") {
    throw fail(fmt::format("expected 'ITEM: TIMESTEP', found '{}'", line.substr(0, 60)));
  }
  f.first_line = reader_.line_number();
  if (!reader_.next(line)) throw TruncatedError(path, reader_.line_number(), "file ends after 'ITEM: TIMESTEP'");
  if (!parse_long(line, f.step) || f.step < 0) throw fail(fmt::format("'{}' is not a timestep", line.substr(0, 60)));
  if (f.step < last_step_) {
    throw fail(fmt::format("timestep {} comes after {}: timesteps go backwards (two runs appended to one file?)", f.step,
                           last_step_));
  }
  expect_item("ITEM: NUMBER OF ATOMS");
  if (!reader_.next(line)) throw TruncatedError(path, reader_.line_number(), "file ends in the frame header");
  if (!parse_long(line, f.atoms) || f.atoms < 0) throw fail(fmt::format("'{}' is not an atom count", line.substr(0, 60)));
  expect_item("ITEM: BOX BOUNDS");
  f.box_flags = std::string(line.substr(16));
  while (!f.box_flags.empty() && f.box_flags.front() == ' ') f.box_flags.erase(0, 1);
  for (int axis = 0; axis < 3; ++axis) {
    if (!reader_.next(line)) throw TruncatedError(path, reader_.line_number(), "file ends in the box bounds");
    split_words(line, words_);
    if (words_.size() < 2 || !parse_double(words_[0], f.box[static_cast<std::size_t>(2 * axis)]) ||
        !parse_double(words_[1], f.box[static_cast<std::size_t>(2 * axis + 1)])) {
      throw fail("a box-bounds line has two numbers");
    }
  }
  expect_item("ITEM: ATOMS");
  split_words(line.substr(11), words_);
  if (words_.empty()) throw fail("'ITEM: ATOMS' names no column");
  if (frames_ == 0 || words_.size() != f.columns.size() ||
      !std::equal(words_.begin(), words_.end(), f.columns.begin())) {
    f.columns.assign(words_.begin(), words_.end());
  }
  const std::size_t ncol = f.columns.size();
  f.values.resize(static_cast<std::size_t>(f.atoms) * ncol);
  double* out = f.values.data();
  for (long a = 0; a < f.atoms; ++a) {
    if (!reader_.next(line)) {
      throw TruncatedError(path, reader_.line_number(),
                           fmt::format("file ends inside the frame at step {}: {} of {} atom lines", f.step, a, f.atoms));
    }
    split_words(line, words_);
    // A bad last line of the file is a run killed while writing: truncation, not corruption.
    auto bad_row = [&](const std::string& msg) {
      FormatError error = fail(msg);
      std::string_view rest;
      if (!reader_.next(rest)) {
        throw TruncatedError(path, error.line(),
                             fmt::format("file ends inside the frame at step {}: atom line {} of {} is cut short",
                                         f.step, a + 1, f.atoms));
      }
      throw error;
    };
    if (words_.size() != ncol) {
      bad_row(fmt::format("atom line {} of the frame at step {} has {} values, the header names {} columns", a + 1,
                          f.step, words_.size(), ncol));
    }
    for (std::size_t c = 0; c < ncol; ++c) {
      if (!parse_double(words_[c], *out++)) {
        bad_row(fmt::format("'{}' in column '{}' (frame at step {}) is not a number", words_[c].substr(0, 40),
                            f.columns[c], f.step));
      }
    }
  }
  last_step_ = f.step;
  ++frames_;
  return true;
}

void require_columns(const DumpFrame& frame, const std::vector<std::string>& names, const std::string& path) {
  std::vector<std::string> missing;
  for (const auto& n : names) {
    if (frame.column(n) < 0) missing.push_back(n);
  }
  if (!missing.empty()) {
    throw FormatError(path, frame.first_line,
                      fmt::format("the dump lacks column(s) {}: add the keyword(s) '{}' to the 'dump ... custom' line "
                                  "of the deck",
                                  fmt::join(missing, ", "), fmt::join(missing, " ")));
  }
}

}  // namespace granstack::formats
