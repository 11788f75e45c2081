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

// The same error (FormatError or TruncatedError) with `delta` added to its line number, when it
// has one; any other exception unchanged.
std::exception_ptr shift_line(std::exception_ptr error, long delta);

}  // namespace granstack::formats
