// The LAMMPS input deck of a case: the same stack, data file, groups, series and dumps as the
// LIGGGHTS deck, with the contacts mapped onto LAMMPS's granular models (model/lammps.hpp).
#include "deck_parts.hpp"

#include <granstack/generator/case_writer.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/model/version.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <set>

namespace granstack::embedded {
std::string_view lammps_template();
}

namespace granstack::generator {

namespace {

// Every type pair's pair_coeff (LAMMPS mixes an unset pair otherwise, and not as LIGGGHTS does).
std::string pair_coeff_lines(const model::StackSpec& spec, const std::vector<std::string>& types,
                             const model::LammpsRules& rules) {
  const auto lib = spec.material_library();
  std::string out;
  for (std::size_t i = 0; i < types.size(); ++i) {
    for (std::size_t j = i; j < types.size(); ++j) {
      const auto& a = types[i];
      const auto& b = types[j];
      const auto c = model::lammps_contact(lib.at(a), lib.at(b), spec.restitution.get(a, b), spec.friction.get(a, b), false, rules);
      out += fmt::format("pair_coeff      {} {} {}\n", i + 1, j + 1, model::lammps_contact_words(c, rules, spec.tangential_model));
    }
  }
  out.pop_back();
  return out;
}

// Whether the spheres lie above a wall along its axis (it bounds them from below: LAMMPS's
// `plane LO NULL`) or below it (`plane NULL HI`).
bool wall_below_spheres(const model::Stack& stack, const model::Wall& w) {
  return std::all_of(stack.spheres().begin(), stack.spheres().end(), [&](const model::Sphere& s) {
    const double c[3] = {s.x, s.y, s.z};
    return c[w.axis] > w.position;
  });
}

// LAMMPS's fix wall/gran takes one set of coefficients for every sphere it acts on, so each wall
// is one fix per atom type that has spheres: the wall's material against that type's.
std::string wall_lines(const model::Stack& stack, const std::vector<std::string>& types, const model::LammpsRules& rules) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  std::string out;
  const auto& wall_material = types[static_cast<std::size_t>(stack.wall_type() - 1)];
  for (const auto& w : stack.walls()) {
    const auto plane = wall_below_spheres(stack, w) ? fmt::format("{} NULL", w.position) : fmt::format("NULL {}", w.position);
    for (std::size_t t = 0; t < types.size(); ++t) {
      const int type = static_cast<int>(t) + 1;
      if (type == stack.wall_type()) continue;
      const auto c = model::lammps_contact(lib.at(types[t]), lib.at(wall_material), spec.restitution.get(types[t], wall_material),
                                           spec.friction.get(types[t], wall_material), true, rules);
      out += fmt::format("fix             {}_{} gs_type{} wall/gran granular {} {}plane {}{}\n", w.name, type, type,
                         model::lammps_contact_words(c, rules, spec.tangential_model), "xyz"[w.axis], plane,
                         w.name == model::kBottomWallName ? " contacts" : "");
    }
  }
  return out;
}

// One group per atom type with spheres, for the walls' fixes.
std::string type_groups(const model::Stack& stack, std::size_t types) {
  std::string out;
  for (std::size_t t = 1; t <= types; ++t) {
    if (static_cast<int>(t) != stack.wall_type()) out += fmt::format("group           gs_type{} type {}\n", t, t);
  }
  return out;
}

// The in-situ energies, as the LIGGGHTS deck's (same columns), each at 17 digits; the bottom
// wall's force is the sum over its fixes (one per atom type) of column 4 (f_z) of `contacts`.
std::string energy_series(const model::Stack& stack, const model::Resolution& res, const formats::CaseFiles& files,
                          std::size_t types) {
  std::string computes, values;
  for (const auto& g : model::series_groups(stack)) {
    computes += fmt::format("compute         kt{} {} ke\ncompute         kr{} {} erotate/sphere\n", g.tag, g.name, g.tag,
                            g.name);
    values += fmt::format(" $(c_kt{}:%.17g) $(c_kr{}:%.17g)", g.tag, g.tag);
  }
  if (stack.spec().bottom == model::Boundary::wall) {
    std::vector<std::string> parts;
    for (std::size_t t = 1; t <= types; ++t) {
      if (static_cast<int>(t) == stack.wall_type()) continue;
      computes += fmt::format("compute         fwb{} all reduce sum f_{}_{}[4]\n", t, model::kBottomWallName, t);
      parts.push_back(fmt::format("c_fwb{}", t));
    }
    computes += fmt::format("variable        fwb equal {}\n", fmt::join(parts, "+"));
    values += " $(v_fwb:%.17g)";
  }
  return fmt::format("{}fix             energy all print {} \"$(step){}\" file {} screen no title \"# {}\"", computes,
                     res.series_every, values, files.series, fmt::join(files.series_columns, " "));
}

// What the deck's contacts were mapped for, and which damping coefficient stands for which of the
// spec's restitutions.
std::string rules_note(const model::StackSpec& spec, const model::LammpsRules& rules) {
  std::string out = fmt::format("# Mapped for {} ({}).\n# {}.", rules.name,
                                rules.run_here ? "checked against a real binary" : "written from its source, not run",
                                rules.source);
  std::set<double> restitutions{spec.restitution.value};
  for (const auto& [pair, e] : spec.restitution.pairs) restitutions.insert(e);
  for (const double e : restitutions) {
    if (!(e < 1.0)) continue;
    if (rules.damping == model::LammpsDamping::coeff_restitution) {
      out += fmt::format("\n# Restitution {}: damping coeff_restitution with e = {} itself (LIGGGHTS's damping law).", e, e);
    } else {
      out += fmt::format("\n# Restitution {}: damping tsuji with e' = {:.17g}, whose alpha(e') is LIGGGHTS's "
                         "sqrt(5) |beta({})| (e' is not the restitution: it stands for it).",
                         e, model::lammps_tsuji_restitution(e), e);
    }
  }
  return out;
}

// Said beside the run: where 29 Sep 2021's fix wall/gran changes its own damping.
std::string run_note(const model::Stack& stack, const model::LammpsRules& rules) {
  if (rules.damping != model::LammpsDamping::tsuji_match || stack.walls().empty()) return "";
  return "# This LAMMPS's fix wall/gran converts its tsuji coefficient in place each time a run does its setup:\n"
         "# keep one `run`, or give every later one `pre no`, or the walls' damping changes from the second\n"
         "# run on.\n";
}

TemplateVars lammps_variables(const model::Stack& stack, const model::Resolution& res, const formats::CaseFiles& files,
                              const std::string& case_name, const model::LammpsRules& rules) {
  const auto& spec = stack.spec();
  const auto types = stack.type_materials();
  TemplateVars v;
  v["case_name"] = case_name;
  v["granstack_version"] = std::string(version());
  v["git_commit"] = std::string(git_commit());
  v["data_file"] = files.data;
  v["processors"] = processors_lines(stack, "LAMMPS");
  v["skin"] = fmt::format("{}", res.skin);
  v["lammps_rules"] = rules_note(spec, rules);
  v["pair_coeffs"] = pair_coeff_lines(spec, types, rules);
  const auto walls = wall_lines(stack, types, rules);
  v["walls"] = walls.empty() ? "# free bottom and free sides: no walls"
                             : type_groups(stack, types.size()) + walls.substr(0, walls.size() - 1);
  v["gravity"] = spec.gravity > 0.0 ? fmt::format("fix             gravity all gravity {} vector 0 0 -1", spec.gravity)
                                    : std::string("# no gravity");
  v["dt"] = fmt::format("{}", res.dt);
  std::string groups;
  for (const auto& g : model::series_groups(stack)) groups += group_command(g);
  groups.pop_back();
  v["groups"] = groups;
  v["energy_series"] = energy_series(stack, res, files, types.size());
  v["dump_every"] = std::to_string(res.dump_every);
  v["dump_file"] = files.dump;
  v["dump_columns"] = fmt::format("{}", fmt::join(files.dump_columns, " "));
  v["dump_modify"] = stack.spec().dump_format == model::DumpFormat::binary
                        ? "dump_modify     stack sort id"
                        : "dump_modify     stack sort id format int %d format float %.17g";
  v["thermo_every"] = std::to_string(res.thermo_every);
  v["run"] = run_note(stack, rules) +
             (res.stops_at_blow_end ? blow_end_run(stack, res, kLammpsDialect) : fmt::format("run             {}", res.steps));
  return v;
}

}  // namespace

std::string_view default_lammps_template() { return embedded::lammps_template(); }

std::string lammps_deck(const model::Stack& stack, const model::Resolution& res, const formats::CaseFiles& files,
                        const std::string& case_name, std::string_view tmpl, std::string_view source,
                        const model::LammpsRules& rules) {
  return render_template(tmpl, lammps_variables(stack, res, files, case_name, rules), source);
}

}  // namespace granstack::generator
