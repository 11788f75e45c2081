#pragma once
// Whitespace-separated numeric tables with a '#' header naming the columns: the in-situ
// series that generated decks write with `fix print ... title "# step ..."`.
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

struct Series {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int column(std::string_view name) const;  // -1 if absent
};

// The last '#' line before the data names the columns. Throws FormatError on a malformed row
// (a final row cut short by a killed run is dropped: the rows before it are complete).
Series read_series(const std::string& path);

}  // namespace granstack::formats
