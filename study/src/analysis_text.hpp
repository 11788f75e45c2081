#pragma once
// How the analyses print numbers in their tables and notes.
#include <granstack/study/reproduce.hpp>

#include <fmt/format.h>

#include <optional>
#include <string>

namespace granstack::study {

inline std::string pct(double f) { return fmt::format("{:.3g} %", 100.0 * f); }
inline std::string num(double v) { return fmt::format("{:.4g}", v); }
inline std::string num(const std::optional<double>& v) { return v ? num(*v) : "-"; }
// An analysis's value with its standard error where it has one: "1.1200 +- 0.0300".
inline std::string with_error(const ExperimentResult& out, const std::string& key) {
  const auto er = out.errors.find(key);
  const double v = out.values.at(key);
  return er == out.errors.end() ? num(v) : fmt::format("{:.4f} +- {:.4f}", v, er->second);
}

}  // namespace granstack::study
