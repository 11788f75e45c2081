#pragma once
// Small file utilities shared by the stages.
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace granstack::formats {

// Writes `text` to a temporary file beside `path` and renames it over `path`, so a reader never
// sees a half-written file. Throws IoError naming the path.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);
// Writes several files into `dir` all or none: each to its temporary first, and only when every
// one is whole are they renamed into place (a full disk leaves none of them, nor a temporary).
// `files`: (name, text). Throws IoError naming the file that could not be written.
void write_files_atomically(const std::filesystem::path& dir,
                            const std::vector<std::pair<std::string, std::string>>& files);
// Throws FormatError unless `path` is a regular file (after following links): granstack reads
// no FIFO, device or directory, which could block or never end.
void require_regular_file(const std::string& path);
// Why `path` is not a regular file to read ("is missing", "is a FIFO (named pipe): ...", "is
// missing, and PATH.xz is there, compressed with xz, which granstack does not read: ..."), or "".
std::string why_not_a_regular_file(const std::string& path);
// Reads a whole regular file. Throws IoError naming the path (FormatError when it is no regular file).
std::string read_file(const std::filesystem::path& path);
// Writes out what `file` (written with stdio, named `path`) holds buffered and closes it. Throws
// IoError naming the path if the system could not write all of it (a full disk),
// which fwrite alone does not tell: the last buffer goes out at the close.
void close_written(std::FILE* file, const std::string& path);
// The current time as ISO 8601 UTC, e.g. "2026-11-22T00:35:28Z".
std::string utc_timestamp();

}  // namespace granstack::formats
