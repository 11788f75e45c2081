#include <granstack/formats/error.hpp>
#include <granstack/formats/line_reader.hpp>
#include <granstack/formats/series.hpp>

#include <fmt/format.h>

namespace granstack::formats {

int Series::column(std::string_view name) const {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i);
  }
  return -1;
}

Series read_series(const std::string& path) {
  LineReader reader(path);
  Series s;
  std::string_view line;
  std::vector<std::string_view> words;
  long pending_line = 0;  // a short row is an error unless it is the last line
  std::string pending_message;
  while (reader.next(line)) {
    if (pending_line != 0) throw FormatError(path, pending_line, pending_message);
    if (!line.empty() && line.front() == '#') {
      if (s.rows.empty()) {
        split_words(line.substr(1), words);
        s.columns.assign(words.begin(), words.end());
      }
      continue;
    }
    split_words(line, words);
    if (words.empty()) continue;
    if (s.columns.empty()) throw FormatError(path, reader.line_number(), "no '# name ...' header line before the data");
    if (words.size() != s.columns.size()) {
      pending_line = reader.line_number();
      pending_message = fmt::format("{} values on a row, the header names {} columns", words.size(), s.columns.size());
      continue;
    }
    std::vector<double> row(words.size());
    for (std::size_t i = 0; i < words.size(); ++i) {
      if (!parse_double(words[i], row[i])) {
        throw FormatError(path, reader.line_number(),
                          fmt::format("'{}' in column '{}' is not a number", words[i].substr(0, 40), s.columns[i]));
      }
    }
    s.rows.push_back(std::move(row));
  }
  if (reader.saw_nul()) throw FormatError(path, 0, "binary data where a text table was expected");
  return s;
}

}  // namespace granstack::formats
