#include <granstack/formats/error.hpp>

#include <fmt/format.h>

#include <string_view>

namespace granstack::formats {

namespace {
std::string describe(const std::string& file, long line, const std::string& message) {
  return line > 0 ? fmt::format("{}:{}: {}", file, line, message) : fmt::format("{}: {}", file, message);
}
}  // namespace

FormatError::FormatError(std::string file, long line, std::string message)
    : std::runtime_error(describe(file, line, message)), file_(std::move(file)), line_(line),
      message_(std::move(message)) {}

std::string short_reason(const std::exception& e) {
  const std::string what = e.what();
  constexpr std::string_view kTag = "[json.exception.";
  if (what.rfind(kTag, 0) != 0) return what;
  const auto end_of_tag = what.find("] ");
  const auto text = end_of_tag == std::string::npos ? what : what.substr(end_of_tag + 2);
  if (what.compare(kTag.size(), 11, "parse_error") == 0) {
    const auto at = text.find("at line ");
    if (at == std::string::npos) return "not valid JSON";
    const auto colon = text.find(':', at);
    return fmt::format("not valid JSON ({})", text.substr(at + 3, colon == std::string::npos ? std::string::npos : colon - at - 3));
  }
  if (what.compare(kTag.size(), 10, "type_error") == 0) return fmt::format("a value of the wrong type ({})", text);
  return text;
}

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
