#pragma once
// What a run wrote, recorded in its run.json ("digests") and checked wherever its outputs are
// read, so results are never reduced under another case's labels: outputs copied in from a
// case with other physics, a run.json copied without its outputs, a file changed since.
#include <granstack/formats/case.hpp>

#include <nlohmann/json_fwd.hpp>

#include <optional>
#include <set>
#include <string>

namespace granstack::formats {

// For run.json: the case the run was of (its manifest's content digest and name), and for each
// output the readers read (every piece of its dump, its series) the size, modification time and
// digest of its content (decompressed: a dump gzipped or zstd-compressed afterwards is still the
// run's), and the size and time of its inputs (manifest, deck, data file; their digests are the
// manifest's own). The outputs' digests are XXH3-128 (formats/digest.hpp says why); a record from
// before holds SHA-256 and is checked with it.
nlohmann::json run_digests(const Case& c);

enum class DigestCheck {
  full,   // every output's content is digested (the commands that read them)
  quick,  // a file whose size and time are as recorded is taken as unchanged; only the others
          // are digested (status, over thousands of cases)
};

// Why the case's files are not those its finished run (`record`) read and wrote, or "" when they
// are: run.json from another case, an input edited since, an output missing, changed, or not
// written by the run. A record without digests (an older granstack's, or edited) cannot vouch for
// the outputs, and says so: its outputs are never read as the case's.
// An output named in `digested_by_caller` is checked to be present and recorded, but its content is
// left to output_not_as_run, with the digest the caller takes while reading it (reduce's dump).
std::string files_not_as_run(const Case& c, const RunRecord& record, DigestCheck how,
                             const std::set<std::string>& digested_by_caller = {});
// Why the output `name` (as run.json names it) is not what its run wrote, or "", given the
// XXH3-128 of its content the caller took while reading it; with nullopt (the caller could not),
// or a record that holds SHA-256, the file is digested here.
std::string output_not_as_run(const Case& c, const RunRecord& record, const std::string& name,
                              const std::optional<std::string>& xxh128);
// The quick look of status over thousands of cases, without the manifest: true when `record`
// holds digests and every input and output it lists has the size and time it recorded (the run's
// files, untouched since); false when anything differs or is missing, and then
// files_not_as_run says what.
bool files_untouched_since_run(const std::filesystem::path& case_dir, const RunRecord& record);

// For the commands that read a case's outputs: throws FormatError (naming run.json) when they are
// not what its run wrote (a full check).
void require_files_as_run(const Case& c);
// The same with files_not_as_run's answer already in hand ("": nothing to refuse).
void refuse_unless_as_run(const Case& c, const std::string& why);

}  // namespace granstack::formats
