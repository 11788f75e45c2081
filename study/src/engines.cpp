#include <granstack/formats/case.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/study/engines.hpp>
#include <granstack/study/report.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace granstack::study {

namespace fs = std::filesystem;

// A claim's values that differ by at most this (relative) differ by the engines' arithmetic: the
// same physics run on both agrees to 1e-14 in every dumped column (docs/explanation/lammps.md).
constexpr double kRoundOff = 1e-12;

int EngineComparison::changed() const {
  return static_cast<int>(std::count_if(claims.begin(), claims.end(), [](const EngineDifference& d) {
    return d.verdict_here != "not run" && d.verdict_there != "not run" && d.verdict_here != d.verdict_there;
  }));
}

int EngineComparison::compared() const {
  return static_cast<int>(std::count_if(claims.begin(), claims.end(), [](const EngineDifference& d) {
    return d.verdict_here != "not run" && d.verdict_there != "not run";
  }));
}

std::string EngineComparison::verdict_changes() const {
  const int both = compared();
  const int elsewhere = static_cast<int>(claims.size()) - both;
  if (both == 0) {
    return fmt::format("none of the {} statements was run there (its report holds other experiments): nothing was "
                       "compared",
                       claims.size());
  }
  return fmt::format("{} of {} statements run on both change their verdict{}", changed(), both,
                     elsewhere > 0 ? fmt::format(" ({} not run there)", elsewhere) : "");
}

namespace {

// Why a case the other report counts as done cannot vouch for its claims ("" when it can).
std::string other_case_problem(const fs::path& dir, const nlohmann::json& entry, const std::string& engine) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / "run.json", ec)) return fmt::format("{} has no run.json", dir.string());
  const auto run = formats::read_run_record(dir, formats::CaseFiles{});
  if (!run.done()) return fmt::format("{}: its run is {} now", dir.string(), run.status.empty() ? "gone" : run.status);
  if (formats::run_engine(run) != engine) {
    return fmt::format("{} ran on {}, the report says {}", dir.string(), formats::run_engine(run), engine);
  }
  const auto recorded = entry.value("run_sha256", std::string());
  if (recorded.empty()) {
    return "the report predates granstack's record of each case's run (report.json has no run_sha256)";
  }
  if (formats::sha256_file(dir / "run.json") != recorded) {
    return fmt::format("{} was run again after the report was written", dir.string());
  }
  try {
    const auto why = formats::files_not_as_run(formats::Case::open(dir.string()), run, formats::DigestCheck::quick);
    if (!why.empty()) return fmt::format("{}: {}", dir.string(), why.substr(0, why.find(';')));
  } catch (const std::exception& e) {
    return fmt::format("{}: {}", dir.string(), e.what());
  }
  return "";
}

}  // namespace

OtherReproduction read_other_report(const std::string& dir) {
  const auto path = fs::path(dir) / "report.json";
  OtherReproduction o;
  o.dir = dir;
  try {
    o.report = nlohmann::json::parse(formats::read_file(path));
  } catch (const std::exception& e) {
    throw AgainstError(fmt::format("--against {}: {} cannot be read as a reproduction's report ({}); give the "
                                     "directory of a finished `granstack reproduce`",
                                     dir, path.string(), formats::short_reason(e)));
  }
  auto& j = *o.report;
  if (!j.is_object() || !j.contains("engine") || !j["engine"].is_string() || !j.contains("experiments") ||
      !j["experiments"].is_array()) {
    throw AgainstError(fmt::format("--against {}: {} is not a reproduction's report (no engine or experiments)", dir,
                                     path.string()));
  }
  const auto recorded = j.value(kReportDigestKey, std::string());
  if (recorded.empty() || recorded != report_digest(j)) {
    std::string again = fmt::format("granstack reproduce -o {}", dir);
    for (const auto& x : j["experiments"]) again += " " + x.value("name", "");
    throw AgainstError(fmt::format(
        "--against {}: {} {}, so its values and verdicts cannot be taken as its cases'; write it anew with `{}` (its "
        "finished cases are kept)",
        dir, path.string(),
        recorded.empty() ? "predates granstack's record of its own digest (no report_sha256)"
                         : "was edited after `granstack reproduce` wrote it (the SHA-256 of its content differs from "
                           "its report_sha256)",
        again));
  }
  o.engine = j["engine"].get<std::string>();
  std::vector<std::string> problems;
  for (const auto& x : j["experiments"]) {
    for (const auto& c : x.value("cases", nlohmann::json::array())) {
      if (c.value("status", "") != "done") continue;
      const auto case_dir = fs::path(dir) / x.value("name", "") / c.value("name", "");
      if (auto why = other_case_problem(case_dir, c, o.engine); !why.empty()) problems.push_back(std::move(why));
    }
  }
  if (!problems.empty()) {
    std::string again = fmt::format("granstack reproduce -o {}", dir);  // the command that made it, from its report
    for (const auto& x : j["experiments"]) again += " " + x.value("name", "");
    if (j.value("quick", false)) again += " --quick";
    if (j.value("full", false)) again += " --full";
    throw AgainstError(fmt::format(
        "--against {}: its report does not describe its cases now ({} case{}: {}{}); bring that reproduction up to date "
        "first (`granstack status {}` names each changed case; run those again with `granstack run --force`, then "
        "`{}` writes its report anew)",
        dir, problems.size(), problems.size() == 1 ? "" : "s", problems.front(),
        problems.size() > 1 ? fmt::format("; and {} more", problems.size() - 1) : "", dir, again));
  }
  return o;
}

namespace {

// Which of the two contact rules each engine runs: LIGGGHTS's (LIGGGHTS, refsim) or LAMMPS's.
bool lammps_rules(const std::string& engine) { return engine == "lammps"; }

// Whether any case of e has contacts with restitution below 1, or with friction.
void dissipation(const Experiment& e, bool& damped, bool& frictional) {
  damped = frictional = false;
  for (const auto& c : e.cases) {
    damped = damped || !c.spec.restitution.everywhere(1.0);
    frictional = frictional || !c.spec.friction.everywhere(0.0);
  }
}

}  // namespace

std::string difference_cause(const Experiment& e, const std::string& a, const std::string& b) {
  if (lammps_rules(a) == lammps_rules(b)) {
    return "round-off: both engines run LIGGGHTS's contact law (validate: agreement to round-off)";
  }
  bool damped = false, frictional = false;
  dissipation(e, damped, frictional);
  std::vector<std::string> causes;
  if (frictional) {
    causes.push_back("friction: LAMMPS's mindlin spring is turned into the tangent plane before the step's slip is "
                     "added, takes the full radii for the sliding speed and is reset to the Coulomb cap differently "
                     "from LIGGGHTS's history spring");
  }
  if (damped) {
    causes.push_back("damping: at the run's first force evaluation (step 0, which does not update the history) "
                     "LIGGGHTS applies the tangential damping gamma_t v_t at every touching contact, friction or not "
                     "(its spring is still zero, so the Coulomb cap does not act), LAMMPS no tangential force without "
                     "friction; the normal damping is the same function (tsuji, matched)");
  }
  if (causes.empty()) return "round-off: elastic and frictionless, the same force law on both (agreement to 1e-14)";
  std::string text;
  for (const auto& c : causes) text += (text.empty() ? "" : "; ") + c;
  return text;
}

EngineComparison compare_engines(const StudyResult& r, const OtherReproduction& other) {
  EngineComparison c;
  c.dir = other.dir;
  c.engine_here = r.engine;
  c.engine_there = other.engine;
  for (const auto& e : r.experiments) {
    const nlohmann::json* theirs = nullptr;
    for (const auto& x : (*other.report)["experiments"]) {
      if (x.value("name", "") == e.experiment->name) theirs = &x;
    }
    const auto cause = difference_cause(*e.experiment, c.engine_here, c.engine_there);
    for (const auto& v : e.verdicts) {
      EngineDifference d;
      d.experiment = e.experiment->name;
      d.claim = v.claim->id;
      d.here = v.value;
      d.verdict_here = v.verdict;
      d.verdict_there = "not run";
      if (theirs != nullptr) {
        for (const auto& claim : (*theirs)["claims"]) {
          if (claim.value("id", "") != d.claim) continue;
          if (claim["value"].is_number()) d.there = claim["value"].get<double>();
          d.verdict_there = claim.value("verdict", "not measured");
        }
      }
      if (d.here && d.there) {
        const double scale = std::max(std::abs(*d.here), std::abs(*d.there));
        d.relative = scale > 0.0 ? std::abs(*d.here - *d.there) / scale : 0.0;
      }
      // A difference at round-off has no cause but the arithmetic.
      if (!d.here || !d.there) {
        d.cause = !d.here && !d.there ? "not measured on either engine" : "measured on one engine only";
      } else {
        d.cause = *d.relative <= kRoundOff ? fmt::format("none beyond round-off (at most {:g})", kRoundOff) : cause;
      }
      c.claims.push_back(std::move(d));
    }
  }
  return c;
}

}  // namespace granstack::study
