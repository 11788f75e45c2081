#pragma once
// Writes case directories: the LIGGGHTS data file, the input deck (decks.hpp) and the manifest.
#include <granstack/formats/data_file.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/generator/decks.hpp>
#include <granstack/generator/spec_input.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include <filesystem>
#include <set>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace granstack::generator {

struct GenerateOptions {
  std::filesystem::path output;          // the case directory, or the sweep directory
  bool force = false;                    // replace an existing directory granstack made
  bool allow_large = false;              // generate cases that model::why_large calls large
  std::optional<std::string> deck_template_path;  // a user's template instead of the default
  std::vector<std::string> command_line;
  // Called as cases are rendered (done of total) and as they are written (total + done of total):
  // a sweep of 10^4 cases takes seconds.
  std::function<void(long done, long total)> on_progress;
};

// Thrown when the output exists and force is off, or is something --force may never replace
// (formats::why_not_replaceable): nothing is written.
using formats::ExistsError;
using formats::RefusedError;

// The names of everything the generated deck writes and the columns of each file.
formats::CaseFiles case_files(const model::Stack& stack);
// The LIGGGHTS data file of a case (atom_style granular): every sphere, its type, radius, density and velocity.
formats::DataFile data_file(const model::Stack& stack, const std::string& case_name);
nlohmann::json derived_json(const model::Stack& stack, const model::Resolution& res);
nlohmann::json layout_json(const model::Stack& stack);

struct GenerateResult {
  std::vector<std::filesystem::path> case_dirs;
  bool sweep = false;  // true: output holds one subdirectory per case and sweep.json
  std::vector<model::Cost> costs;  // per case
  std::vector<model::Resolution> resolutions;  // per case: dt, steps and duration as written
};

// The cost of several cases together.
model::Cost total_cost(const std::vector<model::Cost>& costs);

// One case is written into `output`; several into `output/NAME/` plus `output/sweep.json`.
// Everything is written into a temporary sibling directory first and renamed into place, so
// an error leaves nothing half-written. Throws ExistsError, RefusedError, SpecError or
// std::runtime_error.
GenerateResult generate(const std::vector<CaseSpec>& cases, const GenerateOptions& options);

}  // namespace granstack::generator
