#include <granstack/model/spec_fields.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace granstack::model {

using nlohmann::json;
using Tokens = std::vector<std::string>;
using Issues = std::vector<SpecIssue>;

namespace {

// ---- Reading text ---------------------------------------------------------------------------

bool parse_number(const std::string& token, double& out) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (first != last && *first == '+') ++first;  // from_chars rejects a leading '+'
  const auto [ptr, ec] = std::from_chars(first, last, out);
  return !token.empty() && ec == std::errc() && ptr == last && std::isfinite(out);
}

bool number(const std::string& field, const std::string& token, double& out, Issues& issues) {
  if (parse_number(token, out)) return true;
  issues.push_back({field, fmt::format("'{}' is not a number", token)});
  return false;
}

bool whole(const std::string& field, const std::string& token, int& out, Issues& issues) {
  double v = 0.0;
  if (!number(field, token, v, issues)) return false;
  if (v != std::floor(v) || std::fabs(v) > 1e9) {
    issues.push_back({field, fmt::format("'{}' is not a whole number", token)});
    return false;
  }
  out = static_cast<int>(v);
  return true;
}

// The one token of a single-valued field, or nullptr (with an issue).
const std::string* single(const std::string& field, const Tokens& tokens, Issues& issues) {
  if (tokens.size() == 1) return &tokens.front();
  issues.push_back({field, fmt::format("takes one value, {} given", tokens.size())});
  return nullptr;
}

// "A:B=VALUE" entries into a pair table's pairs.
void parse_pairs(PairTable& table, const std::string& field, const Tokens& tokens, Issues& issues) {
  for (const auto& t : tokens) {
    const auto colon = t.find(':');
    const auto eq = t.find('=');
    double v = 0.0;
    if (colon == std::string::npos || eq == std::string::npos || eq < colon) {
      issues.push_back({field, fmt::format("'{}' is not MATERIAL_A:MATERIAL_B=VALUE", t)});
    } else if (number(field, t.substr(eq + 1), v, issues)) {
      const auto a = t.substr(0, colon), b = t.substr(colon + 1, eq - colon - 1);
      const auto key = a <= b ? std::make_pair(a, b) : std::make_pair(b, a);
      if (const auto it = table.pairs.find(key); it != table.pairs.end()) {  // a:b and b:a are one pair
        issues.push_back({field, fmt::format("the pair {}:{} is given twice ({} and {}): give each pair once", a, b,
                                             it->second, v)});
        continue;
      }
      table.set(a, b, v);
    }
  }
}

// ---- The manifest ---------------------------------------------------------------------------

template <typename T>
T read(const json& j, const std::string& key) {
  try {
    return j.at(key).get<T>();
  } catch (const json::exception& e) {
    throw std::invalid_argument(e.what());
  }
}

json pairs_json(const PairTable& t) {
  json out = json::object();
  for (const auto& [key, v] : t.pairs) out[key.first + ":" + key.second] = v;
  return out;
}

void load_pairs(PairTable& t, const json& j, const std::string& field) {
  if (!j.is_object()) throw std::invalid_argument(fmt::format("{} is an object of \"a:b\": number", field));
  for (const auto& [key, v] : j.items()) {
    const auto colon = key.find(':');
    if (colon == std::string::npos || !v.is_number()) {
      throw std::invalid_argument(fmt::format("{}: entries are \"a:b\": number", field));
    }
    t.set(key.substr(0, colon), key.substr(colon + 1), v.get<double>());
  }
}

// ---- Rows -----------------------------------------------------------------------------------

std::string flag_of(const std::string& name) {
  std::string flag = "--" + name;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

SpecField row(std::string name, std::string type, std::string default_text, std::string help) {
  SpecField f;
  f.flag = flag_of(name);
  f.name = std::move(name);
  f.type = std::move(type);
  f.default_text = std::move(default_text);
  f.help = std::move(help);
  return f;
}

// A number member (whole for an int); sweepable with a short key.
template <typename T>
SpecField number_row(std::string name, T StackSpec::*member, std::string default_text, std::string help,
                     std::string short_key = "") {
  constexpr bool is_whole = std::is_same_v<T, int>;
  auto f = row(std::move(name), is_whole ? "whole number" : "number", std::move(default_text), std::move(help));
  const auto n = f.name;
  f.short_key = std::move(short_key);
  f.whole = is_whole;
  f.in_every_manifest = true;
  f.parse = [n, member](StackSpec& s, const Tokens& t, Issues& issues) {
    const auto* v = single(n, t, issues);
    if (v == nullptr) return;
    if constexpr (is_whole) {
      whole(n, *v, s.*member, issues);
    } else {
      number(n, *v, s.*member, issues);
    }
  };
  f.set_number = [member](StackSpec& s, double v) { s.*member = static_cast<T>(v); };
  f.save = [n, member](const StackSpec& s, json& j) { j[n] = s.*member; };
  f.load = [n, member](StackSpec& s, const json& j) { s.*member = read<T>(j, n); };
  return f;
}

SpecField text_row(std::string name, std::string StackSpec::*member, std::string default_text, std::string help) {
  auto f = row(std::move(name), "material name", std::move(default_text), std::move(help));
  const auto n = f.name;
  f.in_every_manifest = true;
  f.parse = [n, member](StackSpec& s, const Tokens& t, Issues& issues) {
    if (const auto* v = single(n, t, issues)) s.*member = *v;
  };
  f.save = [n, member](const StackSpec& s, json& j) { j[n] = s.*member; };
  f.load = [n, member](StackSpec& s, const json& j) { s.*member = read<std::string>(j, n); };
  return f;
}

// One of a few names: `parse_name` and `name_of` are the enum's; `allowed` says them in a message.
template <typename E, typename Parse, typename Name>
SpecField choice_row(std::string name, E StackSpec::*member, Parse parse_name, Name name_of, std::string allowed,
                     std::string default_text, std::string help) {
  auto f = row(std::move(name), "one of " + allowed, std::move(default_text), std::move(help));
  const auto n = f.name;
  f.in_every_manifest = true;
  f.parse = [n, member, parse_name, allowed](StackSpec& s, const Tokens& t, Issues& issues) {
    const auto* v = single(n, t, issues);
    if (v == nullptr) return;
    if (const auto e = parse_name(*v)) {
      s.*member = *e;
    } else {
      issues.push_back({n, fmt::format("'{}' is not {}", *v, allowed)});
    }
  };
  f.save = [n, member, name_of](const StackSpec& s, json& j) { j[n] = std::string(name_of(s.*member)); };
  f.load = [n, member, parse_name, allowed](StackSpec& s, const json& j) {
    const auto e = parse_name(read<std::string>(j, n));
    if (!e) throw std::invalid_argument(fmt::format("field '{}' is {}", n, allowed));
    s.*member = *e;
  };
  return f;
}

// A number or 'auto' (nullopt).
template <typename T>
SpecField auto_row(std::string name, std::optional<T> StackSpec::*member, std::string default_text, std::string help) {
  constexpr bool is_whole = std::is_same_v<T, int>;
  auto f = row(std::move(name), is_whole ? "whole number or auto" : "number or auto", std::move(default_text),
               std::move(help));
  const auto n = f.name;
  f.in_every_manifest = true;
  f.parse = [n, member](StackSpec& s, const Tokens& t, Issues& issues) {
    const auto* v = single(n, t, issues);
    if (v == nullptr || *v == "auto") return;
    if constexpr (is_whole) {
      int w = 0;
      if (whole(n, *v, w, issues)) s.*member = w;
    } else {
      double d = 0.0;
      if (number(n, *v, d, issues)) s.*member = d;
    }
  };
  f.save = [n, member](const StackSpec& s, json& j) { j[n] = s.*member ? json(*(s.*member)) : json("auto"); };
  f.load = [n, member](StackSpec& s, const json& j) {
    const auto& v = j.at(n);
    s.*member = v.is_string() && v.get<std::string>() == "auto" ? std::nullopt : std::optional<T>(read<T>(j, n));
  };
  return f;
}

// A coefficient's value for every material pair (sweepable), and its entries per pair.
SpecField pair_value_row(std::string name, PairTable StackSpec::*member, std::string default_text, std::string help,
                         std::string short_key) {
  auto f = row(std::move(name), "number", std::move(default_text), std::move(help));
  const auto n = f.name;
  f.short_key = std::move(short_key);
  f.in_every_manifest = true;
  f.parse = [n, member](StackSpec& s, const Tokens& t, Issues& issues) {
    if (const auto* v = single(n, t, issues)) number(n, *v, (s.*member).value, issues);
  };
  f.set_number = [member](StackSpec& s, double v) { (s.*member).value = v; };
  f.save = [n, member](const StackSpec& s, json& j) { j[n] = (s.*member).value; };
  f.load = [n, member](StackSpec& s, const json& j) { (s.*member).value = read<double>(j, n); };
  return f;
}

SpecField pair_entries_row(std::string name, PairTable StackSpec::*member, std::string flag, std::string help) {
  auto f = row(std::move(name), "table \"A:B\" = number", "none", std::move(help));
  const auto n = f.name;
  f.flag = std::move(flag);
  f.shape = FieldShape::pair_entries;
  f.in_every_manifest = true;
  f.parse = [n, member](StackSpec& s, const Tokens& t, Issues& issues) { parse_pairs(s.*member, n, t, issues); };
  f.save = [n, member](const StackSpec& s, json& j) { j[n] = pairs_json(s.*member); };
  f.load = [n, member](StackSpec& s, const json& j) { load_pairs(s.*member, j.at(n), n); };
  return f;
}

// `range` as the checks say it: "must be ..." messages of validate().
void check_range(Issues& issues, const std::string& field, bool ok, std::string message) {
  if (!ok) issues.push_back({field, std::move(message)});
}

bool within(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }
bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

// Written only when not the default, so manifests of the study's model keep their digests.
template <typename Apply>
SpecField& unless_default(SpecField& f, Apply&& when) {
  auto save = f.save;
  f.in_every_manifest = false;
  f.save = [save, when](const StackSpec& s, json& j) {
    if (when(s)) save(s, j);
  };
  return f;
}

// ---- The table ------------------------------------------------------------------------------

std::vector<SpecField> container_rows() {
  std::vector<SpecField> rows;
  const auto panels_only = [](const StackSpec& s) { return s.geometry == Geometry::panels; };
  auto geometry = choice_row(
      "geometry", &StackSpec::geometry, parse_geometry, [](Geometry g) { return to_string(g); },
      "'strip', 'nested3d' or 'panels'", "strip",
      "strip (the study's, one sphere thick) | nested3d (cubic blocks, C x C columns) | panels (the study's container)");
  geometry.doc = "`strip`: every centre at y = 0; `nested3d`: each block a cubic lattice of `C_k x C_k` columns of "
                 "`rows` layers, each sphere of a block's bottom layer on four of the block below, the striker in the "
                 "pocket of the four central top spheres, side walls then on all four sides; `panels`: `panels` strips "
                 "side by side along y at the top spheres' pitch with a separator between them "
                 "([The container](../how-to/paraview.md#the-container))";
  geometry.in_every_manifest = false;  // absent from manifests written before 3D nests: the strip
  rows.push_back(std::move(geometry));

  auto panels = number_row("panels", &StackSpec::panels, "none", "geometry = panels: strips side by side along y, 2..64");
  unless_default(panels, panels_only);
  rows.push_back(std::move(panels));

  auto impact = row("impact_panel", "whole number or all", "the centre one, (panels + 1) / 2",
                    "geometry = panels: the panel the striker hits, 1 = smallest y, or all (a striker on each)");
  impact.doc = "`all`: ids 1 to `panels` are strikers; `E_in` is theirs together, the centre panel is the one measured";
  impact.parse = [](StackSpec& s, const Tokens& t, Issues& issues) {
    const auto* v = single("impact_panel", t, issues);
    if (v == nullptr) return;
    if (*v == "all") {
      s.impact_panel = kAllPanels;
    } else if (whole("impact_panel", *v, s.impact_panel, issues) && s.impact_panel < 1) {
      // -1 and 0 are the model's codes for 'all' and the centre one: never a user's number.
      issues.push_back({"impact_panel", fmt::format("{} is not a panel: give 1..panels (1 = smallest y), or 'all' (a "
                                                    "striker on every panel); leave it out for the centre one",
                                                    *v)});
    }
  };
  impact.save = [panels_only](const StackSpec& s, json& j) {
    if (panels_only(s)) j["impact_panel"] = s.strikes_every_panel() ? json("all") : json(s.impact_panel);
  };
  impact.load = [](StackSpec& s, const json& j) {
    const auto& v = j.at("impact_panel");
    s.impact_panel = v.is_string() && v.get<std::string>() == "all" ? kAllPanels : read<int>(j, "impact_panel");
  };
  rows.push_back(std::move(impact));

  auto separator = choice_row(
      "separator", &StackSpec::separator, parse_separator, [](Separator p) { return to_string(p); },
      "'matrix', 'walls' or 'none'", "matrix",
      "geometry = panels: matrix (soft sphere chains) | walls (rigid) | none");
  separator.doc = "`matrix`: chains of soft spheres between the panels' pockets; `walls`: rigid planes midway between "
                  "panels, the rigid-separator limit";
  unless_default(separator, panels_only);
  rows.push_back(std::move(separator));

  auto matrix = text_row("matrix_material", &StackSpec::matrix_material, "teflon",
                         "geometry = panels, separator = matrix: the matrix's material, built-in or custom");
  unless_default(matrix, panels_only);
  rows.push_back(std::move(matrix));
  return rows;
}

// radius_ratio: one whole number for every interface, or a list of one per interface.
SpecField radius_ratio_row() {
  auto f = row("radius_ratio", "whole number, or a list of one per interface", "2",
               "R_k / R_(k+1), a whole number from 1 to 16; a list gives one per interface, top first");
  f.doc = "even: each sphere rests on two below; odd: on the one straight below; `[2, 3, 2]` for four blocks";
  f.shape = FieldShape::list;
  f.in_every_manifest = true;
  f.parse = [](StackSpec& s, const Tokens& t, Issues& issues) {
    std::vector<int> ratios(t.size());
    for (std::size_t k = 0; k < t.size(); ++k) whole("radius_ratio", t[k], ratios[k], issues);
    if (ratios.size() == 1) {
      s.radius_ratio = ratios.front();
      s.radius_ratios.clear();
    } else {
      s.radius_ratios = ratios;
    }
  };
  f.check = [](const StackSpec& s, Issues& i) {
    for (const int n : s.radius_ratios.empty() ? std::vector<int>{s.radius_ratio} : s.radius_ratios) {
      check_range(i, "radius_ratio", n >= 1 && n <= 16,
                  fmt::format("{} must be a whole number from 1 to 16 (each block's columns tile the block below "
                              "exactly only for whole ratios)",
                              n));
    }
  };
  f.save = [](const StackSpec& s, json& j) {
    j["radius_ratio"] = s.radius_ratios.empty() ? json(s.radius_ratio) : json(s.radius_ratios);
  };
  f.load = [](StackSpec& s, const json& j) {
    if (j.at("radius_ratio").is_array()) s.radius_ratios = read<std::vector<int>>(j, "radius_ratio");
    else s.radius_ratio = read<int>(j, "radius_ratio");
  };
  return f;
}

// block_rows: each block's rows, in place of `rows` for all.
SpecField block_rows_row() {
  auto f = row("block_rows", "list of whole numbers, one per block", "rows in every block",
               "Rows of each block, top first, 1..4096 each (instead of rows)");
  f.shape = FieldShape::list;
  f.conflicts_with = "rows";
  f.parse = [](StackSpec& s, const Tokens& t, Issues& issues) {
    s.block_rows.assign(t.size(), 0);
    for (std::size_t k = 0; k < t.size(); ++k) whole("block_rows", t[k], s.block_rows[k], issues);
  };
  f.check = [](const StackSpec& s, Issues& i) {
    for (const int n : s.block_rows) {
      check_range(i, "block_rows", n >= 1 && n <= 4096, fmt::format("{} must be a whole number from 1 to 4096", n));
    }
  };
  f.save = [](const StackSpec& s, json& j) {
    if (!s.block_rows.empty()) j["block_rows"] = s.block_rows;
  };
  f.load = [](StackSpec& s, const json& j) { s.block_rows = read<std::vector<int>>(j, "block_rows"); };
  return f;
}

std::vector<SpecField> stack_rows() {
  std::vector<SpecField> rows;
  auto blocks = number_row("blocks", &StackSpec::blocks, "4", "Number of blocks N_B (block 1 is the top, impacted one)", "nb");
  blocks.check = [](const StackSpec& s, Issues& i) {
    check_range(i, "blocks", s.blocks >= 1 && s.blocks <= 16, fmt::format("{} must be a whole number from 1 to 16", s.blocks));
  };
  rows.push_back(std::move(blocks));

  auto rows_ = number_row("rows", &StackSpec::rows, "8", "Rows (spheres per column), the same in every block, 1..4096", "rows");
  rows_.check = [](const StackSpec& s, Issues& i) {
    check_range(i, "rows", s.rows >= 1 && s.rows <= 4096, fmt::format("{} must be a whole number from 1 to 4096", s.rows));
  };
  rows.push_back(std::move(rows_));

  auto columns = number_row("top_columns", &StackSpec::top_columns, "2",
                           "Columns of block 1, even, 2..4096; block k has top_columns * radius_ratio^(k-1)", "cols");
  columns.check = [](const StackSpec& s, Issues& i) {
    check_range(i, "top_columns", s.top_columns >= 2 && s.top_columns % 2 == 0 && s.top_columns <= 4096,
                fmt::format("{} must be an even number from 2 to 4096 (the striker hits between the two central "
                            "columns)",
                            s.top_columns));
  };
  rows.push_back(std::move(columns));

  auto radius = number_row("bottom_radius", &StackSpec::bottom_radius, "0.001",
                           "Radius of the bottom block's spheres, m, 1e-7..1", "r");
  radius.doc = "from 100 nm (Hertz contact without adhesion, [physics](../physics.md)); the top block's at most 1 m";
  radius.check = [](const StackSpec& s, Issues& i) {
    check_range(i, "bottom_radius", within(s.bottom_radius, kMinRadius, kMaxRadius),
                fmt::format("{} must be in [{:g}, {:g}] m", s.bottom_radius, kMinRadius, kMaxRadius));
  };
  rows.push_back(std::move(radius));

  rows.push_back(radius_ratio_row());
  auto stacking = choice_row(
      "stacking", &StackSpec::stacking, parse_stacking, [](Stacking v) { return to_string(v); },
      "'by_ratio', 'nested' or 'aligned'", "by_ratio",
      "How a block rests on the one below: by_ratio (even: on two; odd: on one) | nested (on two) | aligned (on one)");
  stacking.doc = "`nested` or `aligned` at every interface, against the ratio's parity where need be: the block below "
                 "then has `n C_k + 1` columns (ratio 2 aligned: each sphere straight on one of a block of `2 C_k + 1`; "
                 "ratio 1 nested: equal spheres, each on two of a block of `C_k + 1`); geometry = strip and free sides only";
  unless_default(stacking, [](const StackSpec& s) { return s.stacking != Stacking::by_ratio; });
  rows.push_back(std::move(stacking));
  rows.push_back(block_rows_row());

  auto materials = row("materials", "list of material names", "steel", "Material per block, top first; one name for all");
  materials.shape = FieldShape::list;
  materials.in_every_manifest = true;
  materials.parse = [](StackSpec& s, const Tokens& t, Issues&) { s.materials = t; };
  materials.save = [](const StackSpec& s, json& j) { j["materials"] = s.materials; };
  materials.load = [](StackSpec& s, const json& j) { s.materials = read<std::vector<std::string>>(j, "materials"); };
  rows.push_back(std::move(materials));
  return rows;
}

std::vector<SpecField> contact_rows() {
  std::vector<SpecField> rows;
  rows.push_back(pair_value_row("restitution", &StackSpec::restitution, "1",
                                "Coefficient of restitution e, 0.05 < e <= 1 (LIGGGHTS's range)", "e"));
  rows.push_back(pair_value_row("friction", &StackSpec::friction, "0", "Coulomb friction coefficient mu, 0..10", "mu"));
  rows.push_back(pair_entries_row("restitution_pairs", &StackSpec::restitution, "--restitution-pair",
                                  "Restitution of one material pair: A:B=E (both in the stack)"));
  rows.push_back(pair_entries_row("friction_pairs", &StackSpec::friction, "--friction-pair",
                                  "Friction of one material pair: A:B=MU (both in the stack)"));
  return rows;
}

// The protected plate under the stack and its mount (StackSpec::plate_mass): written where a plate
// is given, so older manifests and every rigid wall's stay as they were.
void add_plate_rows(std::vector<SpecField>& rows) {
  const auto plate_row = [](std::string name, double StackSpec::*member, std::string help, std::string short_key,
                            std::string unit) {
    auto f = number_row(name, member, "0", std::move(help), std::move(short_key));
    f.in_every_manifest = false;
    f.save = [name, member](const StackSpec& s, json& j) {
      if (s.has_plate()) j[name] = s.*member;
    };
    f.check = [name, member, unit](const StackSpec& s, Issues& i) {
      check_range(i, name, within(s.*member, 0.0, kMaxPlateValue),
                  fmt::format("{} must be in [0, {:g}] ({})", s.*member, kMaxPlateValue, unit));
    };
    return f;
  };
  auto mass = plate_row("plate_mass", &StackSpec::plate_mass,
                        "With bottom = wall: the protected plate's mass, kg, which the stack strikes and which moves "
                        "on its mount; 0: a rigid wall",
                        "pm", "kg; 0 is the rigid wall");
  mass.doc = "the plate moves along z only, its contacts those of the wall's material; its displacement, velocity and "
             "acceleration are the series' last columns (plate_z, plate_vz, plate_az). Runs on refsim and LIGGGHTS "
             "(a mesh moved with an atom of the plate's mass), not on LAMMPS";
  rows.push_back(std::move(mass));
  rows.push_back(plate_row("mount_stiffness", &StackSpec::mount_stiffness,
                           "With plate_mass: the mount's stiffness to the ground, N/m; 0: a free plate", "", "N/m"));
  rows.push_back(plate_row("mount_damping", &StackSpec::mount_damping,
                           "With plate_mass: the mount's damping, N s/m (a dashpot beside the spring)", "", "N s/m"));
}

std::vector<SpecField> striker_and_boundary_rows() {
  std::vector<SpecField> rows;
  auto speed = number_row("striker_speed", &StackSpec::striker_speed, "1", "Striker speed, m/s, along -z", "v");
  speed.check = [](const StackSpec& s, Issues& i) {
    check_range(i, "striker_speed", finite_positive(s.striker_speed), fmt::format("{} must be > 0 (m/s)", s.striker_speed));
  };
  rows.push_back(std::move(speed));

  auto ratio = number_row("striker_radius_ratio", &StackSpec::striker_radius_ratio, "1",
                          "Striker radius over the top spheres', 1..16");
  ratio.doc = "it rests on the two central top spheres at `sin(theta) = 1/(ratio + 1)` from the vertical (one row of "
              "two spheres and ratio 2 is the isolated collision of Eq. 3)";
  ratio.in_every_manifest = false;  // absent from manifests written before the striker could be chosen
  rows.push_back(std::move(ratio));

  auto offset = number_row("impact_offset", &StackSpec::impact_offset, "0",
                           "An off-centre blow: the striker k top-sphere diameters along +x from the centre, "
                           "|k| <= top_columns/2 - 1",
                           "io");
  offset.doc = "the striker rests on top spheres `top_columns/2 + k` and `top_columns/2 + k + 1` (along x only in a 3D "
               "nest); the impact path, the output sphere and the middle spheres follow it down, from the outer of the two "
               "struck spheres, so that a blow at `-k` is the mirror image of one at `k`";
  offset.in_every_manifest = false;  // written where it is not 0, so older manifests stay as they were
  offset.save = [](const StackSpec& s, json& j) {
    if (s.impact_offset != 0) j["impact_offset"] = s.impact_offset;
  };
  offset.check = [](const StackSpec& s, Issues& i) {
    const int most = s.top_columns / 2 - 1;
    check_range(i, "impact_offset", std::abs(s.impact_offset) <= std::max(most, 0),
                most <= 0 ? fmt::format("{} must be 0: the striker must rest on two of the {} top spheres (a blow off "
                                        "centre needs at least 4 top columns)",
                                        s.impact_offset, s.top_columns)
                          : fmt::format("{} must be in [-{}, {}]: the striker must rest on two of the {} top spheres",
                                        s.impact_offset, most, most, s.top_columns));
  };
  rows.push_back(std::move(offset));

  auto striker = text_row("striker_material", &StackSpec::striker_material, "the top block's", "Material of the striker");
  striker.in_every_manifest = false;
  rows.push_back(std::move(striker));

  const auto boundary = [](const char* name, Boundary StackSpec::*member, const char* help) {
    auto f = choice_row(name, member, parse_boundary, [](Boundary b) { return to_string(b); }, "'free' or 'wall'",
                        "free", help);
    f.doc = "`wall`: planar `wall/gran` walls touching the lattice";
    return f;
  };
  rows.push_back(boundary("bottom", &StackSpec::bottom, "Bottom boundary: free | wall"));
  rows.push_back(boundary("sides", &StackSpec::sides, "Side boundaries: free | wall"));
  rows.push_back(text_row("wall_material", &StackSpec::wall_material, "the bottom block's", "Material of the walls"));
  add_plate_rows(rows);

  auto gravity = number_row("gravity", &StackSpec::gravity, "0",
                            "Gravity along -z, m/s^2, 0..1000; true or the bare flag: standard gravity, 9.80665");
  gravity.bare = "true";
  gravity.parse = [](StackSpec& s, const Tokens& t, Issues& issues) {
    const auto* v = single("gravity", t, issues);
    if (v == nullptr) return;
    if (*v == "true") s.gravity = 9.80665;  // standard gravity
    else if (*v == "false") s.gravity = 0.0;
    else number("gravity", *v, s.gravity, issues);
  };
  gravity.check = [](const StackSpec& s, Issues& i) {
    check_range(i, "gravity", within(s.gravity, 0.0, kMaxGravity),
                fmt::format("{} must be in [0, {:g}] (m/s^2, acting along -z; 0 turns it off)", s.gravity, kMaxGravity));
  };
  rows.push_back(std::move(gravity));
  return rows;
}

// The commands a deck template of the user's adds to granstack's (formats/deck_rules.hpp): a run
// that executes a command granstack's deck does not run, and the spec does not list, is refused.
SpecField deck_additions_row() {
  auto f = row("deck_additions", "list of commands", "none",
               "Commands your --template adds to granstack's deck, each 'COMMAND' or 'fix|compute|dump STYLE' "
               "(e.g. 'fix viscous'); a run names them, and refuses any other");
  f.doc = "a run is held to the commands LIGGGHTS or LAMMPS executed (read from its log): granstack's own, run as "
          "its template writes them, and these; `fix viscous`, `dump custom/vtk`, `displace_atoms`. Commands that "
          "change nothing a result is labelled with (variables, prints, thermo output, computes and groups of names "
          "of your own) need no listing. `reduce`, `table` and the reports name a run's additions";
  f.shape = FieldShape::list;
  f.parse = [](StackSpec& s, const Tokens& t, Issues& issues) {
    s.deck_additions.clear();
    for (const auto& entry : t) {
      std::vector<std::string> words;
      std::string word;
      for (const char c : entry + " ") {
        if (c != ' ' && c != '\t') {
          word += c;
        } else if (!word.empty()) {
          words.push_back(std::move(word));
          word.clear();
        }
      }
      const bool styled = !words.empty() && (words[0] == "fix" || words[0] == "compute" || words[0] == "dump");
      if (words.empty() || words.size() != (styled ? 2u : 1u) ||
          words[0].find_first_not_of("abcdefghijklmnopqrstuvwxyz_/") != std::string::npos) {
        issues.push_back({"deck_additions", fmt::format("'{}' is not a command ('displace_atoms') or a fix, compute or "
                                                        "dump with its style ('fix viscous')",
                                                        entry)});
        continue;
      }
      s.deck_additions.push_back(fmt::format("{}", fmt::join(words, " ")));
    }
  };
  f.save = [](const StackSpec& s, json& j) {  // written where given, so older manifests stay as they were
    if (!s.deck_additions.empty()) j["deck_additions"] = s.deck_additions;
  };
  f.load = [](StackSpec& s, const json& j) { s.deck_additions = read<std::vector<std::string>>(j, "deck_additions"); };
  return f;
}

std::vector<SpecField> resolution_rows() {
  std::vector<SpecField> rows;
  auto dt = auto_row("dt", &StackSpec::dt, "auto: 1/100 of the shortest contact time",
                     "Time step, s, at most 1/20 of the shortest contact time, or auto");
  dt.check = [](const StackSpec& s, Issues& i) {
    if (s.dt) check_range(i, "dt", finite_positive(*s.dt), fmt::format("{} must be > 0 (s) or 'auto'", *s.dt));
  };
  rows.push_back(std::move(dt));
  auto duration = auto_row("duration", &StackSpec::duration, "auto", "Simulated time, s, or auto");
  duration.doc = "`auto`: twice the pulse's estimated arrival at the bottom (seven times with a soft block between "
                 "stiffer ones); see below";
  duration.check = [](const StackSpec& s, Issues& i) {
    if (s.duration) {
      check_range(i, "duration", finite_positive(*s.duration), fmt::format("{} must be > 0 (s) or 'auto'", *s.duration));
    }
  };
  rows.push_back(std::move(duration));
  auto stop = choice_row(
      "stop", &StackSpec::stop, parse_stop_rule, [](StopRule r) { return to_string(r); }, "'duration' or 'blow_end'",
      "duration", "How the run ends: duration | blow_end (at the blow's end, at most cap_durations)");
  stop.doc = "`blow_end`: both engines stop at the dump frame where the blow has ended (against a bottom wall the "
             "momentum over the footprint no longer downward and no sphere pressing the wall, under an elastic-plastic "
             "law the wall carrying no force; with a free bottom the output sphere free and none on course to hit it; in both no striker on course to hit a sphere nor, "
             "over a wall, moving down over the footprint; held for one estimated arrival, two with a soft "
             "cavity; docs/physics.md section 7). The stop counts every course to a striker; the blow's end reduce reports "
             "leaves out courses that run into other spheres first, and can come earlier. A blow not ended by the cap is "
             "censored: reduce says why";
  stop.in_every_manifest = false;
  const auto save_stop = stop.save;  // written where it is not the default, so older manifests stay as they were
  stop.save = [save_stop](const StackSpec& s, json& j) {
    if (s.stop != StopRule::duration) save_stop(s, j);
  };
  rows.push_back(std::move(stop));
  auto cap = number_row("cap_durations", &StackSpec::cap_durations, fmt::format("{:g}", kBlowEndCapDurations),
                        fmt::format("With stop = blow_end: the run's cap, in automatic durations, {:g}..{:g}",
                                    kMinBlowEndCapDurations, kMaxBlowEndCapDurations));
  cap.in_every_manifest = false;
  cap.save = [](const StackSpec& s, json& j) {
    if (s.stop == StopRule::blow_end) j["cap_durations"] = s.cap_durations;
  };
  cap.check = [](const StackSpec& s, Issues& i) {
    check_range(i, "cap_durations", within(s.cap_durations, kMinBlowEndCapDurations, kMaxBlowEndCapDurations),
                fmt::format("{} must be in [{:g}, {:g}]: the hold alone lasts up to one automatic duration, so a "
                            "shorter cap could end no blow",
                            s.cap_durations, kMinBlowEndCapDurations, kMaxBlowEndCapDurations));
  };
  rows.push_back(std::move(cap));
  auto dump_every = auto_row("dump_every", &StackSpec::dump_every,
                             "auto: the smaller of a 250th of the run and 0.2 t_c", "Steps between dump frames, or auto");
  dump_every.doc = "the automatic cadence times the smallest block's wave (811 frames for the default case)";
  dump_every.check = [](const StackSpec& s, Issues& i) {
    if (s.dump_every) check_range(i, "dump_every", *s.dump_every >= 1, fmt::format("{} must be >= 1 step", *s.dump_every));
  };
  rows.push_back(std::move(dump_every));
  auto series_every = auto_row("series_every", &StackSpec::series_every, "auto: every step up to 20000 steps, about 20000 samples beyond; over a bottom wall at least 20 per contact of a bottom sphere on the wall",
                               "Steps between in-situ energy samples, or auto");
  series_every.check = [](const StackSpec& s, Issues& i) {
    if (s.series_every) {
      check_range(i, "series_every", *s.series_every >= 1, fmt::format("{} must be >= 1 step", *s.series_every));
    }
  };
  series_every.doc = "over a bottom wall under an elastic-plastic law, and under thornton run to the blow's end, a "
                     "divisor of dump_every (given or automatic), so that a sample falls on every dump frame: the blow's "
                     "end reads the wall's force there, or reduce the work the contacts dissipated at the frame it ends on";
  rows.push_back(std::move(series_every));

  auto files = choice_row(
      "dump_files", &StackSpec::dump_files, parse_dump_files, [](DumpFiles f) { return to_string(f); },
      "'single', 'per_step' or 'per_rank'", "single",
      "single | per_step (LIGGGHTS '*') | per_rank (LIGGGHTS '%', with run --np)");
  files.doc = "all reduce to the same result";
  files.in_every_manifest = false;
  rows.push_back(std::move(files));
  auto format = choice_row(
      "dump_format", &StackSpec::dump_format, parse_dump_format, [](DumpFormat f) { return to_string(f); },
      "'text' or 'binary'", "text", "Dump format: text | binary");
  format.doc = "`text` (`%.17g`) or `binary` (LIGGGHTS `.bin`: a tenth smaller and half again faster to read); both "
               "hold the exact doubles and reduce to identical results. refsim writes its binary dump as a zstd stream "
               "(`zstd -d` gives LIGGGHTS's bytes; every granstack reader takes both)";
  rows.push_back(std::move(format));
  rows.push_back(deck_additions_row());
  return rows;
}

SpecField custom_materials_row() {
  auto f = row("custom_materials", "table of materials", "none",
               "Define a material: NAME:DENSITY:YOUNGS_MODULUS:POISSON_RATIO[:YIELD_STRENGTH] (SI; not steel or teflon, the study's; a library name such as brass is redefined for this spec)");
  f.flag = "--custom-material";
  f.doc = "in a spec file `[custom_materials.NAME]` with `density` (1 to 1e5 kg/m^3), `youngs_modulus` (1e3 to 1e13 "
          "Pa), `poisson_ratio` ([0, 0.5)) and, optionally, `yield_strength` (Pa, the tensile yield strength that judges its "
          "contacts' first yield; without it they are not judged); steel and teflon cannot be redefined, a library "
          "material (brass, glass, ...) can, for this spec alone";
  f.shape = FieldShape::material_entries;
  f.in_every_manifest = true;
  f.parse = [](StackSpec& s, const Tokens& tokens, Issues& issues) {
    for (const auto& t : tokens) {
      std::vector<std::string> parts;
      for (std::size_t at = 0;;) {
        const auto colon = t.find(':', at);
        parts.push_back(t.substr(at, colon == std::string::npos ? std::string::npos : colon - at));
        if (colon == std::string::npos) break;
        at = colon + 1;
      }
      if (parts.size() != 4 && parts.size() != 5) {
        issues.push_back(
            {"custom_materials", fmt::format("'{}' is not NAME:DENSITY:YOUNGS_MODULUS:POISSON_RATIO[:YIELD_STRENGTH]", t)});
        continue;
      }
      Material m;
      m.name = parts[0];
      const auto field = fmt::format("custom_materials.{}", m.name);
      if (number(field + ".density", parts[1], m.density, issues) &&
          number(field + ".youngs_modulus", parts[2], m.youngs_modulus, issues) &&
          number(field + ".poisson_ratio", parts[3], m.poisson_ratio, issues)) {
        double yield = 0.0;
        if (parts.size() == 5 && !number(field + ".yield_strength", parts[4], yield, issues)) continue;
        if (parts.size() == 5) m.yield_strength = yield;
        s.custom_materials.push_back(m);
      }
    }
  };
  f.save = [](const StackSpec& s, json& j) {
    json mats = json::object();
    for (const auto& m : s.custom_materials) {
      mats[m.name] = {{"density", m.density}, {"youngs_modulus", m.youngs_modulus}, {"poisson_ratio", m.poisson_ratio}};
      if (m.yield_strength) mats[m.name]["yield_strength"] = *m.yield_strength;  // absent: as before it existed
    }
    j["custom_materials"] = mats;
  };
  f.load = [](StackSpec& s, const json& j) {
    for (const auto& [name, m] : j.at("custom_materials").items()) {
      s.custom_materials.push_back({name, read<double>(m, "density"), read<double>(m, "youngs_modulus"),
                                    read<double>(m, "poisson_ratio"), std::nullopt});
      if (m.contains("yield_strength")) s.custom_materials.back().yield_strength = read<double>(m, "yield_strength");
    }
  };
  return f;
}

// A sub-model's choice row, its allowed values, help and notes from contact_models.cpp's table.
template <typename Model, typename Parse>
SpecField sub_model_row(std::string name, Model StackSpec::*member, Parse parse_name, std::string what) {
  std::string help = what + ": ", doc;
  for (const auto m : all_models<Model>()) {
    if (m != Model{}) help += " | ";
    help += info(m).help;
    if (info(m).doc.empty()) continue;
    if (!doc.empty()) doc += "; ";
    doc += info(m).doc;
  }
  auto row = choice_row(
      std::move(name), member, parse_name, [](Model m) { return to_string(m); }, keyword_list<Model>(),
      std::string(to_string(Model{})), help);
  row.doc = doc;
  unless_default(row, [member](const StackSpec& s) { return s.*member != Model{}; });
  return row;
}

std::vector<SpecField> contact_model_rows() {
  std::vector<SpecField> rows;
  rows.push_back(sub_model_row("normal_model", &StackSpec::normal_model, parse_normal_model, "Normal contact"));
  rows.push_back(
      sub_model_row("tangential_model", &StackSpec::tangential_model, parse_tangential_model, "Tangential contact"));
  rows.push_back(sub_model_row("rolling_model", &StackSpec::rolling_model, parse_rolling_model, "Rolling friction"));
  const auto rolling_on = [](const StackSpec& s) { return s.rolling_model != RollingModel::off; };
  auto mu_r = pair_value_row("rolling_friction", &StackSpec::rolling_friction, "0",
                             "Rolling friction coefficient mu_r, 0..1 (rolling_model = " +
                                 keyword_list<RollingModel>(true) + ")",
                             "mur");
  unless_default(mu_r, rolling_on);
  rows.push_back(std::move(mu_r));
  auto mu_r_pairs = pair_entries_row("rolling_friction_pairs", &StackSpec::rolling_friction, "--rolling-friction-pair",
                                     "Rolling friction of one material pair: A:B=MU_R");
  unless_default(mu_r_pairs, rolling_on);
  rows.push_back(std::move(mu_r_pairs));

  auto velocity = auto_row("characteristic_velocity", &StackSpec::characteristic_velocity, "auto: the striker speed",
                           "normal_model = hooke: the speed at which its spring reaches Hertz's overlap, m/s, >= 0.01");
  unless_default(velocity, [](const StackSpec& s) { return s.characteristic_velocity.has_value(); });
  rows.push_back(std::move(velocity));
  auto yield = number_row("yield_pressure_factor", &StackSpec::yield_pressure_factor, "1.6",
                          "normal_model = thornton or thornton_ning: the yield pressure p_y over the softer body's "
                          "yield strength, 1.5..3 (1.6 first yield, about 3 fully plastic)",
                          "pyf");
  unless_default(yield, [](const StackSpec& s) { return s.yield_pressure_factor != kDefaultYieldPressureFactor; });
  rows.push_back(std::move(yield));
  auto order = choice_row(
      "order_dependent_yield", &StackSpec::order_dependent_yield, parse_order_dependent_yield,
      [](OrderDependentYield o) { return to_string(o); }, "'refuse' or 'accept'", "refuse",
      "normal_model = thornton_ning: a case no yield ratios make order-independent (an atom type of two radii): "
      "refuse | accept");
  order.doc = "LIGGGHTS's `thornton_ning` yields at `r_i * coefficientYieldRatio[type_i]` of the first sphere alone; "
              "`accept` runs a case where that depends on which sphere LIGGGHTS calls i, and generate and the deck "
              "say which type";
  unless_default(order, [](const StackSpec& s) { return s.order_dependent_yield != OrderDependentYield::refuse; });
  rows.push_back(std::move(order));
  return rows;
}

std::vector<SpecField> build_table() {
  std::vector<SpecField> all;
  for (auto part : {container_rows(), stack_rows(), contact_rows(), striker_and_boundary_rows(), resolution_rows(),
                    std::vector<SpecField>{custom_materials_row()}, contact_model_rows()}) {
    for (auto& f : part) all.push_back(std::move(f));
  }
  return all;
}

}  // namespace

bool parse_sweep_value(const SpecField& field, const std::string& token, double& value, Issues& issues) {
  if (!field.whole) return number(field.name, token, value, issues);
  int w = 0;
  if (!whole(field.name, token, w, issues)) return false;
  value = w;
  return true;
}

const std::vector<SpecField>& spec_fields() {
  static const std::vector<SpecField> table = build_table();
  return table;
}

const SpecField* find_spec_field(std::string_view name) {
  for (const auto& f : spec_fields()) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

std::string spec_field_names() {
  std::vector<std::string> names;
  for (const auto& f : spec_fields()) names.push_back(f.name);
  return fmt::format("{}", fmt::join(names, ", "));
}

namespace {
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}
}  // namespace

std::string unknown_field_hint(std::string_view name) {
  const SpecField* best = nullptr;
  std::size_t best_distance = 0;
  for (const auto& f : spec_fields()) {
    const auto d = edit_distance(name, f.name);
    if (best == nullptr || d < best_distance) {
      best = &f;
      best_distance = d;
    }
  }
  const bool close = best != nullptr && best_distance <= std::max<std::size_t>(2, name.size() / 4);
  return fmt::format("{}known fields: {}", close ? fmt::format("did you mean '{}'? ", best->name) : "",
                     spec_field_names());
}

json spec_json(const StackSpec& spec) {
  json j = json::object();
  for (const auto& f : spec_fields()) f.save(spec, j);
  return j;
}

namespace {

// A JSON value as a TOML node (the manifest's spec JSON has the spec file's shapes).
std::unique_ptr<toml::node> toml_of(const json& v) {
  if (v.is_boolean()) return std::make_unique<toml::value<bool>>(v.get<bool>());
  if (v.is_number_integer()) return std::make_unique<toml::value<std::int64_t>>(v.get<std::int64_t>());
  if (v.is_number()) return std::make_unique<toml::value<double>>(v.get<double>());
  if (v.is_string()) return std::make_unique<toml::value<std::string>>(v.get<std::string>());
  if (v.is_array()) {
    auto a = std::make_unique<toml::array>();
    for (const auto& e : v) {
      if (auto n = toml_of(e)) a->push_back(std::move(*n));
    }
    return a;
  }
  if (v.is_object()) {
    auto t = std::make_unique<toml::table>();
    for (const auto& [k, e] : v.items()) {
      if (auto n = toml_of(e)) t->insert(k, std::move(*n));
    }
    return t;
  }
  return nullptr;  // null: the field keeps its default
}

}  // namespace

std::string spec_toml(const model::StackSpec& spec) {
  auto j = spec_json(spec);
  // The manifest keeps a field's default beside the one that replaces it (rows beside
  // block_rows); a spec file may give only one of them.
  for (const auto& f : spec_fields()) {
    if (!f.conflicts_with.empty() && j.contains(f.name)) j.erase(f.conflicts_with);
  }
  // The space fixes the wall's material (the study's steel) for every design; a design without a
  // wall leaves it out (generate refuses a wall's material where there is none).
  if (!spec.has_walls()) j.erase("wall_material");
  const auto t = toml_of(j);
  std::ostringstream os;
  os << *t->as_table() << "\n";
  return os.str();
}

StackSpec spec_from_json_fields(const json& j) {
  StackSpec s;
  for (const auto& f : spec_fields()) {
    if (!j.contains(f.name)) {
      if (f.in_every_manifest) throw std::invalid_argument(fmt::format("missing field '{}'", f.name));
      continue;
    }
    try {
      f.load(s, j);
    } catch (const json::exception& e) {
      throw std::invalid_argument(fmt::format("field '{}': {}", f.name, e.what()));
    } catch (const std::invalid_argument& e) {
      const std::string why = e.what();
      throw std::invalid_argument(why.rfind("field '", 0) == 0 ? why : fmt::format("field '{}': {}", f.name, why));
    }
  }
  return s;
}

std::string spec_fields_markdown() {
  std::string out = "| field | type | meaning | default |\n|---|---|---|---|\n";
  for (const auto& f : spec_fields()) {
    std::string meaning = f.help;
    if (!f.doc.empty()) meaning += "; " + f.doc;
    if (f.sweepable()) meaning += fmt::format("; sweepable (case names `{}...`)", f.short_key);
    if (f.flag != flag_of(f.name)) meaning += fmt::format(" (flag `{}`, repeatable)", f.flag);
    const auto cell = [](const std::string& text) {  // a '|' would end the cell
      std::string escaped;
      for (const char c : text) {
        if (c == '|') escaped += '\\';
        escaped += c;
      }
      return escaped;
    };
    out += fmt::format("| `{}` | {} | {} | {} |\n", f.name, cell(f.type), cell(meaning), cell(f.default_text));
  }
  return out;
}

}  // namespace granstack::model
