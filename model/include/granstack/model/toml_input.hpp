#pragma once
// Reading a TOML document (a spec, a material library, a design space, the study's catalogue):
// one parse, whose syntax error names the file, line and column the same way for every reader,
// and what every reader's messages quote of a value. Included by the readers only (it brings
// toml++ with it).
#include <toml++/toml.h>

#include <stdexcept>
#include <string>
#include <string_view>

namespace granstack::model {

// "SOURCE:LINE:COLUMN: TOML syntax error: WHAT".
std::string toml_syntax_error(const toml::parse_error& e, std::string_view source);

// The document in `text`; a syntax error throws Error(toml_syntax_error(...)), the reader's own
// exception type.
template <typename Error = std::runtime_error>
toml::table parse_toml(std::string_view text, std::string_view source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw Error(toml_syntax_error(e, source));
  }
}

// Where a value stands in its file: "line N".
std::string toml_line(const toml::node& node);
// A value as the file wrote it, in TOML (a string quoted, a list bracketed).
std::string toml_text(const toml::node& node);

}  // namespace granstack::model
