#include <granstack/model/toml_input.hpp>

#include <fmt/format.h>

#include <sstream>

namespace granstack::model {

std::string toml_syntax_error(const toml::parse_error& e, std::string_view source) {
  return fmt::format("{}:{}:{}: TOML syntax error: {}", source, e.source().begin.line, e.source().begin.column,
                     e.description());
}

std::string toml_line(const toml::node& node) { return fmt::format("line {}", node.source().begin.line); }

std::string toml_text(const toml::node& node) {
  std::ostringstream out;
  out << toml::toml_formatter{node};
  return out.str();
}

}  // namespace granstack::model
