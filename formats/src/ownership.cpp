#include <granstack/formats/case.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <granstack/formats/dump.hpp>

#include <cstdlib>
#include <fstream>
#include <set>

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
// The files postproc::reduce_case writes into CASE/reduce.
const std::set<std::string> kReduceFiles{"block_ke.csv", "energy_parts.csv", "row_ke.csv",  "column_ke.csv",
                                         "column_y_ke.csv", "panel_ke.csv", "summary.json"};

class ForeignFinder {
 public:
  explicit ForeignFinder(std::size_t most) : most_(most) {}
  std::vector<std::string> found;

  void sweep(const fs::path& dir, const std::string& prefix) {
    std::set<std::string> cases;
    try {
      const auto index = json::parse(read_file(dir / "sweep.json"));
      for (const auto& c : index.at("cases")) cases.insert(c.at("dir").get<std::string>());
    } catch (const std::exception&) {
    }
    each(dir, [&](const fs::directory_entry& e, const std::string& name) {
      if (name == "sweep.json" || name == "slurm" || temporary(name)) return true;
      if (cases.count(name) != 0 && e.is_directory()) {
        if (fs::exists(e.path() / "manifest.json")) one_case(e.path(), prefix + name + "/");
        return true;
      }
      return false;
    }, prefix);
  }

  void one_case(const fs::path& dir, const std::string& prefix) {
    Manifest m;
    try {
      m = read_manifest(dir.string(), false);
    } catch (const std::exception&) {
      return add(prefix + "manifest.json");
    }
    // Every file granstack writes in a case, relative to it.
    const auto lammps = lammps_files(m.files);  // an earlier run on LAMMPS leaves its own deck, log and screen
    std::set<std::string> files{"manifest.json", m.files.data, m.files.deck, m.files.series, m.files.log,
                                m.files.screen, m.files.run_record, ".granstack.lock", lammps.deck, lammps.log,
                                lammps.screen};
    for (const auto& piece : dump_files_matching((dir / m.files.dump).string())) {
      for (const char* suffix : {"", ".gz", ".zst"}) files.insert(fs::path(piece + suffix).lexically_relative(dir).string());
    }
    for (const auto& f : kReduceFiles) files.insert("reduce/" + f);
    try {  // what the run made beyond those (a user's template writing more files): run.json lists them
      for (const auto& f : read_run_record(dir, m.files).record->value("outputs", json::array())) {
        files.insert(f.get<std::string>());
      }
    } catch (const std::exception&) {
    }
    // The folders they sit in, and those granstack makes whole.
    std::set<std::string> folders{fs::path(m.files.dump).parent_path().string(), "reduce", "validate"};
    for (const auto& f : files) {
      for (auto p = fs::path(f).parent_path(); !p.empty(); p = p.parent_path()) folders.insert(p.string());
    }
    walk(dir, dir, prefix, files, folders);
  }

 private:
  // The entries below `at` in the case `root`: a file is granstack's when listed (or a temporary,
  // or LIGGGHTS's forced restart); a folder when listed (then its entries are looked at), export's
  // marked paraview/, the stash of an earlier run, or one of validate's copies (a case of its own).
  void walk(const fs::path& root, const fs::path& at, const std::string& prefix, const std::set<std::string>& files,
            const std::set<std::string>& folders) {
    each(at, [&](const fs::directory_entry& e, const std::string& name) {
      const auto rel = e.path().lexically_relative(root).string();
      std::error_code ec;
      if (!e.is_directory(ec) || e.is_symlink(ec)) {
        return files.count(rel) != 0 || temporary(name) || name.rfind("restart_forced_liggghts_", 0) == 0;
      }
      if (name == ".granstack-earlier-run") return true;  // run's stash of an earlier run's outputs
      if (rel == "paraview") return json_object_with(e.path() / kOutputMarker, "written_by");
      if ((rel == "validate/liggghts" || rel == "validate/refsim" || rel == "validate/lammps") &&
          fs::exists(e.path() / "manifest.json")) {
        one_case(e.path(), prefix + rel + "/");
        return true;
      }
      if (folders.count(rel) == 0) return false;
      walk(root, e.path(), prefix, files, folders);
      return true;
    }, prefix + (at == root ? "" : at.lexically_relative(root).string() + "/"));
  }
  static bool temporary(const std::string& name) {
    return name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0;
  }
  void add(const std::string& entry) {
    if (found.size() < most_) found.push_back(entry);
  }
  // Calls `ours` for each entry of `dir`; what it does not claim is foreign.
  template <typename Ours>
  void each(const fs::path& dir, Ours ours, const std::string& prefix) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const auto name = e.path().filename().string();
      if (!ours(e, name)) add(prefix + name + (e.is_directory(ec) && !e.is_symlink(ec) ? "/" : ""));
    }
  }
  std::size_t most_;
};
}  // namespace

std::vector<std::string> foreign_entries(const fs::path& dir, std::size_t most) {
  ForeignFinder finder(most);
  std::error_code ec;
  if (fs::is_regular_file(dir / "manifest.json", ec)) {
    finder.one_case(dir, "");
  } else if (fs::is_regular_file(dir / "sweep.json", ec)) {
    finder.sweep(dir, "");
  }
  return finder.found;
}

std::string output_written_by(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / kOutputMarker, ec)) return "";
  try {
    return json::parse(read_file(dir / kOutputMarker)).value("written_by", std::string());
  } catch (const std::exception&) {
    return "";
  }
}

namespace {
// A design directory (granstack design run): its SQLite store, by name and by SQLite's header.
bool design_directory(const fs::path& dir) {
  std::ifstream in(dir / "design.sqlite", std::ios::binary);
  char header[16] = {};
  return in.read(header, sizeof header) && std::string_view(header, sizeof header) == std::string_view("SQLite format 3\0", 16);
}
}  // namespace

std::string made_by(const fs::path& dir) {
  if (!made_by_granstack(dir)) return "";
  std::error_code ec;
  if (fs::is_regular_file(dir / "manifest.json", ec) || json_object_with(dir / "sweep.json", "cases")) return kGenerate;
  if (design_directory(dir)) return "granstack design run";
  return output_written_by(dir);
}

bool made_by_granstack(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return false;
  if (fs::is_regular_file(dir / "manifest.json", ec)) {
    try {
      read_manifest(dir.string(), false);  // an edited case is still granstack's
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }
  return json_object_with(dir / "sweep.json", "cases") || json_object_with(dir / kOutputMarker, "written_by") ||
         design_directory(dir);
}

std::string why_not_replaceable(const fs::path& path, const std::string& by) {
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
  if (const auto maker = made_by(path); !by.empty() && maker != by) {
    return fmt::format("{} was made by {}, not by {}{}", path.string(), maker, by,
                       by == kGenerate ? " (which replaces only a case or a sweep)" : "");
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
  const auto maker = output_written_by(dir);
  for (const auto& name : names) {
    const auto file = dir / name;
    if (!fs::exists(fs::symlink_status(file, ec))) continue;
    if (maker != command) {
      throw RefusedError(fmt::format("{} exists and {} was {}: granstack replaces only files {} wrote; choose a new "
                                     "directory with -o",
                                     file.string(), dir.string(),
                                     maker.empty() ? std::string("not made by granstack") : "made by " + maker, command));
    }
    // A directory granstack wrote there (reduce -o writes one per case) is replaced like a file.
    const bool own_directory = fs::is_directory(fs::symlink_status(file, ec));
    if (!fs::is_regular_file(fs::symlink_status(file, ec)) && !own_directory) {
      throw RefusedError(fmt::format("{} exists and is neither a file nor a directory; move it away", file.string()));
    }
    if (!force) {
      throw ExistsError(fmt::format("{} exists; pass --force to replace it (or choose a new directory with -o)",
                                    file.string()));
    }
  }
}

}  // namespace granstack::formats
