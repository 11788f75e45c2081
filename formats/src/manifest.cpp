#include <granstack/formats/digest.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/model/spec_fields.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

namespace granstack::formats {

CaseFiles lammps_files(CaseFiles files) {
  files.deck = "in.lammps";
  files.log = "log.lammps";
  files.screen = "lammps.out";
  return files;
}


using nlohmann::json;

namespace {
bool has_control_character(const std::string& text) {
  return std::any_of(text.begin(), text.end(), [](unsigned char c) { return c < 0x20 || c == 0x7f; });
}

template <typename T>
T get(const json& j, const char* key, const std::string& source) {
  if (!j.contains(key)) throw FormatError(source, 0, fmt::format("missing field '{}'", key));
  try {
    return j.at(key).get<T>();
  } catch (const json::exception& e) {
    throw FormatError(source, 0, fmt::format("field '{}': {}", key, e.what()));
  }
}

}  // namespace

json spec_to_json(const model::StackSpec& s) { return model::spec_json(s); }

model::StackSpec spec_from_json(const json& j, const std::string& source) {
  try {
    return model::spec_from_json_fields(j);
  } catch (const std::invalid_argument& e) {
    throw FormatError(source, 0, e.what());
  }
}

namespace {
// The digest of a manifest's content: every field but `rendered`.
std::string content_digest(json j) {
  j.erase("rendered");
  return sha256_hex(j.dump());
}
}  // namespace

json manifest_to_json(const Manifest& m) {
  json j = {{"schema", m.schema},
          {"case", m.case_name},
          {"granstack", {{"version", m.granstack_version}, {"git_commit", m.git_commit}, {"created", m.created},
                         {"command_line", m.command_line}}},
          {"spec", spec_to_json(m.spec)},
          {"files",
           {{"data", m.files.data}, {"deck", m.files.deck}, {"dump", m.files.dump}, {"series", m.files.series},
            {"log", m.files.log}, {"screen", m.files.screen}, {"run_record", m.files.run_record},
            {"dump_columns", m.files.dump_columns}, {"series_columns", m.files.series_columns}}},
          {"derived", *m.derived},
          {"layout", *m.layout}};
  j["rendered"] = {{"deck_sha256", m.rendered.deck_sha256}, {"data_sha256", m.rendered.data_sha256},
                   {"content_sha256", content_digest(j)}};
  return j;
}

Manifest manifest_from_json(const json& j, const std::string& source, bool verify) {
  Manifest m;
  m.schema = get<int>(j, "schema", source);
  // Unverified (only "did granstack make this?") an older case is still granstack's, to replace.
  const bool older = !verify && m.schema >= 1 && m.schema < kManifestSchema;
  if (m.schema != kManifestSchema && !older) {
    throw FormatError(source, 0, fmt::format("manifest schema {} is not {}{}: generate the case again with this granstack",
                                             m.schema, kManifestSchema,
                                             m.schema < kManifestSchema ? " (an older granstack made it, without the "
                                                                          "digests of its rendered files)"
                                                                        : ""));
  }
  const auto rendered = older ? json::object() : get<json>(j, "rendered", source);
  m.rendered.deck_sha256 = rendered.value("deck_sha256", std::string());
  m.rendered.data_sha256 = rendered.value("data_sha256", std::string());
  m.rendered.content_sha256 = rendered.value("content_sha256", std::string());
  if (verify && get<std::string>(rendered, "content_sha256", source) != content_digest(j)) {
    throw FormatError(source, 0, "the manifest was edited after 'granstack generate' (its content no longer has the "
                                 "SHA-256 recorded in rendered.content_sha256), so its spec may not be what the deck "
                                 "and data file say: generate the case again with the values you want (a deck of your "
                                 "own: 'granstack generate --template FILE')");
  }
  m.case_name = get<std::string>(j, "case", source);
  if (has_control_character(m.case_name)) {
    throw FormatError(source, 0, "field 'case' holds a control character (it is written into the deck): the manifest "
                                 "was edited; generate the case again");
  }
  const auto g = get<json>(j, "granstack", source);
  m.granstack_version = get<std::string>(g, "version", source);
  m.git_commit = get<std::string>(g, "git_commit", source);
  m.created = get<std::string>(g, "created", source);
  m.command_line = get<std::vector<std::string>>(g, "command_line", source);
  m.spec = spec_from_json(get<json>(j, "spec", source), source);
  const auto f = get<json>(j, "files", source);
  m.files.data = get<std::string>(f, "data", source);
  m.files.deck = get<std::string>(f, "deck", source);
  m.files.dump = get<std::string>(f, "dump", source);
  m.files.series = get<std::string>(f, "series", source);
  m.files.log = get<std::string>(f, "log", source);
  m.files.screen = get<std::string>(f, "screen", source);
  m.files.run_record = get<std::string>(f, "run_record", source);
  m.files.dump_columns = get<std::vector<std::string>>(f, "dump_columns", source);
  m.files.series_columns = get<std::vector<std::string>>(f, "series_columns", source);
  m.derived = j.value("derived", json::object());
  m.layout = j.value("layout", json::object());
  return m;
}

std::string not_a_case(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto under = [&](const fs::path& p) { return (fs::path(dir) / p).string(); };
  if (fs::is_regular_file(fs::path(dir) / "sweep.json", ec)) {
    std::string first;
    try {
      first = json::parse(read_file(fs::path(dir) / "sweep.json")).at("cases").at(0).at("dir").get<std::string>();
    } catch (const std::exception&) {
    }
    return fmt::format("is a sweep's directory (granstack generate of several cases): name one of its cases{}",
                       first.empty() ? "" : fmt::format(", e.g. {}", under(first)));
  }
  const auto maker = made_by(dir);
  if (maker == "granstack design run") {
    return "is a design search's folder (granstack design run): its designs live in its store; 'granstack design report' "
           "writes the front's spec files, which 'granstack generate --config FILE -o DIR' makes into cases";
  }
  if (maker == "granstack reproduce") {
    return "is a reproduction's folder (granstack reproduce): its cases are its EXPERIMENT/CASE folders, e.g. " +
           under("fig3/nb1_e1");
  }
  if (!maker.empty()) return fmt::format("is what '{}' wrote, not a case", maker);
  return "holds no manifest.json: it is not a case directory; make one with 'granstack generate -o DIR'";
}

Manifest read_manifest(const std::string& case_dir, bool verify) {
  const std::string path = case_dir + "/manifest.json";
  if (std::filesystem::exists(path)) require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(case_dir, 0, not_a_case(case_dir));
  // Parsed from memory: nlohmann's stream adapter reads a character at a time (half the time of
  // a 10,000-case submit went there).
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw FormatError(path, 0, fmt::format("not valid JSON: {}", e.what()));
  }
  return manifest_from_json(j, path, verify);
}

std::string find_dump(const std::string& case_dir, const std::string& name) {
  namespace fs = std::filesystem;
  const auto plain = fs::path(case_dir) / name;
  if (name.find_first_of("*%") != std::string::npos) return plain.string();  // the reader globs the pieces
  for (const char* suffix : {"", ".gz", ".zst"}) {
    const auto p = plain.string() + suffix;
    if (fs::exists(p)) return p;
  }
  return plain.string();
}

std::vector<std::string> expand_case_dirs(const std::vector<std::string>& dirs) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  std::set<std::string> seen;  // a case named twice (directly and through its sweep) counts once
  auto add = [&](const std::string& dir) {
    if (seen.insert(fs::weakly_canonical(dir).string()).second) out.push_back(dir);
  };
  for (const auto& d : dirs) {
    if (fs::exists(fs::path(d) / "manifest.json")) {
      add(d);
      continue;
    }
    if (output_written_by(d) == "granstack reproduce") {  // DIR/EXPERIMENT/CASE, in name order
      std::set<fs::path> cases;
      std::error_code ec;
      for (const auto& e : fs::directory_iterator(d, ec)) {
        if (!e.is_directory(ec)) continue;
        for (const auto& c : fs::directory_iterator(e.path(), ec)) {
          if (fs::is_regular_file(c.path() / "manifest.json", ec)) cases.insert(c.path());
        }
      }
      for (const auto& c : cases) add(c.string());
      continue;
    }
    const auto sweep_path = (fs::path(d) / "sweep.json").string();
    if (fs::exists(sweep_path)) require_regular_file(sweep_path);
    std::ifstream in(sweep_path);
    if (!in) throw FormatError(d, 0, not_a_case(d) + " (nor a sweep's, with sweep.json)");
    try {
      const auto j = json::parse(in);
      for (const auto& c : j.at("cases")) {
        const auto name = c.at("dir").get<std::string>();
        if (has_control_character(name) || name.find('/') != std::string::npos || name == ".." || name.empty()) {
          throw FormatError(sweep_path, 0, fmt::format("case directory {:?} is not a plain name within the sweep: the "
                                                       "index was edited; generate the sweep again", name));
        }
        add((fs::path(d) / name).string());
      }
    } catch (const json::exception& e) {
      throw FormatError(sweep_path, 0, fmt::format("is damaged ({}): it is not the index 'granstack generate' wrote; "
                                                   "generate the sweep again with --force",
                                                   short_reason(e)));
    }
  }
  return out;
}

}  // namespace granstack::formats
