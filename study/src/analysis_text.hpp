#pragma once
// How the analyses print numbers in their tables and notes.
#include <fmt/format.h>

#include <optional>
#include <string>

namespace granstack::study {

inline std::string pct(double f) { return fmt::format("{:.3g} %", 100.0 * f); }
inline std::string num(double v) { return fmt::format("{:.4g}", v); }
inline std::string num(const std::optional<double>& v) { return v ? num(*v) : "-"; }

}  // namespace granstack::study
