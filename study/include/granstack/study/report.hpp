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

// report.json's content, with report_sha256: the SHA-256 of everything else in it (as a manifest
// records its own), so that a report edited by hand is told from the one reproduce wrote.
nlohmann::json report_json(const StudyResult& result);
inline constexpr const char* kReportDigestKey = "report_sha256";
// The digest report_json records: of the report without its own digest.
std::string report_digest(const nlohmann::json& report);

// With --validate: how many cases the two engines agree on, and the largest difference.
std::string validation_summary(const StudyResult& result);

}  // namespace granstack::study
