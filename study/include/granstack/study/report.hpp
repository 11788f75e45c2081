#pragma once
// The reproduction's report: DIR/report.md, a self-contained DIR/report.html (figures embedded
// as inline SVG, no network needed), and DIR/report.json for machines.
#include <granstack/study/reproduce.hpp>

#include <nlohmann/json_fwd.hpp>
#include <string>

namespace granstack::study {

// Writes the three files into `dir` (each atomically).
void write_report(const StudyResult& result, const std::string& dir);

// The first table of the report, as text for a terminal: every statement with its verdict.
std::string summary_text(const StudyResult& result);

nlohmann::json report_json(const StudyResult& result);

// With --validate: how many cases the two engines agree on, and the largest difference.
std::string validation_summary(const StudyResult& result);

}  // namespace granstack::study
