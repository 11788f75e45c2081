#pragma once
// Specs from TOML files and command-line flags, through one path: every source becomes a map
// of field -> text tokens (later sources override earlier ones), then one parser turns that
// into a sweep and reports every problem with the field's name.
#include <granstack/model/spec.hpp>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace granstack::generator {

using RawSpec = std::map<std::string, std::vector<std::string>>;

// The fields, their types and whether they sweep: model/spec_fields.hpp.

// Reads a TOML spec file. Throws model::SpecError (unknown keys, wrong types) or
// std::runtime_error (unreadable file, TOML syntax, with line and column).
RawSpec read_spec_file(const std::string& path);
RawSpec parse_spec_toml(std::string_view text, const std::string& source);
// Splits a flag's value on commas.
std::vector<std::string> split_list(const std::string& value);

struct SweepAxis {
  std::string field;
  std::vector<double> values;
};

struct Sweep {
  model::StackSpec base;
  std::vector<SweepAxis> axes;  // fields given more than one value
  std::set<std::string> given;  // the fields the input named (to refuse those that would do nothing)
};

// Throws model::SpecError listing every problem.
Sweep build_sweep(const RawSpec& raw);

struct CaseSpec {
  std::string name;  // readable, from the swept values ("nb3_e0.9"); "case" when nothing is swept
  model::StackSpec spec;
};

// One case per combination of the axes (the last axis varies fastest). Every case is
// validated, and a field the input gave that would do nothing in it is refused (ignored_fields);
// throws model::SpecError naming the case.
std::vector<CaseSpec> expand(const Sweep& sweep);

// The fields of `given` that would do nothing in `spec`, each with why (a container's field on a
// strip, a wall's material with no wall, rolling friction's model with none, no_history's
// friction where nothing damps): a value set that has no effect is a mistake, never a choice.
std::vector<model::SpecIssue> ignored_fields(const model::StackSpec& spec, const std::set<std::string>& given);

}  // namespace granstack::generator
