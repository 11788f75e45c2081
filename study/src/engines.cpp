#include <granstack/formats/files.hpp>
#include <granstack/study/engines.hpp>

#include <fmt/format.h>

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
    return d.verdict_here != d.verdict_there;
  }));
}

nlohmann::json read_other_report(const std::string& dir, const std::string& engine_here) {
  const auto path = fs::path(dir) / "report.json";
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(formats::read_file(path));
  } catch (const std::exception& e) {
    throw ReproduceError(fmt::format("--against {}: {} cannot be read as a reproduction's report ({}); give the "
                                     "directory of a finished `granstack reproduce`",
                                     dir, path.string(), e.what()));
  }
  if (!j.contains("engine") || !j["engine"].is_string() || !j.contains("experiments")) {
    throw ReproduceError(fmt::format("--against {}: {} is not a reproduction's report (no engine or experiments)", dir,
                                     path.string()));
  }
  if (j["engine"].get<std::string>() == engine_here) {
    throw ReproduceError(fmt::format("--against {}: that reproduction ran on {} too; give one made with another "
                                     "--engine",
                                     dir, engine_here));
  }
  return j;
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

EngineComparison compare_engines(const StudyResult& r, const nlohmann::json& other, const std::string& dir) {
  EngineComparison c;
  c.dir = dir;
  c.engine_here = r.engine;
  c.engine_there = other["engine"].get<std::string>();
  for (const auto& e : r.experiments) {
    const nlohmann::json* theirs = nullptr;
    for (const auto& x : other["experiments"]) {
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
