#include <granstack/formats/digest.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

namespace granstack::formats {

using nlohmann::json;

namespace {
bool has_control_character(const std::string& text) {
  return std::any_of(text.begin(), text.end(), [](unsigned char c) { return c < 0x20 || c == 0x7f; });
}

json pairs_to_json(const model::PairTable& t) {
  json out = json::object();
  for (const auto& [key, v] : t.pairs) out[key.first + ":" + key.second] = v;
  return out;
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

model::PairTable pairs_from_json(double value, const json& j, const std::string& source, const char* field) {
  model::PairTable t{value, {}};
  for (const auto& [key, v] : j.items()) {
    auto colon = key.find(':');
    if (colon == std::string::npos || !v.is_number()) {
      throw FormatError(source, 0, fmt::format("{}: entries are \"a:b\": number", field));
    }
    t.set(key.substr(0, colon), key.substr(colon + 1), v.get<double>());
  }
  return t;
}
}  // namespace

namespace {
// Absent from manifests of the study's contact model: hertz, history, no rolling friction.
void read_contact_model(model::StackSpec& s, const json& j, const std::string& source) {
  const auto choice = [&](const char* key, auto parse, auto& target, const char* allowed) {
    if (!j.contains(key)) return;
    const auto m = parse(get<std::string>(j, key, source));
    if (!m) throw FormatError(source, 0, fmt::format("field '{}' is {}", key, allowed));
    target = *m;
  };
  choice("normal_model", model::parse_normal_model, s.normal_model, "'hertz' or 'hooke'");
  choice("tangential_model", model::parse_tangential_model, s.tangential_model, "'history' or 'no_history'");
  choice("rolling_model", model::parse_rolling_model, s.rolling_model, "'off' or 'epsd2'");
  if (j.contains("rolling_friction")) {
    s.rolling_friction = pairs_from_json(get<double>(j, "rolling_friction", source),
                                         get<json>(j, "rolling_friction_pairs", source), source, "rolling_friction_pairs");
  }
  if (j.contains("characteristic_velocity")) s.characteristic_velocity = get<double>(j, "characteristic_velocity", source);
}
}  // namespace

json spec_to_json(const model::StackSpec& s) {
  json mats = json::object();
  for (const auto& m : s.custom_materials) {
    mats[m.name] = {{"density", m.density}, {"youngs_modulus", m.youngs_modulus}, {"poisson_ratio", m.poisson_ratio}};
  }
  auto opt = [](const auto& o) -> json { return o ? json(*o) : json("auto"); };
  json j = {{"geometry", model::to_string(s.geometry)},
          {"blocks", s.blocks},
          {"rows", s.rows},
          {"top_columns", s.top_columns},
          {"bottom_radius", s.bottom_radius},
          {"radius_ratio", s.radius_ratio},
          {"materials", s.materials},
          {"custom_materials", mats},
          {"restitution", s.restitution.value},
          {"restitution_pairs", pairs_to_json(s.restitution)},
          {"friction", s.friction.value},
          {"friction_pairs", pairs_to_json(s.friction)},
          {"striker_speed", s.striker_speed},
          {"striker_radius_ratio", s.striker_radius_ratio},
          {"striker_material", s.striker_material},
          {"bottom", model::to_string(s.bottom)},
          {"sides", model::to_string(s.sides)},
          {"wall_material", s.wall_material},
          {"gravity", s.gravity},
          {"dt", opt(s.dt)},
          {"duration", opt(s.duration)},
          {"dump_every", opt(s.dump_every)},
          {"series_every", opt(s.series_every)},
          {"dump_format", model::to_string(s.dump_format)},
          {"dump_files", model::to_string(s.dump_files)}};
  // The contact model, written when it is not the study's (so the study's cases keep their digests).
  if (s.normal_model != model::NormalModel::hertz) j["normal_model"] = model::to_string(s.normal_model);
  if (s.tangential_model != model::TangentialModel::history) j["tangential_model"] = model::to_string(s.tangential_model);
  if (s.rolling_model != model::RollingModel::off) {
    j["rolling_model"] = model::to_string(s.rolling_model);
    j["rolling_friction"] = s.rolling_friction.value;
    j["rolling_friction_pairs"] = pairs_to_json(s.rolling_friction);
  }
  if (s.characteristic_velocity) j["characteristic_velocity"] = *s.characteristic_velocity;
  if (s.geometry == model::Geometry::panels) {
    j["panels"] = s.panels;
    j["impact_panel"] = s.strikes_every_panel() ? json("all") : json(s.impact_panel);
    j["separator"] = model::to_string(s.separator);
    j["matrix_material"] = s.matrix_material;
  }
  return j;
}

model::StackSpec spec_from_json(const json& j, const std::string& source) {
  model::StackSpec s;
  // Absent from manifests written before 3D nests: the strip.
  if (j.contains("geometry")) {
    const auto g = model::parse_geometry(get<std::string>(j, "geometry", source));
    if (!g) throw FormatError(source, 0, "field 'geometry' is 'strip', 'nested3d' or 'panels'");
    s.geometry = *g;
  }
  // Written for containers only.
  if (j.contains("panels")) s.panels = get<int>(j, "panels", source);
  if (j.contains("impact_panel")) {
    const auto& v = j.at("impact_panel");
    s.impact_panel = v.is_string() && v.get<std::string>() == "all" ? model::kAllPanels : get<int>(j, "impact_panel", source);
  }
  if (j.contains("separator")) {
    const auto sep = model::parse_separator(get<std::string>(j, "separator", source));
    if (!sep) throw FormatError(source, 0, "field 'separator' is 'matrix', 'walls' or 'none'");
    s.separator = *sep;
  }
  if (j.contains("matrix_material")) s.matrix_material = get<std::string>(j, "matrix_material", source);
  s.blocks = get<int>(j, "blocks", source);
  s.rows = get<int>(j, "rows", source);
  s.top_columns = get<int>(j, "top_columns", source);
  s.bottom_radius = get<double>(j, "bottom_radius", source);
  s.radius_ratio = get<int>(j, "radius_ratio", source);
  s.materials = get<std::vector<std::string>>(j, "materials", source);
  const auto custom = get<json>(j, "custom_materials", source);
  for (const auto& [name, m] : custom.items()) {
    s.custom_materials.push_back({name, get<double>(m, "density", source), get<double>(m, "youngs_modulus", source),
                                  get<double>(m, "poisson_ratio", source)});
  }
  const auto restitution_pairs = get<json>(j, "restitution_pairs", source);
  const auto friction_pairs = get<json>(j, "friction_pairs", source);
  s.restitution = pairs_from_json(get<double>(j, "restitution", source), restitution_pairs, source, "restitution_pairs");
  s.friction = pairs_from_json(get<double>(j, "friction", source), friction_pairs, source, "friction_pairs");
  s.striker_speed = get<double>(j, "striker_speed", source);
  // Absent from manifests written before the striker could be chosen: the study's striker.
  if (j.contains("striker_radius_ratio")) s.striker_radius_ratio = get<double>(j, "striker_radius_ratio", source);
  if (j.contains("striker_material")) s.striker_material = get<std::string>(j, "striker_material", source);
  auto boundary = [&](const char* key) {
    auto b = model::parse_boundary(get<std::string>(j, key, source));
    if (!b) throw FormatError(source, 0, fmt::format("field '{}' is 'free' or 'wall'", key));
    return *b;
  };
  s.bottom = boundary("bottom");
  s.sides = boundary("sides");
  s.wall_material = get<std::string>(j, "wall_material", source);
  s.gravity = get<double>(j, "gravity", source);
  auto opt_double = [&](const char* key) -> std::optional<double> {
    const auto v = get<json>(j, key, source);
    if (v.is_string() && v.get<std::string>() == "auto") return std::nullopt;
    return get<double>(j, key, source);
  };
  auto opt_int = [&](const char* key) -> std::optional<int> {
    const auto v = get<json>(j, key, source);
    if (v.is_string() && v.get<std::string>() == "auto") return std::nullopt;
    return get<int>(j, key, source);
  };
  s.dt = opt_double("dt");
  s.duration = opt_double("duration");
  s.dump_every = opt_int("dump_every");
  s.series_every = opt_int("series_every");
  auto format = model::parse_dump_format(get<std::string>(j, "dump_format", source));
  if (!format) throw FormatError(source, 0, "field 'dump_format' is 'text' or 'binary'");
  s.dump_format = *format;
  auto files = model::parse_dump_files(j.value("dump_files", std::string("single")));
  if (!files) throw FormatError(source, 0, "field 'dump_files' is 'single', 'per_step' or 'per_rank'");
  s.dump_files = *files;
  read_contact_model(s, j, source);
  return s;
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
          {"derived", m.derived},
          {"layout", m.layout}};
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

Manifest read_manifest(const std::string& case_dir, bool verify) {
  const std::string path = case_dir + "/manifest.json";
  if (std::filesystem::exists(path)) require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path, 0, "cannot open: is this a case directory made by 'granstack generate'?");
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
    if (!in) {
      throw FormatError(d, 0, "not a case directory (no manifest.json) nor a sweep directory (no sweep.json); "
                              "make one with 'granstack generate -o DIR'");
    }
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
      throw FormatError(sweep_path, 0, fmt::format("not a valid sweep index: {}", e.what()));
    }
  }
  return out;
}

}  // namespace granstack::formats
