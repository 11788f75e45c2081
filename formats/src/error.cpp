#include <granstack/formats/error.hpp>

#include <fmt/format.h>

namespace granstack::formats {

namespace {
std::string describe(const std::string& file, long line, const std::string& message) {
  return line > 0 ? fmt::format("{}:{}: {}", file, line, message) : fmt::format("{}: {}", file, message);
}
}  // namespace

FormatError::FormatError(std::string file, long line, std::string message)
    : std::runtime_error(describe(file, line, message)), file_(std::move(file)), line_(line),
      message_(std::move(message)) {}

std::exception_ptr shift_line(std::exception_ptr error, long delta) {
  if (!error || delta == 0) return error;
  try {
    std::rethrow_exception(error);
  } catch (const TruncatedError& e) {
    if (e.line() > 0) return std::make_exception_ptr(TruncatedError(e.file(), e.line() + delta, e.message()));
  } catch (const FormatError& e) {
    if (e.line() > 0) return std::make_exception_ptr(FormatError(e.file(), e.line() + delta, e.message()));
  } catch (...) {
  }
  return error;
}

}  // namespace granstack::formats
