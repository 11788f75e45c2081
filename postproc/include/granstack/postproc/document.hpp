#pragma once
// A report as a list of blocks (headings, paragraphs, tables, figures), rendered once as
// Markdown and once as self-contained HTML (styles inline, figures as inline SVG): the study's
// report and the design search's share it.
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace granstack::postproc {

struct Heading {
  int level;
  std::string text, anchor;
};
struct Paragraph {
  std::string text;
};
struct Table {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  // Columns of verdicts: their cells that begin "within" or "outside" take the verdict's colour in
  // HTML (no other cell does: an "expected" column is no verdict).
  std::vector<std::size_t> verdict_columns = {};
};
struct Figure {
  std::string file;     // the SVG, relative to the report's directory
  std::string caption;
};
using Block = std::variant<Heading, Paragraph, Table, Figure>;

std::string markdown(const std::vector<Block>& document);
// Cells that start with "within" or "outside" are shaded (a claim's verdict).
std::string html(const std::vector<Block>& document, const std::filesystem::path& dir, const std::string& title);

}  // namespace granstack::postproc
