#pragma once
// What granstack may replace or remove: only what it made. A directory counts as made by
// granstack when it holds a case manifest (manifest.json), a sweep index (sweep.json) or the
// marker table and plot leave in their output directories (.granstack-output), each readable
// as granstack writes it.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace granstack::formats {

inline constexpr const char* kOutputMarker = ".granstack-output";

bool made_by_granstack(const std::filesystem::path& dir);
// The command that made the output directory `dir` ("granstack plot -o", "granstack reproduce"),
// from its marker; "" when it has none.
std::string output_written_by(const std::filesystem::path& dir);

// What made `dir`, as a command's words: "granstack generate" for a case or a sweep, the
// marker's command for another output directory ("granstack reproduce", "granstack plot -o"),
// "" for a directory granstack did not make. Each command replaces only what it made itself.
std::string made_by(const std::filesystem::path& dir);
inline constexpr const char* kGenerate = "granstack generate";

// Why `path` may not be replaced (removed and written anew) even with --force, or "" when it
// may: it must be a directory made by granstack, and neither '/', the home directory, the
// working directory nor one of its parents. A regular file or anything else is never replaced.
// With `by` (a command as made_by() says it), it must also be that command's: generate never
// replaces a reproduction, nor validate a report folder.
std::string why_not_replaceable(const std::filesystem::path& path, const std::string& by = "");

// What lies in `dir`, a case or sweep granstack made, that granstack did not write there (a
// user's notes, an analysis folder): paths relative to `dir`, directories ending in '/', at most
// `most` of them. A case holds its inputs, its run's outputs and lock, reduce/ and export's
// paraview/ (when marked), validate's copies; a sweep its index, slurm/ and its cases.
std::vector<std::string> foreign_entries(const std::filesystem::path& dir, std::size_t most = 10);

// An output is in the way (exit 3): nothing is written.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// It exists and --force was not given.
class ExistsError : public OutputError {
 public:
  using OutputError::OutputError;
};
// It is something granstack never replaces, whatever the flags: a user's file or directory,
// '.', a parent of the working directory, '/', the home directory.
class RefusedError : public OutputError {
 public:
  using OutputError::OutputError;
};

// Before a command writes `names` into the directory `dir` (table -o, plot -o): a new directory
// is made and marked as granstack's; in an existing one, a file of `names` that is already there
// is replaced only with `force`, and only when `command` itself made the directory (another
// command's output directory is as good as the user's: new files only). Throws ExistsError or
// RefusedError naming the file.
void prepare_output_directory(const std::filesystem::path& dir, const std::vector<std::string>& names, bool force,
                              const std::string& command);

}  // namespace granstack::formats
