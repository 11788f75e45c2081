#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cstdlib>

namespace granstack::formats {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
bool json_object_with(const fs::path& file, const char* key) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;
  try {
    const auto j = json::parse(read_file(file));
    return j.is_object() && j.contains(key);
  } catch (const std::exception&) {
    return false;
  }
}

// `inner` is `outer` or lies below it (both absolute and normal).
bool within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}
}  // namespace

bool made_by_granstack(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return false;
  if (fs::is_regular_file(dir / "manifest.json", ec)) {
    try {
      read_manifest(dir.string());
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }
  return json_object_with(dir / "sweep.json", "cases") || json_object_with(dir / kOutputMarker, "written_by");
}

std::string why_not_replaceable(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::symlink_status(path, ec);
  if (!fs::exists(status)) return "";
  const auto target = fs::weakly_canonical(fs::absolute(path), ec);
  const auto cwd = fs::current_path(ec);
  if (target == target.root_path()) return fmt::format("{} is the root directory", path.string());
  if (const char* home = std::getenv("HOME"); home != nullptr && home[0] != '\0' &&
                                              target == fs::weakly_canonical(home, ec)) {
    return fmt::format("{} is your home directory", path.string());
  }
  if (within(cwd, target)) {
    return fmt::format("{} is the working directory or one of its parents", path.string());
  }
  if (fs::is_symlink(status)) return fmt::format("{} is a symbolic link", path.string());
  if (fs::is_regular_file(status)) return fmt::format("{} is a file, not a directory granstack made", path.string());
  if (!fs::is_directory(status)) return fmt::format("{} is not a directory", path.string());
  if (!made_by_granstack(path)) {
    return fmt::format("{} was not made by granstack (it holds no manifest.json, sweep.json or {})", path.string(),
                       kOutputMarker);
  }
  return "";
}

void prepare_output_directory(const fs::path& dir, const std::vector<std::string>& names, bool force,
                              const std::string& command) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec))) {
    fs::create_directories(dir);
    write_file_atomically(dir / kOutputMarker,
                          json{{"written_by", command},
                               {"note", "made by granstack, which replaces the files it wrote here only with --force"}}
                                  .dump(2) + "\n");
    return;
  }
  if (!fs::is_directory(dir, ec)) {
    throw RefusedError(fmt::format("{} exists and is not a directory; name a directory with -o", dir.string()));
  }
  const bool ours = json_object_with(dir / kOutputMarker, "written_by");
  for (const auto& name : names) {
    const auto file = dir / name;
    if (!fs::exists(fs::symlink_status(file, ec))) continue;
    if (!ours) {
      throw RefusedError(fmt::format("{} exists and {} was not made by granstack: granstack does not replace files it "
                                     "did not write; choose a new directory with -o",
                                     file.string(), dir.string()));
    }
    if (!fs::is_regular_file(fs::symlink_status(file, ec))) {
      throw RefusedError(fmt::format("{} exists and is not a regular file; move it away", file.string()));
    }
    if (!force) {
      throw ExistsError(fmt::format("{} exists; pass --force to replace it (or choose a new directory with -o)",
                                    file.string()));
    }
  }
}

}  // namespace granstack::formats
