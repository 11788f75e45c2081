#include <granstack/formats/files.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/model/version.hpp>
#include <granstack/study/report.hpp>

#include <fmt/format.h>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <variant>

namespace granstack::study {

namespace fs = std::filesystem;

namespace {

// The report as a list of blocks, rendered once as Markdown and once as HTML.
struct Heading {
  int level;
  std::string text, anchor;
};
struct Paragraph {
  std::string text;
};
using Block = std::variant<Heading, Paragraph, Table, Figure>;

std::string value_text(const std::optional<double>& v) { return v ? fmt::format("{:.4g}", *v) : "-"; }

std::string band_text(const Claim& c) { return fmt::format("[{:.4g}, {:.4g}]", c.low, c.high); }

std::string verdict_text(const Verdict& v) {
  if (v.verdict == "outside") return fmt::format("outside, by {:.0f} %", 100.0 * v.off);
  return v.verdict;
}

std::string run_line(const StudyResult& r) {
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  int cases = 0;
  for (const auto& e : r.experiments) cases += static_cast<int>(e.cases.size());
  return fmt::format("granstack {} ({}), {}. Engine: {}{}{}. {} cases, {} failed{}; {:.1f} s of wall time.", version(),
                     git_commit(), date, r.engine, r.validated ? ", every case validated against the other engine" : "",
                     r.quick ? ", --quick subset" : "", cases, r.failed_cases,
                     r.interrupted ? fmt::format(", {} interrupted (the run was stopped: run the same command again to "
                                                 "finish)", r.interrupted_cases)
                                   : "",
                     r.wall_seconds);
}

Table summary_table(const StudyResult& r) {
  Table t{"Every statement of the paper with granstack's measurement and the verdict against the band",
          {"claim", "the paper says", "paper", "granstack", "band", "verdict", "expected"}, {}};
  for (const auto& e : r.experiments) {
    for (const auto& v : e.verdicts) {
      const auto measured = v.readings.size() > 1 && v.value ? fmt::format("{} ({})", value_text(v.value), v.reading) : value_text(v.value);
      t.rows.push_back({v.claim->id, v.claim->statement, value_text(v.claim->paper), measured, band_text(*v.claim),
                        verdict_text(v), v.claim->expect});
    }
  }
  return t;
}

Table claim_table(const ExperimentResult& e) {
  Table t{"The statements, every reading", {"claim", "reading", "value", "band", "verdict"}, {}};
  for (const auto& v : e.verdicts) {
    for (const auto& [q, x] : v.readings) {
      const bool chosen = q == v.reading;
      t.rows.push_back({v.claim->id, q, value_text(x), band_text(*v.claim),
                        !x ? "not measured" : chosen ? verdict_text(v) : (*x >= v.claim->low && *x <= v.claim->high) ? "within" : "outside"});
    }
  }
  return t;
}

Table case_table(const ExperimentResult& e, bool validated) {
  Table t{"The cases", {"case", "status", "output", "warnings"}, {}};
  if (validated) t.header.push_back(fmt::format("validate: worst relative difference (where), against {:g}", postproc::kDefaultTolerance));
  for (const auto& c : e.cases) {
    std::vector<std::string> row{c.name, c.status, c.reduction ? fmt::format("{:.4g}", c.reduction->output_fraction) : "-",
                                 c.reduction ? std::to_string(c.reduction->warnings.size()) : c.problem.substr(0, 120)};
    if (validated) {
      row.push_back(!c.validate_worst ? "-"
                    : fmt::format("{:.2e} ({}), {}", *c.validate_worst, c.validate_quantity,
                                  *c.validate_worst <= postproc::kDefaultTolerance ? "agree" : "over"));
    }
    t.rows.push_back(row);
  }
  return t;
}

std::vector<Block> document(const StudyResult& r) {
  std::vector<Block> d;
  d.push_back(Heading{1, "Reproducing the study with granstack", "top"});
  d.push_back(Paragraph{run_line(r)});
  d.push_back(Paragraph{"Each statement of the paper is set beside granstack's measurement of it and judged against an "
                        "acceptance band whose width study/data/catalogue.toml justifies. 'expected' is what the "
                        "elastic model gives, measured when the catalogue was written; a verdict that differs from it "
                        "means the physics changed. Where the model misses the paper, the experiment's section shows "
                        "the evidence and the likely reason."});
  if (r.validated) d.push_back(Paragraph{validation_summary(r)});
  d.push_back(summary_table(r));
  for (const auto& e : r.experiments) {
    const auto& x = *e.experiment;
    d.push_back(Heading{2, fmt::format("{}: {} ({})", x.name, x.title, x.source), x.name});
    if (!x.explanation.empty()) d.push_back(Paragraph{x.explanation});
    if (!e.verdicts.empty()) d.push_back(claim_table(e));
    for (const auto& v : e.verdicts) {
      std::vector<std::string> within;
      for (const auto& [q, value] : v.readings) {
        if (value && *value >= v.claim->low && *value <= v.claim->high) within.push_back(q);
      }
      const auto readings = v.readings.size() < 2 ? std::string()
                            : within.empty()      ? " No reading falls within it."
                                                  : fmt::format(" Within it: {}.", fmt::join(within, ", "));
      d.push_back(Paragraph{fmt::format("{}: band {} because {}.{}", v.claim->id, band_text(*v.claim), v.claim->band_reason, readings)});
    }
    for (const auto& n : e.notes) d.push_back(Paragraph{n});
    for (const auto& t : e.tables) d.push_back(t);
    for (const auto& f : e.figures) d.push_back(f);
    d.push_back(case_table(e, r.validated));
  }
  return d;
}

// Markdown.
std::string cell_md(std::string s) {
  std::string out;
  for (const char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

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

std::string html(const std::vector<Block>& d, const fs::path& dir) {
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
        for (const auto& c : row) {
          const char* cls = c.rfind("within", 0) == 0 ? " class=\"within\"" : c.rfind("outside", 0) == 0 ? " class=\"outside\"" : "";
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
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>granstack: reproducing the study</title>\n"
      "<style>\nbody {{ font-family: sans-serif; max-width: 72em; margin: 2em auto; padding: 0 1em; line-height: 1.4; }}\n"
      "table {{ border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }}\n"
      "caption {{ text-align: left; font-style: italic; padding-bottom: 0.3em; }}\n"
      "th, td {{ border: 1px solid #bbb; padding: 0.25em 0.5em; vertical-align: top; }}\nth {{ background: #eee; }}\n"
      "td.within {{ background: #dff0d8; }}\ntd.outside {{ background: #f8e0c0; }}\n"
      "figure {{ margin: 1.5em 0; }}\nfigure svg {{ width: 100%; height: auto; max-width: 60em; }}\n"
      "figcaption {{ font-style: italic; }}\n</style>\n</head>\n<body>\n{}</body>\n</html>\n",
      body);
}

nlohmann::json optional_json(const std::optional<double>& v) { return v && std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json(nullptr); }

}  // namespace

nlohmann::json report_json(const StudyResult& r) {
  using nlohmann::json;
  json experiments = json::array();
  for (const auto& e : r.experiments) {
    json claims = json::array(), cases = json::array(), values = json::object();
    for (const auto& v : e.verdicts) {
      json readings = json::object();
      for (const auto& [q, x] : v.readings) readings[q] = optional_json(x);
      claims.push_back({{"id", v.claim->id}, {"statement", v.claim->statement}, {"paper", optional_json(v.claim->paper)},
                        {"band", {v.claim->low, v.claim->high}}, {"band_reason", v.claim->band_reason},
                        {"expect", v.claim->expect}, {"reading", v.reading}, {"value", optional_json(v.value)},
                        {"error", optional_json(v.error)}, {"verdict", v.verdict}, {"off", v.off}, {"readings", readings}});
    }
    for (const auto& [k, x] : e.values) values[k] = std::isfinite(x) ? json(x) : json(nullptr);
    for (const auto& c : e.cases) {
      cases.push_back({{"name", c.name}, {"dir", c.dir}, {"status", c.status}, {"problem", c.problem},
                       {"output_fraction", c.reduction ? json(c.reduction->output_fraction) : json(nullptr)},
                       {"warnings", c.reduction ? json(c.reduction->warnings) : json::array()},
                       {"validate_worst", optional_json(c.validate_worst)}, {"validate_quantity", c.validate_quantity},
                       {"validate_output_fraction", optional_json(c.validate_output)}});
    }
    json figures = json::array();
    for (const auto& f : e.figures) figures.push_back({{"file", f.file}, {"caption", f.caption}});
    experiments.push_back({{"name", e.experiment->name}, {"title", e.experiment->title}, {"source", e.experiment->source},
                           {"claims", claims}, {"values", values}, {"cases", cases}, {"figures", figures}, {"notes", e.notes}});
  }
  return {{"granstack_version", std::string(version())}, {"validation", r.validated ? json(validation_summary(r)) : json(nullptr)}, {"git_commit", std::string(git_commit())}, {"engine", r.engine},
          {"validated", r.validated}, {"quick", r.quick}, {"wall_seconds", r.wall_seconds},
          {"failed_cases", r.failed_cases}, {"interrupted_cases", r.interrupted_cases}, {"interrupted", r.interrupted}, {"experiments", experiments}};
}

// How the two engines agreed over every case.
std::string validation_summary(const StudyResult& r) {
  int cases = 0, agree = 0, same_output = 0;
  double worst = -1.0, worst_output = 0.0;
  std::string where;
  for (const auto& e : r.experiments) {
    for (const auto& c : e.cases) {
      if (!c.validate_worst) continue;
      ++cases;
      if (*c.validate_worst <= postproc::kDefaultTolerance) ++agree;
      if (c.validate_output && *c.validate_output == 0.0) ++same_output;
      if (c.validate_output) worst_output = std::max(worst_output, *c.validate_output);
      if (!(*c.validate_worst <= worst)) {
        worst = *c.validate_worst;
        where = fmt::format("{}/{}, {}", e.experiment->name, c.name, c.validate_quantity);
      }
    }
  }
  return fmt::format("Validation: every case also ran on the other engine and every dumped column, series column and the "
                     "output fraction were compared (granstack validate). {} of {} cases agree to a relative difference "
                     "of at most {:g} (validate's default, round-off); the largest difference is {:.3g} ({}). The output "
                     "fractions are identical in {} of {} cases and differ by at most {:.2g} (relative) in the others.",
                     agree, cases, postproc::kDefaultTolerance, worst, where, same_output, cases, worst_output);
}

void write_report(const StudyResult& r, const std::string& dir) {
  const auto d = document(r);
  formats::write_file_atomically(fs::path(dir) / "report.md", markdown(d));
  formats::write_file_atomically(fs::path(dir) / "report.html", html(d, dir));
  formats::write_file_atomically(fs::path(dir) / "report.json", report_json(r).dump(2) + "\n");
}

std::string summary_text(const StudyResult& r) {
  auto shorten = [](const std::string& text) { return text.size() <= 64 ? text : text.substr(0, 61) + "..."; };
  std::string out = fmt::format("{:<11} {:>9} {:>10}  {:<18} {}\n", "claim", "paper", "granstack", "verdict", "the paper says");
  for (const auto& e : r.experiments) {
    for (const auto& v : e.verdicts) {
      out += fmt::format("{:<11} {:>9} {:>10}  {:<18} {}{}\n", v.claim->id, value_text(v.claim->paper), value_text(v.value),
                         verdict_text(v), shorten(v.claim->statement),
                         v.verdict == v.claim->expect || v.verdict == "not measured" ? "" : "   (expected " + v.claim->expect + ")");
    }
  }
  return out;
}

}  // namespace granstack::study
