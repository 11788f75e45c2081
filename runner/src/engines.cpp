#include <granstack/runner/engines.hpp>

#include "engine.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace granstack::runner {

namespace {
// Each engine's contact rules: LIGGGHTS's and LAMMPS's their own (the model's rows say what each
// lacks); refsim LIGGGHTS's, whose frame also runs refsim's own Thornton, or LAMMPS's.
std::string_view liggghts_refuses(const model::ContactModel& m, bool) { return model::liggghts_refusal(m); }
std::string_view lammps_refuses(const model::ContactModel& m, bool) { return model::lammps_refusal(m); }
std::string_view refsim_refuses(const model::ContactModel& m, bool lammps_rules) {
  return lammps_rules ? model::lammps_refusal(m) : model::refsim_liggghts_refusal(m);
}
}  // namespace

const std::vector<EngineRow>& engine_table() {
  static const std::vector<EngineRow> table{
      {Engine::liggghts, "liggghts", "the real DEM code", {"--liggghts", "--np", "--grid"},
       {"--liggghts", "liggghts", "LIGGGHTS"}, make_liggghts_engine, liggghts_refuses},
      {Engine::refsim, "refsim", "the in-house reference integrator", {"--threads", "--kernel", "--contact-rules"}, {},
       make_refsim_engine, refsim_refuses},
      {Engine::lammps, "lammps", "LAMMPS's GRANULAR package, the case's contacts mapped onto its models",
       {"--lammps", "--lammps-template", "--np"}, {"--lammps", "lmp", "LAMMPS"}, make_lammps_engine, lammps_refuses},
  };
  return table;
}

std::string engine_list(bool with_help) {
  const auto& table = engine_table();
  std::string out;
  for (std::size_t i = 0; i < table.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == table.size() ? " or " : ", ") + table[i].name;
    if (with_help) out += " (" + table[i].help + ")";
  }
  return out;
}

const EngineRow& engine_row(Engine e) {
  for (const auto& row : engine_table()) {
    if (row.engine == e) return row;
  }
  throw std::logic_error("an engine without a row in engine_table()");
}

std::vector<std::string> engines_owning(const std::string& option) {
  std::vector<std::string> out;
  for (const auto& row : engine_table()) {
    if (std::find(row.options.begin(), row.options.end(), option) != row.options.end()) out.push_back(row.name);
  }
  return out;
}

std::vector<std::string> engine_options() {
  std::set<std::string> seen;
  std::vector<std::string> out;
  for (const auto& row : engine_table()) {
    for (const auto& o : row.options) {
      if (seen.insert(o).second) out.push_back(o);
    }
  }
  return out;
}

const std::vector<std::string>& engine_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& row : engine_table()) n.push_back(row.name);
    return n;
  }();
  return names;
}

std::string to_string(Engine e) { return engine_row(e).name; }

Engine parse_engine(const std::string& name) {
  for (const auto& row : engine_table()) {
    if (row.name == name) return row.engine;
  }
  throw std::invalid_argument("'" + name + "' is no engine: give " + engine_list());
}

std::string_view model_refusal(Engine e, const model::ContactModel& m, bool lammps_rules) {
  return engine_row(e).refusal(m, lammps_rules);
}

}  // namespace granstack::runner
