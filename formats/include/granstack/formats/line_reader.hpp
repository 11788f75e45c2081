#pragma once
// Reads a text file (plain, gzip or zstd) line by line through a large buffer, handing out
// string_views that stay valid until the next call. Memory does not grow with the file.
#include <granstack/formats/byte_source.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

class LineReader {
 public:
  // Lines longer than this are an error (FormatError), so memory stays bounded whatever the file.
  static constexpr std::size_t kLongestLine = std::size_t{8} << 20;
  // Throws FormatError when the file cannot be opened.
  explicit LineReader(const std::string& path, std::size_t buffer_bytes = std::size_t{1} << 18);
  // Lines of `text`, a piece of the file `path` already in memory (it must outlive the reader);
  // line numbers count from the piece's first line.
  LineReader(std::string_view text, const std::string& path);
  // Lines of an open source (named `path` in messages).
  LineReader(std::unique_ptr<ByteSource> source, const std::string& path, std::size_t buffer_bytes = std::size_t{1} << 18);
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // The next line without its '\n' (and without a '\r' before it); false at the end of the file.
  bool next(std::string_view& line);
  long line_number() const { return line_number_; }
  // The end of the bytes held: the lines handed out may be read up to here.
  const char* data_end() const { return data_ + end_; }
  const std::string& path() const { return path_; }
  // True when a NUL byte came before the end of the last line read: the file is binary, not
  // text. (Only what was read counts, whatever the buffer holds beyond it.)
  bool saw_nul() const { return first_nul_ >= 0 && first_nul_ < base_ + static_cast<long>(begin_); }

 private:
  bool refill();
  std::string path_;
  std::unique_ptr<ByteSource> source_;
  std::string buffer_;            // reading a file
  const char* data_ = nullptr;    // the bytes held: buffer_'s, or the piece in memory
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  bool eof_ = false;
  long base_ = 0;        // offset in the file of buffer_[0]
  long first_nul_ = -1;  // offset in the file of the first NUL byte read, or -1
  long line_number_ = 0;
};

// Splits on spaces and tabs.
void split_words(std::string_view line, std::vector<std::string_view>& words);
// Parses a whole word as a double (accepts what printf's %g writes, including inf and nan).
bool parse_double(std::string_view word, double& value);
bool parse_long(std::string_view word, long& value);
// Parses the next blank-separated number of [p, end) into `value` and returns where it ended;
// nullptr when there is no number there (or it runs into other characters).
const char* parse_next_double(const char* p, const char* end, double& value);

}  // namespace granstack::formats
