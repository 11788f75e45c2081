#pragma once
// The spec's fields in one table: each field's name, type, range, default, help, whether it
// sweeps, how it is read from text (spec files and flags), checked, and written to and read
// from a manifest. Spec files, the flags of `generate`, validation, the manifest and the
// reference documentation (`granstack fields`) all come from this table, so a new field is a
// row here and a member of StackSpec.
#include <granstack/model/spec.hpp>

#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::model {

// How a field's value is written as text: one value; a list (a spec file's array, a flag's
// comma list), which sweeps when the field is sweepable; entries, repeatable, of a material pair
// ("A:B=VALUE"; in a spec file a table "A:B" = value) or of a custom material
// ("NAME:DENSITY:YOUNGS_MODULUS:POISSON_RATIO"; in a spec file a table of tables).
enum class FieldShape { scalar, list, pair_entries, material_entries };

struct SpecField {
  std::string name;          // in spec files and manifests
  std::string flag;          // generate's flag: --name with '-' for '_', or its own (--restitution-pair)
  std::string type;          // for the reference: "whole number", "number", "text", "list of names", ...
  std::string default_text;  // what an absent field means
  std::string help;          // one line: --help and the reference
  std::string doc;           // the reference's longer text (markdown), added to help
  std::string short_key;     // in sweep case names ("nb" for blocks); empty: not sweepable
  FieldShape shape = FieldShape::scalar;
  bool whole = false;         // a sweep's values are whole numbers
  std::string bare;           // the value of the flag given bare (--gravity: "true"); empty: it takes one
  bool in_every_manifest = false;  // manifests have always had it (an absent one is refused)
  std::string conflicts_with;      // a field that may not be given with it (block_rows: rows)

  // Sets the field from its text tokens, adding an issue for each problem.
  std::function<void(StackSpec&, const std::vector<std::string>&, std::vector<SpecIssue>&)> parse;
  // The value of a sweep (sweepable fields).
  std::function<void(StackSpec&, double)> set_number;
  // Its own range (empty: validate()'s checks across fields hold it).
  std::function<void(const StackSpec&, std::vector<SpecIssue>&)> check;
  // The manifest: writes j[name], or nothing where the field does not apply or keeps a default
  // that older manifests lack; reads j[name] back (throws std::invalid_argument with the reason).
  std::function<void(const StackSpec&, nlohmann::json&)> save;
  std::function<void(StackSpec&, const nlohmann::json&)> load;

  bool sweepable() const { return !short_key.empty(); }
};

// One value of a sweepable field from text: a number, whole where the field is (false with an
// issue otherwise).
bool parse_sweep_value(const SpecField& field, const std::string& token, double& value, std::vector<SpecIssue>& issues);

// Every field, in the reference's order (sweep axes and case names follow it too).
const std::vector<SpecField>& spec_fields();
// The field named `name`, or nullptr.
const SpecField* find_spec_field(std::string_view name);
// Every field's name, comma-separated (for "known fields: ...").
std::string spec_field_names();
// What to say of an unknown field `name`: "did you mean 'blocks'? " when one is a few edits
// away, then the known fields.
std::string unknown_field_hint(std::string_view name);

// The spec as a manifest writes it, and back (throws std::invalid_argument naming the field).
nlohmann::json spec_json(const StackSpec& spec);

// The same spec as a spec file `granstack generate --config` takes (TOML).
std::string spec_toml(const StackSpec& spec);
StackSpec spec_from_json_fields(const nlohmann::json& j);

// The reference table of the fields (markdown), as docs/reference/spec.md shows it.
std::string spec_fields_markdown();

}  // namespace granstack::model
