#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/run_digests.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sys/stat.h>
#include <map>
#include <set>

namespace granstack::formats {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kCompressed[] = {".gz", ".zst"};

// Size and modification time (ns since 1970) of a file, as stat(2) gives them; false when absent.
bool stat_file(const fs::path& p, long long& bytes, long long& mtime_ns) {
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) return false;
  bytes = static_cast<long long>(st.st_size);
  mtime_ns = static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  return true;
}

// The file holding `name` in the case: itself, or its compressed copy (find_dump's rule, which
// every reader follows); "" when none is there.
fs::path present(const Case& c, const std::string& name) {
  const fs::path p = find_dump(c.dir(), name);
  std::error_code ec;
  return fs::is_regular_file(p, ec) ? p : fs::path();
}

// The outputs the readers read, by their uncompressed names relative to the case.
std::vector<std::string> output_names(const Case& c) {
  std::vector<std::string> names;
  for (auto piece : dump_files_matching(c.path(c.files().dump).string())) {
    for (const std::string ext : kCompressed) {
      if (piece.size() > ext.size() && piece.compare(piece.size() - ext.size(), ext.size(), ext) == 0) {
        piece.resize(piece.size() - ext.size());
      }
    }
    auto rel = fs::path(piece).lexically_relative(c.dir()).string();
    if (std::find(names.begin(), names.end(), rel) == names.end()) names.push_back(std::move(rel));
  }
  names.push_back(c.files().series);
  return names;
}

json stat_of(const fs::path& p) {
  long long bytes = 0, ns = 0;
  if (!stat_file(p, bytes, ns)) throw FormatError(p.string(), 0, fmt::format("cannot stat: {}", std::strerror(errno)));
  return {{"bytes", bytes}, {"mtime_ns", ns}};
}

bool same_stat(const fs::path& p, const json& recorded) {
  long long bytes = 0, ns = 0;
  return stat_file(p, bytes, ns) && recorded.value("bytes", -1LL) == bytes && recorded.value("mtime_ns", -1LL) == ns;
}

std::string record_problem(const fs::path& run_json) {
  return fmt::format("; {} no longer describes the case's files: run it again with 'granstack run --force'",
                     run_json.string());
}

std::string check_case(const Case& c, const json& d) {
  const auto recorded = d.value("case_sha256", std::string());
  if (recorded == c.manifest().rendered.content_sha256) return "";
  return fmt::format("its run.json is the record of another case ('{}', manifest digest {}; this case's is {})",
                     d.value("case", std::string("?")), recorded.substr(0, 12),
                     c.manifest().rendered.content_sha256.substr(0, 12));
}

std::string check_inputs(const Case& c, const json& inputs) {
  const auto& m = c.manifest();
  const std::map<std::string, std::string> digest{{m.files.deck, m.rendered.deck_sha256},
                                                  {m.files.data, m.rendered.data_sha256}};
  for (const auto& [name, stat] : inputs.items()) {
    const auto p = c.path(name);
    if (same_stat(p, stat)) continue;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return fmt::format("its input {} is gone since the run", p.string());
    const auto it = digest.find(name);  // the manifest itself is verified whenever it is read
    if (it != digest.end() && sha256_file(p) != it->second) {
      return fmt::format("its input {} was edited after 'granstack generate'", p.string());
    }
  }
  return "";
}

// Why the output `p` (recorded as `rec`) is not what its run wrote; `xxh128`, when known, is its
// content's XXH3-128, taken by the caller.
std::string check_output_content(const fs::path& p, const json& rec, const std::optional<std::string>& xxh128) {
  // Runs record XXH3-128; records from before (2026-11-28) hold SHA-256, checked as they are.
  const bool xxh = rec.contains("xxh3_128");
  const auto digest = !xxh ? sha256_content(p) : xxh128 ? *xxh128 : xxh128_content(p);
  if (digest == rec.value(xxh ? "xxh3_128" : "sha256", std::string())) return "";
  return fmt::format("{} is not what its run wrote (its {} differs from run.json's: copied from another case, or "
                     "changed since)",
                     p.string(), xxh ? "XXH3-128 digest" : "SHA-256");
}

std::string check_outputs(const Case& c, const json& outputs, DigestCheck how, const std::set<std::string>& later) {
  for (const auto& name : output_names(c)) {
    if (!outputs.contains(name) && !present(c, name).empty()) {
      return fmt::format("{} was not written by its run (copied in afterwards?)", c.path(name).string());
    }
  }
  for (const auto& [name, rec] : outputs.items()) {
    const auto p = present(c, name);
    if (p.empty()) {
      const auto path = c.path(name).string();
      auto why = why_not_a_regular_file(path);
      if (why.empty() || why == "is missing") why = "is missing";
      return fmt::format("{}, which its run wrote, {}", path, why);
    }
    if (how == DigestCheck::quick && same_stat(p, rec)) continue;
    if (later.count(name) > 0 && rec.contains("xxh3_128")) continue;  // output_not_as_run's
    if (auto why = check_output_content(p, rec, std::nullopt); !why.empty()) return why;
  }
  return "";
}

}  // namespace

json run_digests(const Case& c) {
  json outputs = json::object();
  for (const auto& name : output_names(c)) {
    const auto p = present(c, name);
    if (p.empty()) continue;
    auto entry = stat_of(p);
    entry["xxh3_128"] = xxh128_content(p);
    outputs[name] = entry;
  }
  json inputs = json::object();
  for (const auto& name : {std::string("manifest.json"), c.files().deck, c.files().data}) {
    std::error_code ec;
    if (fs::is_regular_file(c.path(name), ec)) inputs[name] = stat_of(c.path(name));
  }
  return {{"case", c.name()}, {"case_sha256", c.manifest().rendered.content_sha256}, {"inputs", inputs},
          {"outputs", outputs}};
}

std::string files_not_as_run(const Case& c, const RunRecord& record, DigestCheck how,
                             const std::set<std::string>& digested_by_caller) {
  if (!record.record->contains("digests")) {
    return "its run.json holds no digests of what its run wrote (a record from a granstack before they were kept, or "
           "edited), so nothing vouches that the outputs in the case are this case's run's and not another's" +
           record_problem(c.path(c.files().run_record));
  }
  const auto& d = record.record->at("digests");
  if (!d.is_object()) return "its run.json's digests are damaged" + record_problem(c.path(c.files().run_record));
  auto why = check_case(c, d);
  if (why.empty()) why = check_inputs(c, d.value("inputs", json::object()));
  if (why.empty()) why = check_outputs(c, d.value("outputs", json::object()), how, digested_by_caller);
  return why.empty() ? why : why + record_problem(c.path(c.files().run_record));
}

std::string output_not_as_run(const Case& c, const RunRecord& record, const std::string& name,
                              const std::optional<std::string>& xxh128) {
  const auto& outputs = record.record->value("digests", json::object()).value("outputs", json::object());
  const auto it = outputs.find(name);
  const auto p = present(c, name);
  // Not recorded or missing: files_not_as_run said so; a SHA-256 record: it checked the content.
  if (it == outputs.end() || p.empty() || !it->contains("xxh3_128")) return "";
  const auto why = check_output_content(p, *it, xxh128);
  return why.empty() ? why : why + record_problem(c.path(c.files().run_record));
}

namespace {
// Whether the folders that hold the run's outputs (the dump's, not the case's own) hold a file the
// run did not write: an extra dump piece, copied in, would be read as part of the dump.
bool output_folders_hold_more(const fs::path& case_dir, const json& outputs) {
  std::set<std::string> folders;
  for (const auto& [name, stat] : outputs.items()) {
    if (const auto parent = fs::path(name).parent_path(); !parent.empty()) folders.insert(parent.string());
  }
  for (const auto& folder : folders) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(case_dir / folder, ec)) {
      if (!entry.is_regular_file(ec)) continue;
      auto name = (fs::path(folder) / entry.path().filename()).string();
      for (const std::string ext : kCompressed) {
        if (name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0) name.resize(name.size() - ext.size());
      }
      if (!outputs.contains(name)) return true;
    }
  }
  return false;
}
}  // namespace

bool files_untouched_since_run(const fs::path& case_dir, const RunRecord& record) {
  const auto& d = record.record->value("digests", json());
  if (!d.is_object()) return false;
  for (const char* part : {"inputs", "outputs"}) {
    const auto& files = d.value(part, json());
    if (!files.is_object() || files.empty()) return false;
    for (const auto& [name, stat] : files.items()) {
      if (!same_stat(case_dir / name, stat)) return false;
    }
  }
  return !output_folders_hold_more(case_dir, d.at("outputs"));
}

void refuse_unless_as_run(const Case& c, const std::string& why) {
  if (!why.empty()) throw FormatError(c.path(c.files().run_record).string(), 0, fmt::format("case {}: {}", c.dir(), why));
}

void require_files_as_run(const Case& c) { refuse_unless_as_run(c, files_not_as_run(c, c.run_record(), DigestCheck::full)); }

}  // namespace granstack::formats
