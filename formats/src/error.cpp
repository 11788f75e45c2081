#include <granstack/formats/error.hpp>

#include <fmt/format.h>

namespace granstack::formats {

namespace {
std::string describe(const std::string& file, long line, const std::string& message) {
  return line > 0 ? fmt::format("{}:{}: {}", file, line, message) : fmt::format("{}: {}", file, message);
}
}  // namespace

FormatError::FormatError(std::string file, long line, std::string message)
    : std::runtime_error(describe(file, line, message)), file_(std::move(file)), line_(line) {}

}  // namespace granstack::formats
