#pragma once
// LIGGGHTS `dump custom` text files (liggghts-3.8.md section 6), read one frame at a time so
// memory does not grow with the number of frames. Columns are found by name, in any order.
#include <granstack/formats/line_reader.hpp>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

struct DumpFrame {
  long step = 0;
  long atoms = 0;
  std::string box_flags;            // e.g. "mm mm mm"
  std::array<double, 6> box{};      // xlo xhi ylo yhi zlo zhi
  std::vector<std::string> columns; // as in the ITEM: ATOMS line
  std::vector<double> values;       // atoms x columns, row-major
  long first_line = 0;              // line of "ITEM: TIMESTEP", for messages

  // Index of a column, or -1.
  int column(std::string_view name) const;
  double at(long row, int col) const {
    return values[static_cast<std::size_t>(row) * columns.size() + static_cast<std::size_t>(col)];
  }
};

class TextDumpReader {
 public:
  explicit TextDumpReader(const std::string& path);
  // Reads the next frame; false at the end of the file. Throws FormatError for a malformed
  // frame (naming file, line and step) and TruncatedError when the file ends inside a frame.
  bool next(DumpFrame& frame);
  const std::string& path() const { return reader_.path(); }
  long frames_read() const { return frames_; }

 private:
  LineReader reader_;
  std::vector<std::string_view> words_;
  long frames_ = 0;
  long last_step_ = -1;
};

// Throws FormatError naming each missing column and the `dump custom` keyword that adds it.
void require_columns(const DumpFrame& frame, const std::vector<std::string>& names, const std::string& path);

}  // namespace granstack::formats
