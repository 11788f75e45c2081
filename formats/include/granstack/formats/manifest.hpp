#pragma once
// The case manifest (manifest.json): the spec, provenance, the files of the case, and the
// derived values and id index the generator computed (informative: readers rebuild the
// stack from the spec, which is deterministic).
#include <granstack/formats/json_box.hpp>
#include <granstack/model/spec.hpp>

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace granstack::formats {

// 2: the manifest records the SHA-256 of what generate rendered (`rendered`), and of itself.
inline constexpr int kManifestSchema = 2;

struct CaseFiles {
  std::string data = "data.stack";
  std::string deck = "in.stack";
  std::string dump = "dumps/dump.txt";
  std::string series = "ke_series.txt";
  std::string log = "log.liggghts";
  std::string screen = "liggghts.out";
  std::string run_record = "run.json";
  std::vector<std::string> dump_columns;
  std::vector<std::string> series_columns;
  bool operator==(const CaseFiles&) const = default;
};

// A LAMMPS run's own deck, log and screen files in the case (`run --engine lammps`), beside the
// manifest's (LIGGGHTS's) names; the dump and series are the same.
CaseFiles lammps_files(CaseFiles files);

// The SHA-256 of the deck and data file as generate wrote them; every reader of the results
// checks them (check_case_inputs), so an edited case is never labelled with its manifest's spec.
// The manifest's own digest (of everything but this record) is checked whenever it is read.
struct Rendered {
  std::string deck_sha256;
  std::string data_sha256;
  std::string content_sha256;  // the manifest's own, as read (the case's identity); "" when written anew
  bool operator==(const Rendered&) const = default;
};

struct Manifest {
  int schema = kManifestSchema;
  std::string case_name;
  model::StackSpec spec;
  CaseFiles files;
  std::string granstack_version;
  std::string git_commit;
  std::string created;                    // ISO 8601, UTC
  std::vector<std::string> command_line;  // argv of the generating command
  JsonBox derived;                        // informative
  JsonBox layout;                         // informative
  Rendered rendered;
};

nlohmann::json spec_to_json(const model::StackSpec& spec);
// Throws FormatError (with `source` as the file name) on a missing or mistyped field.
model::StackSpec spec_from_json(const nlohmann::json& j, const std::string& source);

// With `rendered.content_sha256`, the digest of all the other fields (as nlohmann::json dumps them).
nlohmann::json manifest_to_json(const Manifest& m);
// Why DIR is not a case directory, naming what it is (a sweep's, a reproduction's, a design
// search's folder) and what to give instead.
std::string not_a_case(const std::string& dir);

// Throws FormatError for a missing or mistyped field, an older schema, or (with `verify`) a
// manifest whose content no longer has the digest it was written with: it was edited.
Manifest manifest_from_json(const nlohmann::json& j, const std::string& source, bool verify = true);
// Reads CASE/manifest.json. Throws FormatError. Only the question "did granstack make this
// directory?" reads it without `verify`.
Manifest read_manifest(const std::string& case_dir, bool verify = true);

// The path of a case's dump: `name` itself, or the same compressed afterwards with gzip
// (name.gz) or zstd (name.zst). Returns `name` (under `case_dir`) when none exists.
std::string find_dump(const std::string& case_dir, const std::string& name);

// The case directories named by DIRS: a case directory (with manifest.json) stands for itself,
// a sweep directory (with sweep.json) for its cases in sweep order; a case named twice counts
// once. Throws FormatError for a directory that is neither.
std::vector<std::string> expand_case_dirs(const std::vector<std::string>& dirs);

}  // namespace granstack::formats
