#include <granstack/formats/digest.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/postproc/document.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/model/version.hpp>
#include <granstack/study/report.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <variant>

namespace granstack::study {

namespace fs = std::filesystem;

namespace {

// The report as a list of blocks (postproc/document.hpp), rendered once as Markdown and once as HTML.
using postproc::Block;
using postproc::Heading;
using postproc::Paragraph;

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
  int cases = 0, warnings = 0;
  for (const auto& e : r.experiments) {
    cases += static_cast<int>(e.cases.size());
    for (const auto& c : e.cases) warnings += c.reduction ? static_cast<int>(c.reduction->warnings.size()) : 0;
  }
  return fmt::format("granstack {} ({}), {}. Engine: {}{}{}. {} cases, {} failed, {} reduce warning{} (each in its "
                     "experiment's section){}; {:.1f} s of wall time.",
                     version(), git_commit(), date, r.engine, r.validated ? ", every case validated against the other engine" : "",
                     r.quick ? ", --quick subset" : r.full ? ", --full set" : "", cases, r.failed_cases, warnings,
                     warnings == 1 ? "" : "s",
                     r.interrupted ? fmt::format(", {} interrupted (the run was stopped: run the same command again to "
                                                 "finish)", r.interrupted_cases)
                                   : "",
                     r.wall_seconds);
}

// From the paper's value: "+3.2 %", with "(+1.4 sigma)" where the value has a standard error.
std::string from_paper_text(const Verdict& v) {
  if (!v.from_paper) return "-";
  const double p = 100.0 * *v.from_paper, a = std::fabs(p);
  if (a < 0.0005) return "0.000 %";
  auto out = a < 1.0 ? fmt::format("{:+.3f} %", p) : a < 10.0 ? fmt::format("{:+.2f} %", p) : a < 100.0 ? fmt::format("{:+.1f} %", p)
                                                                                                     : fmt::format("{:+.0f} %", p);
  if (v.sigmas) out += fmt::format(" ({:+.2g} s.e.)", *v.sigmas);
  return out;
}

// Whose statement a claim is, in the summary's words.
std::string whose(const Claim& c) {
  return c.scope == "paper" ? "the paper" : c.scope == "granstack" ? "granstack's" : c.scope;
}

// The statement with what its analysis adds for the summary (ExperimentResult::claim_notes).
std::string statement_text(const ExperimentResult& e, const Claim& c) {
  const auto it = e.claim_notes.find(c.quantity);
  return it == e.claim_notes.end() ? c.statement : fmt::format("{} ({})", c.statement, it->second);
}

// Where a reduced case's blow stood when its run ended: "ended at T s", or why not.
std::string blow_text(const CaseRecord& c) {
  if (!c.reduction) return "-";
  if (c.reduction->blow_end_time) return fmt::format("ended at {:.4g} s", *c.reduction->blow_end_time);
  return "NOT ENDED: " + c.reduction->blow_not_ended;
}

// The cases of an experiment whose blow had not ended when their run did, of those `claim` reads:
// the cases its primary reading names (v_ratio.steel_rho4 reads steel_rho4,
// sideways_cut_run.free.cols4.mu0.1 reads free_cols4_mu0.1: the name among its parts, '.' and '_'
// alike), or every case where it names none; `named`: whether it named any.
std::vector<std::string> unended_cases(const ExperimentResult& e, const Claim& claim, bool& named) {
  const auto parts = [](std::string s) {
    std::replace(s.begin(), s.end(), '.', '_');
    return "_" + s + "_";
  };
  const auto quantity = parts(claim.quantity);
  const auto reads = [&](const CaseRecord& c) { return quantity.find(parts(c.name)) != std::string::npos; };
  named = std::any_of(e.cases.begin(), e.cases.end(), reads);
  std::vector<std::string> out;
  for (const auto& c : e.cases) {
    if ((!named || reads(c)) && c.reduction && !c.reduction->blow_end_time) out.push_back(c.name);
  }
  return out;
}

// The summary's statement of a verdict: the statement with what its analysis adds, the cases it
// reads whose blow had not ended, and the readings of the same quantity that would turn it.
std::string summary_text(const ExperimentResult& e, const Verdict& v) {
  bool named = false;
  const auto unended = unended_cases(e, *v.claim, named);
  auto text = statement_text(e, *v.claim);
  if (!unended.empty()) {
    text += fmt::format(" [{} {} case{} whose blow had not ended: {}]", named ? "it reads" : "its experiment holds",
                        unended.size(), unended.size() == 1 ? "" : "s", fmt::join(unended, ", "));
  }
  if (const auto other = v.other_side(); !other.empty()) {
    text += fmt::format(" [{} at this reading only: {} at {}]", v.verdict, v.verdict == "within" ? "outside" : "within",
                        fmt::join(other, ", "));
  }
  return text;
}

Table summary_table(const StudyResult& r) {
  Table t{"Every statement, whose it is, granstack's primary reading of it (fixed in the catalogue; the record below "
          "lists every change), its distance from the paper's value (\"from the paper\": (granstack - paper) / paper, "
          "in standard errors where a fit gives one) and the verdict against the band (\"outside, by X %\": X % "
          "beyond the band's nearer edge, a different percentage)",
          {"claim", "whose", "the statement", "paper", "granstack", "from the paper", "band", "verdict", "expected"}, {}, {7}};
  for (const auto& e : r.experiments) {
    for (const auto& v : e.verdicts) {
      t.rows.push_back({v.claim->id, whose(*v.claim), summary_text(e, v), value_text(v.claim->paper),
                        value_text(v.value), from_paper_text(v), band_text(*v.claim), verdict_text(v), v.claim->expect});
    }
  }
  return t;
}

// Every change to a statement, reading, band, paper value, scope, geometry or physics of the experiments that ran.
Table record_table(const StudyResult& r) {
  Table t{"The record: every change to a claim's statement, reading, band, paper value or scope, or to an experiment's "
          "geometry or physics, "
          "since the catalogue first fixed it (study/data/catalogue.toml)",
          {"date", "commit", "claim or experiment", "field", "before", "after", "with results known", "why"}, {}};
  auto add = [&](const std::string& who, const Record& rec) {
    if (rec.fixed_with_results) {
      std::vector<std::string> values;
      for (const auto& [field, value] : rec.fixed) values.push_back(fmt::format("{} {}", field, value));
      t.rows.push_back({rec.date, rec.commit, who, "first fixed", "-", fmt::format("{}", fmt::join(values, "; ")), "yes",
                        "fixed in the commit that first reported its results"});
    }
    for (const auto& c : rec.changes) {
      t.rows.push_back({c.date, c.commit.empty() ? fmt::format("{} (this build)", std::string(git_commit()).substr(0, 7)) : c.commit,
                        who, c.field, c.before, c.after,
                        c.results_known ? "yes" : "no", c.why});
    }
  };
  for (const auto& e : r.experiments) {
    add(e.experiment->name, e.experiment->record);
    for (const auto& c : e.experiment->claims) add(c.id, c.record);
  }
  std::stable_sort(t.rows.begin(), t.rows.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return t;
}

// A change of an experiment's geometry or physics made with its results in view (the record's
// start of a field, "not recorded" before it, changes nothing).
bool changed_with_results(const Record& r) {
  return std::any_of(r.changes.begin(), r.changes.end(),
                     [](const Change& x) { return x.results_known && x.before != "not recorded"; });
}

// Whether the geometry or physics of the stacks `e`'s claims read was changed with results in view:
// its own, or, for an experiment with no case of its own (eq45 reads Fig. 2's stack), those of the
// experiments it needs.
bool stacks_changed_with_results(const StudyResult& r, const Experiment& e) {
  if (!e.cases.empty()) return changed_with_results(e.record);
  return std::any_of(e.needs.begin(), e.needs.end(), [&](const std::string& name) {
    return std::any_of(r.experiments.begin(), r.experiments.end(), [&](const ExperimentResult& other) {
      return other.experiment->name == name && stacks_changed_with_results(r, *other.experiment);
    });
  });
}

// What the record says in a sentence, computed from it: how many verdicts were settled with
// results in view, by a change to the claim itself or to the geometry or physics it reads.
std::string record_note(const StudyResult& r) {
  int claims = 0, changed = 0;
  std::vector<std::string> own, by_experiment, at_first;
  for (const auto& e : r.experiments) {
    const bool experiment_known = stacks_changed_with_results(r, *e.experiment);
    for (const auto& c : e.experiment->claims) {
      ++claims;
      if (!c.record.changes.empty()) ++changed;
      if (std::any_of(c.record.changes.begin(), c.record.changes.end(), [](const Change& x) { return x.results_known; })) {
        own.push_back(c.id);
      } else if (experiment_known) {
        by_experiment.push_back(c.id);
      } else if (c.record.fixed_with_results || e.experiment->record.fixed_with_results) {
        at_first.push_back(c.id);
      }
    }
  }
  const auto list = [](const std::vector<std::string>& ids) {
    return ids.empty() ? std::string("none") : fmt::format("{}", fmt::join(ids, ", "));
  };
  return fmt::format(
      "The record. Each claim's statement, reading, band, paper value and scope (and a wave speed's timing rule), and each experiment's geometry and physics, is "
      "fixed in the catalogue with the date it was first fixed; every change since is recorded with its date, its "
      "commit, the values before and after and why, and a test fails when a change has no record or, made after its "
      "claim first ran, does not say its results were known. Of the {} claims here, {} verdicts were settled with "
      "results in view: {} by a change to the claim itself ({}), {} by a change to the geometry or physics of its "
      "experiment's stack, or of the stack it reads, alone ({}), and {} fixed first in the commit that first reported their results ({}); those are not "
      "predictions made before the run. {} claims changed in all since they were first fixed; the table below says what "
      "each change was.",
      claims, own.size() + by_experiment.size() + at_first.size(), own.size(), list(own), by_experiment.size(),
      list(by_experiment), at_first.size(), list(at_first), changed);
}

Table claim_table(const ExperimentResult& e) {
  Table t{"The statements: the primary reading, which alone gives the verdict, and the other readings as sensitivity",
          {"claim", "reading", "value", "band", "verdict"}, {}, {4}};
  for (const auto& v : e.verdicts) {
    t.rows.push_back({v.claim->id, v.claim->quantity + " (primary)", value_text(v.value), band_text(*v.claim), verdict_text(v)});
    for (const auto& [q, x] : v.sensitivity) {
      const auto where = !x ? "not measured" : (*x >= v.claim->low && *x <= v.claim->high) ? "in the band" : "not in the band";
      t.rows.push_back({v.claim->id, q, value_text(x), band_text(*v.claim), fmt::format("sensitivity: {}", where)});
    }
    for (const auto& [q, x] : v.context) {
      t.rows.push_back({v.claim->id, q, value_text(x), "-", "context: another quantity, not judged against the band"});
    }
  }
  return t;
}

Table case_table(const ExperimentResult& e, bool validated) {
  Table t{"The cases (the blow: where it stood when the run ended; a reading taken before it ended may still change)",
          {"case", "status", "engine", "the blow", "output", "warnings"}, {}};
  if (validated) t.header.push_back(fmt::format("validate: worst relative difference (where), against {:g}", postproc::kDefaultTolerance));
  for (const auto& c : e.cases) {
    std::vector<std::string> row{c.name, c.status, c.engine.empty() ? "-" : c.engine, blow_text(c),
                                 c.reduction ? fmt::format("{:.4g}", c.reduction->output_fraction) : "-",
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

// Each experiment's main case as granstack ran it: the geometry, boundaries,
// time step and duration, with the rules that chose them.
Table parameter_table(const StudyResult& r) {
  Table t{"The parameters each experiment's main case ran with (the paper's where it states them: 8 rows in Fig. 3, "
          "blocks 'large enough for fully developed solitary waves' in Fig. 2 and 4, r = 1 mm, dt = 1e-9 s)",
          {"experiment", "blocks", "rows", "top columns", "bottom radius (m)", "striker (m/s)", "bottom, sides", "dt (s)",
           "duration (s)", "rules"},
          {}};
  for (const auto& e : r.experiments) {
    for (const auto& c : e.cases) {
      if (!c.reduction || c.name != e.experiment->main) continue;
      const auto& s = c.reduction->spec;
      const auto res = model::resolve(model::Stack::build(s));
      t.rows.push_back({fmt::format("{}/{}", e.experiment->name, c.name), std::to_string(s.blocks), std::to_string(s.rows),
                        std::to_string(s.top_columns), fmt::format("{:g}", s.bottom_radius), fmt::format("{:g}", s.striker_speed),
                        fmt::format("{}, {}", s.bottom == model::Boundary::wall ? "wall" : "free",
                                    s.sides == model::Boundary::wall ? "walls" : "free"),
                        fmt::format("{:.3g}", res.dt),
                        res.stops_at_blow_end ? fmt::format("{} (blow's end; cap {:.3g})", c.reduction->blow_end_time ? fmt::format("{:.3g}", *c.reduction->blow_end_time) : "censored", res.duration)
                                              : fmt::format("{:.3g}", res.duration),
                        fmt::format("dt {}; duration {}{}", res.dt_auto ? "automatic" : "given", res.duration_auto ? "automatic" : "given",
                                    res.soft_cavity ? " (soft cavity: 7 arrivals)" : "")});
      break;
    }
  }
  return t;
}

// The departures from the paper, with the evidence the run computed for each.
std::string parameter_note(const StudyResult& r) {
  auto value = [&](const char* exp, const char* key) -> std::string {
    for (const auto& e : r.experiments) {
      if (e.experiment->name != exp) continue;
      const auto it = e.values.find(key);
      if (it != e.values.end()) return fmt::format("{:.6f}", it->second);
    }
    return "not run (reproduce scale)";
  };
  return fmt::format(
      "The paper integrates with dt = 1e-9 s; granstack chooses dt as the shortest Hertz contact time at the striker "
      "speed over 100 (docs/reference/spec.md, 'The automatic time step and duration'): the three-block stack's output at the automatic "
      "dt over its output at 1e-9 s is {}. The striker runs at 1 m/s and the bottom spheres are 1 mm; the output does "
      "not depend on either (experiment scale: 5 m/s over 1 m/s {}, 100 nm over 1 mm {}). Teflon's Poisson ratio, which "
      "the paper does not give, is 0.46 (the usual value; --full runs 0.35 as sensitivity). The boundaries are the "
      "study's (free bottom, free sides, no gravity) unless the table says otherwise; the duration is twice the "
      "estimated arrival of the pulse at the bottom face, seven times with a soft block between stiffer ones, except "
      "where a case stops at its blow's end (the Teflon experiments), which the table gives with the time it came.",
      value("scale", "output.r1mm_over_dt1e-9"), value("scale", "output.v5_over_v1"), value("scale", "output.r100nm_over_r1mm"));
}

// reproduce --against: each claim beside the other engine's reproduction.
std::string against_note(const EngineComparison& c) {
  double largest = 0.0;
  std::string where = "-";
  for (const auto& d : c.claims) {
    if (d.relative && *d.relative > largest) {
      largest = *d.relative;
      where = d.claim;
    }
  }
  return fmt::format("This reproduction ran on {}; the one in {} on {}: {}; the largest relative difference of a "
                     "claim's value is {:.3g} ({}). Each row names why "
                     "the engines differ on the experiment's cases: the mapping of the spec onto LAMMPS's models "
                     "(docs/explanation/lammps.md) is exact for the Hertz force and the normal damping, and differs "
                     "only where named.",
                     c.engine_here, c.dir, c.engine_there, c.verdict_changes(), largest, where);
}

Table against_table(const EngineComparison& c) {
  Table t{fmt::format("Each claim on {} and on {}", c.engine_here, c.engine_there),
          {"claim", c.engine_here, c.engine_there, "relative difference", "verdict, " + c.engine_here,
           "verdict, " + c.engine_there, "why they differ"},
          {},
          {4, 5}};
  for (const auto& d : c.claims) {
    t.rows.push_back({d.claim, value_text(d.here), value_text(d.there), d.relative ? fmt::format("{:.2g}", *d.relative) : "-",
                      d.verdict_here, d.verdict_there, d.cause});
  }
  return t;
}

void experiment_blocks(const ExperimentResult& e, const StudyResult& r, int level, std::vector<Block>& d);

std::vector<Block> document(const StudyResult& r) {
  std::vector<Block> d;
  d.push_back(Heading{1, "Reproducing the study with granstack", "top"});
  d.push_back(Paragraph{run_line(r)});
  d.push_back(Paragraph{"Each statement of the paper is set beside granstack's measurement of it and judged against an "
                        "acceptance band whose width study/data/catalogue.toml justifies. Every statement has one "
                        "primary reading, fixed in the catalogue, with the same boundaries and definitions for every "
                        "statement of one figure (the record below lists every change to a reading, band, paper value "
                        "or geometry, and which were made with results known); other readings of an ambiguous statement are "
                        "shown in the experiment's section as sensitivity and never count as a pass. 'from the "
                        "paper' is (granstack - paper) / paper, and in standard errors (s.e.) where granstack's value "
                        "comes from a fit that gives one; 'outside, by X %' means the value lies X % beyond the nearer "
                        "band edge, relative to that edge. 'expected' is what the elastic model gives, measured when "
                        "the catalogue was written; a verdict that differs from it means the physics changed. Where "
                        "the model misses the paper, the experiment's section shows the evidence. 'whose' "
                        "says whose statement a claim scores: the paper's, granstack's own extension or model of it, a "
                        "model check (a property of the model the paper's claim rests on) or the paper's arithmetic."});
  if (r.validated) d.push_back(Paragraph{validation_summary(r)});
  d.push_back(summary_table(r));
  if (r.against) {
    d.push_back(Heading{2, "Against " + r.against->engine_there, "against"});
    d.push_back(Paragraph{against_note(*r.against)});
    d.push_back(against_table(*r.against));
  }
  for (const auto& e : r.experiments) {
    for (const auto& c : e.experiment->claims) {
      if (c.scope != "paper") {
        // "granstack's", "a model check", "the paper's arithmetic": whose the statement is.
        const auto whose_text = c.scope == "granstack" ? std::string("granstack's")
                                : c.scope == "arithmetic" ? std::string("the paper's arithmetic")
                                                          : "a " + c.scope;
        d.push_back(Paragraph{fmt::format("{} is {}: {}.", c.id, whose_text, c.scope_reason)});
      }
    }
  }
  if (!r.out_of_scope.empty()) {
    std::string text = "Out of scope, not tested:";
    for (const auto& o : r.out_of_scope) text += fmt::format(" {} ({});", o.statement, o.why);
    text.back() = '.';
    d.push_back(Paragraph{text});
  }
  d.push_back(Heading{2, "The record of the readings", "record"});
  d.push_back(Paragraph{record_note(r)});
  d.push_back(record_table(r));
  d.push_back(Heading{2, "The paper's parameters and granstack's", "parameters"});
  d.push_back(Paragraph{parameter_note(r)});
  d.push_back(parameter_table(r));
  for (const auto& e : r.experiments) {
    if (!e.experiment->beyond) experiment_blocks(e, r, 2, d);
  }
  if (std::any_of(r.experiments.begin(), r.experiments.end(), [](const auto& e) { return e.experiment->beyond; })) {
    d.push_back(Heading{2, "Beyond the paper", "beyond"});
    d.push_back(Paragraph{"What the paper did not ask, measured with the same stacks: no claim of the paper's is judged "
                          "here, and nothing here enters the summary, the verdicts or the record's count of them."});
    for (const auto& e : r.experiments) {
      if (e.experiment->beyond) experiment_blocks(e, r, 3, d);
    }
  }
  return d;
}

// One experiment's section at heading `level`: its explanation, verdicts, notes, tables, figures
// and cases.
void experiment_blocks(const ExperimentResult& e, const StudyResult& r, int level, std::vector<Block>& d) {
  const auto& x = *e.experiment;
  d.push_back(Heading{level, fmt::format("{}: {} ({})", x.name, x.title, x.source), x.name});
  if (!x.explanation.empty()) d.push_back(Paragraph{x.explanation});
  if (!e.verdicts.empty()) d.push_back(claim_table(e));
  for (const auto& v : e.verdicts) {
    d.push_back(Paragraph{fmt::format("{}: band {} because {}.", v.claim->id, band_text(*v.claim), v.claim->band_reason)});
  }
  for (const auto& n : e.notes) d.push_back(Paragraph{n});
  for (const auto& c : e.cases) {
    if (!c.reduction) continue;
    for (const auto& w : c.reduction->warnings) d.push_back(Paragraph{fmt::format("Warning from reduce, {}/{}: {}", x.name, c.name, w)});
  }
  for (const auto& t : e.tables) d.push_back(t);
  for (const auto& f : e.figures) d.push_back(f);
  if (!e.cases.empty()) {
    d.push_back(case_table(e, r.validated));
  } else if (!x.needs.empty()) {
    d.push_back(Paragraph{fmt::format("It runs no case of its own: it reads the cases of {} (their tables are there).",
                                      fmt::join(x.needs, ", "))});
  }
}

nlohmann::json record_json(const Record& r) {
  nlohmann::json changes = nlohmann::json::array();
  for (const auto& c : r.changes) {
    changes.push_back({{"date", c.date}, {"commit", c.commit}, {"field", c.field}, {"before", c.before}, {"after", c.after},
                       {"why", c.why}, {"results_known", c.results_known}});
  }
  return {{"fixed", {{"date", r.date}, {"commit", r.commit}, {"values", r.fixed}}}, {"changes", changes}};
}

nlohmann::json optional_json(const std::optional<double>& v) { return v && std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json(nullptr); }
}  // namespace

nlohmann::json report_json(const StudyResult& r) {
  using nlohmann::json;
  json experiments = json::array();
  for (const auto& e : r.experiments) {
    json claims = json::array(), cases = json::array(), values = json::object();
    for (const auto& v : e.verdicts) {
      json sensitivity = json::object();
      for (const auto& [q, x] : v.sensitivity) sensitivity[q] = optional_json(x);
      json context = json::object();
      for (const auto& [q, x] : v.context) context[q] = optional_json(x);
      claims.push_back({{"id", v.claim->id}, {"statement", v.claim->statement}, {"paper", optional_json(v.claim->paper)},
                        {"band", {v.claim->low, v.claim->high}}, {"band_reason", v.claim->band_reason},
                        {"expect", v.claim->expect}, {"quantity", v.claim->quantity}, {"value", optional_json(v.value)},
                        {"error", optional_json(v.error)}, {"from_paper", optional_json(v.from_paper)},
                        {"sigmas", optional_json(v.sigmas)}, {"verdict", v.verdict}, {"off", v.off},
                        {"sensitivity", sensitivity}, {"context", context}, {"other_side", v.other_side()}, {"scope", v.claim->scope}, {"scope_reason", v.claim->scope_reason},
                        {"summary", summary_text(e, v)}, {"record", record_json(v.claim->record)}});
    }
    for (const auto& [k, x] : e.values) values[k] = std::isfinite(x) ? json(x) : json(nullptr);
    for (const auto& c : e.cases) {
      cases.push_back({{"name", c.name}, {"dir", c.dir}, {"status", c.status}, {"engine", c.engine},
                       {"run_sha256", c.run_sha256}, {"problem", c.problem},
                       {"output_fraction", c.reduction ? json(c.reduction->output_fraction) : json(nullptr)},
                       {"warnings", c.reduction ? json(c.reduction->warnings) : json::array()},
                       {"validate_worst", optional_json(c.validate_worst)}, {"validate_quantity", c.validate_quantity},
                       {"validate_output_fraction", optional_json(c.validate_output)}});
    }
    json figures = json::array();
    for (const auto& f : e.figures) figures.push_back({{"file", f.file}, {"caption", f.caption}});
    experiments.push_back({{"name", e.experiment->name}, {"title", e.experiment->title}, {"source", e.experiment->source},
                           {"beyond", e.experiment->beyond},
                           {"record", record_json(e.experiment->record)},
                           {"claims", claims}, {"values", values}, {"cases", cases}, {"figures", figures}, {"notes", e.notes}});
  }
  json against = nullptr;
  if (r.against) {
    json rows = json::array();
    for (const auto& d : r.against->claims) {
      rows.push_back({{"experiment", d.experiment}, {"claim", d.claim}, {"here", optional_json(d.here)},
                      {"there", optional_json(d.there)}, {"relative", optional_json(d.relative)},
                      {"verdict_here", d.verdict_here}, {"verdict_there", d.verdict_there}, {"cause", d.cause}});
    }
    against = {{"dir", r.against->dir}, {"engine", r.against->engine_there}, {"changed", r.against->changed()},
               {"claims", rows}};
  }
  json report = {{"granstack_version", std::string(version())}, {"against", against}, {"validation", r.validated ? json(validation_summary(r)) : json(nullptr)}, {"git_commit", std::string(git_commit())}, {"engine", r.engine},
          {"validated", r.validated}, {"quick", r.quick}, {"full", r.full}, {"wall_seconds", r.wall_seconds},
          {"failed_cases", r.failed_cases}, {"interrupted_cases", r.interrupted_cases}, {"interrupted", r.interrupted}, {"experiments", experiments}};
  report[kReportDigestKey] = report_digest(report);
  return report;
}

std::string report_digest(const nlohmann::json& report) {
  auto rest = report;
  rest.erase(kReportDigestKey);
  return formats::sha256_hex(rest.dump());
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
  formats::write_file_atomically(fs::path(dir) / "report.md", postproc::markdown(d));
  formats::write_file_atomically(fs::path(dir) / "report.html", postproc::html(d, dir, "granstack: reproducing the study"));
  formats::write_file_atomically(fs::path(dir) / "report.json", report_json(r).dump(2) + "\n");
}

std::string summary_text(const StudyResult& r) {
  auto shorten = [](const std::string& text) { return text.size() <= 56 ? text : text.substr(0, 53) + "..."; };
  std::string out = fmt::format("{:<11} {:>9} {:>10} {:>20}  {:<18} {}\n", "claim", "paper", "granstack", "from the paper",
                                "verdict", "the statement");
  for (const auto& e : r.experiments) {
    for (const auto& v : e.verdicts) {
      out += fmt::format("{:<11} {:>9} {:>10} {:>20}  {:<18} {}{}\n", v.claim->id, value_text(v.claim->paper),
                         value_text(v.value), from_paper_text(v), verdict_text(v),
                         shorten(v.claim->scope == "paper" ? v.claim->statement : fmt::format("[{}] {}", whose(*v.claim), v.claim->statement)),
                         v.verdict == v.claim->expect || v.verdict == "not measured" ? "" : "   (expected " + v.claim->expect + ")");
    }
  }
  if (r.against) {
    out += fmt::format("\nagainst {} ({}): {} (report.md, 'Against {}')\n", r.against->engine_there, r.against->dir,
                       r.against->verdict_changes(), r.against->engine_there);
  }
  out += "\nfrom the paper: (granstack - paper) / paper, in standard errors (s.e.) where a fit gives one; outside, by X %:\n"
         "X % beyond the nearer band edge. Each verdict is on the claim's one primary reading (report.md lists the others).\n";
  return out;
}

}  // namespace granstack::study
