#include <granstack/formats/error.hpp>
#include <granstack/formats/line_reader.hpp>

#include <cerrno>
#include <charconv>
#include <fast_float/fast_float.h>
#include <fmt/format.h>
#include <cstring>

namespace granstack::formats {

LineReader::LineReader(const std::string& path, std::size_t buffer_bytes)
    : path_(path), source_(open_bytes(path)), buffer_(buffer_bytes, '\0'), data_(buffer_.data()) {}

LineReader::LineReader(std::unique_ptr<ByteSource> source, const std::string& path, std::size_t buffer_bytes)
    : path_(path), source_(std::move(source)), buffer_(buffer_bytes, '\0'), data_(buffer_.data()) {}

LineReader::LineReader(std::string_view text, const std::string& path)
    : path_(path), data_(text.data()), end_(text.size()), eof_(true) {
  const void* nul = text.empty() ? nullptr : std::memchr(text.data(), '\0', text.size());
  if (nul != nullptr) first_nul_ = static_cast<long>(static_cast<const char*>(nul) - text.data());
}

bool LineReader::refill() {
  if (eof_) return false;
  // Keep the unfinished line; grow the buffer if one line fills it.
  if (begin_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    base_ += static_cast<long>(begin_);
    begin_ = 0;
  }
  if (end_ == buffer_.size()) {
    // No line of a LIGGGHTS text file comes near this: a file padded with zeros (truncate -s, a
    // crash) or not text at all must not grow the buffer until memory runs out.
    if (buffer_.size() >= kLongestLine) {
      // (The line number is the file's once the batch reader rebases it; a byte offset would be the piece's.)
      throw FormatError(path_, line_number_ + 1,
                        fmt::format("a line longer than {} MiB{}: not a LIGGGHTS text file (cut short and padded, or "
                                    "another kind of file); run the case again",
                                    kLongestLine >> 20,
                                    first_nul_ >= 0 ? ", holding NUL bytes" : ""));
    }
    buffer_.resize(buffer_.size() * 2, '\0');
    data_ = buffer_.data();
  }
  const std::size_t got = source_->read(buffer_.data() + end_, buffer_.size() - end_);
  if (first_nul_ < 0) {
    if (const void* nul = std::memchr(buffer_.data() + end_, '\0', got)) {
      first_nul_ = base_ + static_cast<long>(static_cast<const char*>(nul) - buffer_.data());
    }
  }
  end_ += got;
  if (got == 0) eof_ = true;
  return got > 0;
}

bool LineReader::next(std::string_view& line) {
  std::size_t scanned = begin_;
  for (;;) {
    const char* start = data_ + scanned;
    const void* nl = end_ > scanned ? std::memchr(start, '\n', end_ - scanned) : nullptr;
    if (nl != nullptr) {
      const std::size_t pos = static_cast<std::size_t>(static_cast<const char*>(nl) - data_);
      std::size_t len = pos - begin_;
      if (len > 0 && data_[begin_ + len - 1] == '\r') --len;
      line = std::string_view(data_ + begin_, len);
      begin_ = pos + 1;
      ++line_number_;
      return true;
    }
    const std::size_t offset = end_ - begin_;
    if (!refill()) {
      if (end_ > begin_) {  // last line without '\n'
        line = std::string_view(data_ + begin_, end_ - begin_);
        begin_ = end_;
        ++line_number_;
        return true;
      }
      return false;
    }
    scanned = begin_ + offset;
  }
}

void split_words(std::string_view line, std::vector<std::string_view>& words) {
  words.clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < n && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
}

bool parse_double(std::string_view word, double& value) {
  if (word.empty()) return false;
  const char* first = word.data();
  if (*first == '+') ++first;  // from_chars rejects a leading '+', printf-style output may have one
  // fast_float: correctly rounded like strtod, several times faster than libstdc++'s from_chars.
  auto [ptr, ec] = fast_float::from_chars(first, word.data() + word.size(), value);
  return ec == std::errc() && ptr == word.data() + word.size();
}

const char* parse_next_double(const char* p, const char* end, double& value) {
  while (p < end && (*p == ' ' || *p == '\t')) ++p;
  if (p == end) return nullptr;
  if (*p == '+') ++p;
  auto [ptr, ec] = fast_float::from_chars(p, end, value);
  if (ec != std::errc() || (ptr < end && *ptr != ' ' && *ptr != '\t')) return nullptr;
  return ptr;
}

bool parse_long(std::string_view word, long& value) {
  auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  return !word.empty() && ec == std::errc() && ptr == word.data() + word.size();
}

}  // namespace granstack::formats
