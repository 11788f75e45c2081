#include <granstack/runner/engines.hpp>

#include "engine.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace granstack::runner {

namespace {
// The table, in --engine's order: each engine's row is in its own file, row i being enumerator i
// (add_engine gives the next one).
std::vector<EngineRow>& rows() {
  static std::vector<EngineRow> table = [] {
    std::vector<EngineRow> t{liggghts_row(), refsim_row(), lammps_row()};
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (t[i].engine != static_cast<Engine>(i)) throw std::logic_error("engine '" + t[i].name + "' out of its enumerator's place");
    }
    return t;
  }();
  return table;
}
}  // namespace

const std::vector<EngineRow>& engine_table() { return rows(); }

Engine add_engine(EngineRow row) {
  auto& table = rows();
  row.engine = static_cast<Engine>(table.size());
  for (const auto& r : table) {
    if (r.name == row.name || r.engine == row.engine) throw std::logic_error("engine '" + row.name + "' added twice");
  }
  table.push_back(std::move(row));
  return table.back().engine;
}

std::string RunOptions::program(Engine e) const {
  const auto it = programs.find(e);
  return it != programs.end() ? it->second : engine_row(e).program.name;
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

std::vector<std::string> engine_names() {
  std::vector<std::string> names;
  for (const auto& row : engine_table()) names.push_back(row.name);
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

std::string case_refusal(Engine e, const model::StackSpec& s, bool lammps_rules) {
  if (const auto why = model_refusal(e, s.contact_model(), lammps_rules); !why.empty()) return std::string(why);
  if (!s.has_plate() || engine_row(e).carries_plate) return "";
  std::string carriers;
  for (const auto& row : engine_table()) {
    if (row.carries_plate) carriers += (carriers.empty() ? "" : " or ") + row.name;
  }
  return "plate_mass: a protected plate on a mount runs on " + carriers + " (--engine " +
         carriers.substr(0, carriers.find(' ')) + "); this engine's deck has a rigid bottom wall only";
}

}  // namespace granstack::runner
