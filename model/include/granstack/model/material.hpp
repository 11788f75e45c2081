#pragma once
// Elastic materials of the blocks (physics.md section 3).
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::model {

struct Material {
  std::string name;
  double density = 0.0;         // kg/m^3
  double youngs_modulus = 0.0;  // Pa
  double poisson_ratio = 0.0;   // dimensionless, 0 <= nu < 0.5
  // Pa, the stress at which it starts to yield in tension (its 0.2 % proof stress): what a Hertz
  // contact's first yield is judged by (model/yield.hpp). None for a brittle material (it cracks
  // rather than yields) or one given without it.
  std::optional<double> yield_strength;
  bool operator==(const Material&) const = default;
};

// The study's materials: a spec may not redefine them (steel means the study's steel in every
// case). The other built-in materials (the design library) a spec may define its own way,
// which then holds for that spec alone (cases written before they were built in keep theirs).
bool is_study_material(std::string_view name);

// Built-in materials (from model/data/materials.toml) plus the ones a spec defines.
class MaterialLibrary {
 public:
  // steel and teflon.
  static MaterialLibrary builtin();

  // Adds or replaces a material (a spec may redefine a built-in one on purpose).
  void add(Material material);
  const Material* find(std::string_view name) const;
  // Throws std::invalid_argument naming the known materials when `name` is unknown.
  const Material& at(std::string_view name) const;
  std::vector<std::string> names() const;
  bool is_builtin(std::string_view name) const;

 private:
  std::map<std::string, Material, std::less<>> materials_;
  std::vector<std::string> builtin_names_;
};

// Parses a table of materials in the format of model/data/materials.toml.
// Throws std::invalid_argument with the offending name and field.
std::vector<Material> parse_material_table(std::string_view toml_text, std::string_view source_name);

}  // namespace granstack::model
