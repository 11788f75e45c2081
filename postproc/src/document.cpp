#include <granstack/formats/files.hpp>
#include <granstack/postproc/document.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace granstack::postproc {

namespace fs = std::filesystem;

namespace {
std::string cell_md(std::string s) {
  std::string out;
  for (const char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

// HTML, self-contained: styles inline, figures as inline SVG.
std::string escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string inline_svg(const fs::path& file) {
  std::string svg;
  try {
    svg = formats::read_file(file.string());
  } catch (const std::exception& e) {
    return fmt::format("<p class=\"missing\">figure missing: {}</p>", escape(e.what()));
  }
  const auto start = svg.find("<svg");
  return start == std::string::npos ? std::string() : svg.substr(start);
}

}  // namespace

std::string markdown(const std::vector<Block>& d) {
  std::string out;
  for (const auto& b : d) {
    if (const auto* h = std::get_if<Heading>(&b)) {
      out += fmt::format("{} {}\n\n", std::string(static_cast<std::size_t>(h->level), '#'), h->text);
    } else if (const auto* p = std::get_if<Paragraph>(&b)) {
      out += p->text + "\n\n";
    } else if (const auto* t = std::get_if<Table>(&b)) {
      out += fmt::format("*{}*\n\n", t->caption);
      std::vector<std::string> header, rule;
      for (const auto& col : t->header) {
        header.push_back(cell_md(col));
        rule.push_back("---");
      }
      out += fmt::format("| {} |\n| {} |\n", fmt::join(header, " | "), fmt::join(rule, " | "));
      for (const auto& row : t->rows) {
        std::vector<std::string> cells;
        for (const auto& c : row) cells.push_back(cell_md(c));
        out += fmt::format("| {} |\n", fmt::join(cells, " | "));
      }
      out += "\n";
    } else if (const auto* f = std::get_if<Figure>(&b)) {
      out += fmt::format("![{}]({})\n\n*{}*\n\n", cell_md(f->caption), f->file, f->caption);
    }
  }
  return out;
}

std::string html(const std::vector<Block>& d, const fs::path& dir, const std::string& title) {
  std::string body;
  for (const auto& b : d) {
    if (const auto* h = std::get_if<Heading>(&b)) {
      body += fmt::format("<h{0} id=\"{1}\">{2}</h{0}>\n", h->level, escape(h->anchor), escape(h->text));
    } else if (const auto* p = std::get_if<Paragraph>(&b)) {
      body += fmt::format("<p>{}</p>\n", escape(p->text));
    } else if (const auto* t = std::get_if<Table>(&b)) {
      body += fmt::format("<table>\n<caption>{}</caption>\n<tr>", escape(t->caption));
      for (const auto& col : t->header) body += fmt::format("<th>{}</th>", escape(col));
      body += "</tr>\n";
      for (const auto& row : t->rows) {
        body += "<tr>";
        for (std::size_t i = 0; i < row.size(); ++i) {
          const auto& c = row[i];
          const bool verdict = std::find(t->verdict_columns.begin(), t->verdict_columns.end(), i) != t->verdict_columns.end();
          const char* cls = !verdict                     ? ""
                            : c.rfind("within", 0) == 0  ? " class=\"within\""
                            : c.rfind("outside", 0) == 0 ? " class=\"outside\""
                                                         : "";
          body += fmt::format("<td{}>{}</td>", cls, escape(c));
        }
        body += "</tr>\n";
      }
      body += "</table>\n";
    } else if (const auto* f = std::get_if<Figure>(&b)) {
      body += fmt::format("<figure>\n{}\n<figcaption>{}</figcaption>\n</figure>\n", inline_svg(dir / f->file), escape(f->caption));
    }
  }
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n"
      "<style>\nbody {{ font-family: sans-serif; max-width: 72em; margin: 2em auto; padding: 0 1em; line-height: 1.4; }}\n"
      "table {{ border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }}\n"
      "caption {{ text-align: left; font-style: italic; padding-bottom: 0.3em; }}\n"
      "th, td {{ border: 1px solid #bbb; padding: 0.25em 0.5em; vertical-align: top; }}\nth {{ background: #eee; }}\n"
      "td.within {{ background: #dff0d8; }}\ntd.outside {{ background: #f8e0c0; }}\n"
      "figure {{ margin: 1.5em 0; }}\nfigure svg {{ width: 100%; height: auto; max-width: 60em; }}\n"
      "figcaption {{ font-style: italic; }}\n"
      "@media print {{ body {{ max-width: none; margin: 0; font-size: 8.5pt; }} table {{ font-size: 8pt; width: 100%; }}\n"
      "  tr, figure {{ page-break-inside: avoid; }} h2 {{ page-break-after: avoid; }} }}\n</style>\n</head>\n<body>\n{}</body>\n</html>\n",
      escape(title), body);
}



}  // namespace granstack::postproc
