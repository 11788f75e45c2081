#pragma once
#include <exception>
#include <stdexcept>
#include <string>

namespace granstack::formats {

// A file that is not what it should be. what() names the file, and the line and frame where known.
class FormatError : public std::runtime_error {
 public:
  FormatError(std::string file, long line, std::string message);
  const std::string& file() const { return file_; }
  long line() const { return line_; }  // 1-based; 0 when not about one line
  const std::string& message() const { return message_; }  // without the file and line

 private:
  std::string file_;
  long line_;
  std::string message_;
};

// A file that could not be read or written (a full disk, permissions): exit code 7. what()
// names the file.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The file ends inside a frame; the frames before it are complete.
class TruncatedError : public FormatError {
 public:
  using FormatError::FormatError;
};

// Why a file could not be read, in a user's words: the JSON library's "[json.exception.parse_error.101]
// parse error at line 1, column 1: syntax error while parsing value - invalid literal; last read:
// 'g'" becomes "not valid JSON (line 1, column 1)", its type errors "a value of the wrong type
// (...)"; any other message is what() unchanged.
std::string short_reason(const std::exception& e);

// The same error (FormatError or TruncatedError) with `delta` added to its line number, when it
// has one; any other exception unchanged.
std::exception_ptr shift_line(std::exception_ptr error, long delta);

}  // namespace granstack::formats
