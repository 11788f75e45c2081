#include <granstack/model/material.hpp>

#include <fmt/format.h>

#include <stdexcept>
#include <granstack/model/toml_input.hpp>

namespace granstack::embedded {
std::string_view materials_toml();
}

namespace granstack::model {

namespace {
double require_number(const toml::table& table, std::string_view material, std::string_view field,
                      std::string_view source) {
  const auto* node = table.get(field);
  if (node == nullptr) {
    throw std::invalid_argument(fmt::format("{}: material '{}' has no '{}'", source, material, field));
  }
  if (auto v = node->value<double>()) return *v;
  throw std::invalid_argument(fmt::format("{}: material '{}': '{}' must be a number", source, material, field));
}
}  // namespace

std::vector<Material> parse_material_table(std::string_view toml_text, std::string_view source_name) {
  const auto root = parse_toml<std::invalid_argument>(toml_text, source_name);
  std::vector<Material> out;
  for (const auto& [key, node] : root) {
    const auto* table = node.as_table();
    if (table == nullptr) {
      throw std::invalid_argument(fmt::format("{}: '{}' must be a table of density, youngs_modulus, poisson_ratio",
                                              source_name, key.str()));
    }
    Material m;
    m.name = std::string(key.str());
    m.density = require_number(*table, m.name, "density", source_name);
    m.youngs_modulus = require_number(*table, m.name, "youngs_modulus", source_name);
    m.poisson_ratio = require_number(*table, m.name, "poisson_ratio", source_name);
    if (table->contains("yield_strength")) m.yield_strength = require_number(*table, m.name, "yield_strength", source_name);
    for (const auto& [field, value] : *table) {
      (void)value;
      if (field != "density" && field != "youngs_modulus" && field != "poisson_ratio" && field != "yield_strength") {
        throw std::invalid_argument(fmt::format(
            "{}: material '{}' has unknown field '{}' (known: density, youngs_modulus, poisson_ratio, yield_strength)",
            source_name, m.name, field.str()));
      }
    }
    out.push_back(std::move(m));
  }
  return out;
}

bool is_study_material(std::string_view name) { return name == "steel" || name == "teflon"; }

MaterialLibrary MaterialLibrary::builtin() {
  // Parsed once: every Stack::build asks for it (10,000 cases of a sweep, 10,000 parses).
  static const MaterialLibrary parsed = [] {
    MaterialLibrary lib;
    for (auto& m : parse_material_table(embedded::materials_toml(), "model/data/materials.toml")) {
      lib.builtin_names_.push_back(m.name);
      lib.add(std::move(m));
    }
    return lib;
  }();
  return parsed;
}

void MaterialLibrary::add(Material material) {
  auto name = material.name;
  materials_.insert_or_assign(std::move(name), std::move(material));
}

const Material* MaterialLibrary::find(std::string_view name) const {
  auto it = materials_.find(name);
  return it == materials_.end() ? nullptr : &it->second;
}

const Material& MaterialLibrary::at(std::string_view name) const {
  if (const auto* m = find(name)) return *m;
  throw std::invalid_argument(fmt::format("unknown material '{}' (known: {}; define others under [materials.NAME])",
                                          name, fmt::join(names(), ", ")));
}

std::vector<std::string> MaterialLibrary::names() const {
  std::vector<std::string> out;
  for (const auto& [name, m] : materials_) out.push_back(name);
  return out;
}

bool MaterialLibrary::is_builtin(std::string_view name) const {
  for (const auto& n : builtin_names_) {
    if (n == name) return true;
  }
  return false;
}

}  // namespace granstack::model
