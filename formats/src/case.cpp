#include <granstack/formats/case.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <system_error>

namespace granstack::formats {

namespace fs = std::filesystem;
using nlohmann::json;

std::string run_engine(const RunRecord& record) {
  const auto engine = record.record->value("engine", json());
  if (!engine.is_string()) return "";
  const auto name = engine.get<std::string>();
  if (record.record->value("run_by", std::string()) == "hand") return name + " (run by hand)";
  return name == "refsim" && record.record->value("contact_rules", std::string()) == "lammps" ? "refsim (LAMMPS's rules)" : name;
}

RunRecord read_run_record(const fs::path& case_dir, const CaseFiles& files) {
  RunRecord r;
  r.record = json::object();
  const auto path = case_dir / files.run_record;
  std::error_code ec;
  if (!fs::exists(path, ec)) return r;
  try {
    r.record = json::parse(read_file(path));
    if (!r.record->is_object() || !r.record->contains("status") || !r.record->at("status").is_string()) {
      throw std::runtime_error("it has no status");
    }
    r.status = r.record->at("status").get<std::string>();
    r.error = r.record->value("error", std::string());
  } catch (const std::exception& e) {
    r.record = json::object();
    r.status = "damaged";
    r.error = fmt::format("{} cannot be read ({}): run the case again with --force", path.string(), short_reason(e));
  }
  return r;
}

std::vector<std::string> deck_additions_ran(const RunRecord& record) {
  std::vector<std::string> out;
  const auto executed = record.record->value("executed", json::object());
  if (!executed.is_object()) return out;
  for (const auto& a : executed.value("additions", json::array())) {
    if (a.is_string()) out.push_back(a.get<std::string>());
  }
  return out;
}

long frames_written(const Case& c) {
  if (c.spec().stop != model::StopRule::blow_end) return c.derived().frames();
  const auto record = read_run_record(c.dir(), c.files());
  const auto steps = record.record->value("steps", json());
  if (!steps.is_number_integer() || steps.get<long>() < 0 || steps.get<long>() > c.derived().steps ||
      steps.get<long>() % c.derived().dump_every != 0) {
    throw FormatError((fs::path(c.dir()) / c.files().run_record).string(), 0,
                      "this case stops at the blow's end, and its run record does not say where its run stopped (a "
                      "whole number of dump intervals up to the cap): run the case with granstack");
  }
  return steps.get<long>() / c.derived().dump_every + 1;
}

void write_run_record(const fs::path& case_dir, const CaseFiles& files, const json& record) {
  write_file_atomically(case_dir / files.run_record, record.dump(2) + "\n");
}

namespace {
// A derived value as the manifest holds it; refused when missing or not a number.
template <typename T>
T derived_value(const json& derived, const char* key, const std::string& source) {
  if (!derived.is_object() || !derived.contains(key) || !derived.at(key).is_number()) {
    throw FormatError(source, 0, fmt::format("derived.{} is missing or not a number: generate the case again", key));
  }
  return derived.at(key).get<T>();
}
}  // namespace

Case Case::open(const std::string& dir) {
  Case c;
  c.dir_ = dir;
  c.manifest_ = read_manifest(dir);
  const auto source = (fs::path(dir) / "manifest.json").string();
  const auto& d = *c.manifest_.derived;
  c.derived_ = {derived_value<double>(d, "dt", source), derived_value<double>(d, "duration", source),
                derived_value<long>(d, "steps", source), derived_value<long>(d, "dump_every", source),
                derived_value<long>(d, "series_every", source)};
  if (!(c.derived_.dt > 0.0) || c.derived_.steps < 1 || c.derived_.dump_every < 1 || c.derived_.series_every < 1) {
    throw FormatError(source, 0, "its derived dt, steps or output cadences are not positive: generate the case again");
  }
  return c;
}

const model::Stack& Case::stack() const {
  std::call_once(stack_->built, [this] { stack_->stack.emplace(model::Stack::build(manifest_.spec)); });
  return *stack_->stack;
}

model::Cost Case::cost() const {
  const auto source = path("manifest.json").string();
  const long spheres = derived_value<long>(*manifest_.derived, "sphere_count", source);
  return model::estimate_cost(manifest_.spec, spheres, derived_.steps, derived_.dump_every, derived_.series_every);
}

void Case::check_derived() const {
  const auto res = resolution();
  if (derived_.dt != res.dt || derived_.steps != res.steps || derived_.dump_every != res.dump_every ||
      derived_.series_every != res.series_every) {
    throw FormatError(path("manifest.json").string(), 0,
                      "its derived dt, steps or output cadences are not what its spec gives: the manifest was edited; "
                      "generate the case again");
  }
}

}  // namespace granstack::formats
