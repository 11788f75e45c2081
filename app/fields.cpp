// granstack fields: every spec field (model/spec_fields.hpp) with its type, default and
// meaning, and the built-in materials; --markdown gives the reference's tables (docs/reference/
// spec.md holds them, scripts/doc_tables.py checks them).
#include "commands.hpp"

#include <granstack/design/space.hpp>
#include <granstack/model/material.hpp>
#include <granstack/model/spec_fields.hpp>

#include <fmt/format.h>

#include <memory>

namespace granstack::app {

namespace {

// A design space's [fixed] takes one key beside the spec's fields (design/space.hpp).
std::string top_radius_note() {
  return fmt::format("A design space's [fixed] also takes top_radius (m, default {:g}): the top block's sphere radius, "
                     "each design's bottom radius following from its ratios (granstack design; docs/how-to/design.md).",
                     design::kDefaultTopRadius);
}

// A material's yield strength, or why it has none.
std::string yield_text(const model::Material& m) {
  return m.yield_strength ? fmt::format("{:g}", *m.yield_strength) : "none (brittle: not judged)";
}

std::string materials_markdown() {
  const auto lib = model::MaterialLibrary::builtin();
  std::string out = "| material | density (kg/m^3) | Young's modulus (Pa) | Poisson's ratio | yield strength (Pa) | a spec "
                    "may redefine it |\n|---|---|---|---|---|---|\n";
  for (const auto& name : lib.names()) {
    const auto& m = lib.at(name);
    out += fmt::format("| `{}` | {:g} | {:g} | {:g} | {} | {} |\n", name, m.density, m.youngs_modulus, m.poisson_ratio,
                       yield_text(m), model::is_study_material(name) ? "no (the study's)" : "yes, for that spec alone");
  }
  return out;
}

int list_fields(bool markdown, bool materials) {
  if (markdown) {
    fmt::print("{}", materials ? materials_markdown() : model::spec_fields_markdown());
    return kOk;
  }
  if (!materials) {
    for (const auto& f : model::spec_fields()) {
      fmt::print("{:<24} {}{}\n", f.name, f.type, f.sweepable() ? ", sweepable" : "");
      fmt::print("{:<24} {} [default: {}]\n", "", f.help, f.default_text);
    }
    fmt::print("\n{}\n\n", top_radius_note());
  }
  const auto lib = model::MaterialLibrary::builtin();
  fmt::print("Built-in materials (a spec defines more as [custom_materials.NAME] density, youngs_modulus, "
             "poisson_ratio, optionally yield_strength):\n");
  for (const auto& name : lib.names()) {
    const auto& m = lib.at(name);
    fmt::print("  {:<18} {:>7g} kg/m^3  E {:>9.4g} Pa  nu {:.3g}  yield {}\n", name, m.density, m.youngs_modulus,
               m.poisson_ratio, m.yield_strength ? fmt::format("{:.4g} Pa", *m.yield_strength) : "none (brittle)");
  }
  return kOk;
}

}  // namespace

Command add_fields(CLI::App& app) {
  auto markdown = std::make_shared<bool>(false);
  auto materials = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("fields", "List every spec field (its type, default and meaning) and the built-in materials");
  cmd->add_flag("--markdown", *markdown, "As the reference's markdown table");
  cmd->add_flag("--materials", *materials, "The built-in materials only");
  return {cmd, [markdown, materials] { return list_fields(*markdown, *materials); }};
}

}  // namespace granstack::app
