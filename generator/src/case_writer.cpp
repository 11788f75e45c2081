#include <granstack/formats/data_file.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/version.hpp>
#include <granstack/os/case_lock.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <unistd.h>

namespace granstack::generator {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
const std::vector<std::string> kDumpColumns{"id", "type", "radius", "mass", "x", "y", "z", "vx", "vy", "vz",
                                            "omegax", "omegay", "omegaz", "fx", "fy", "fz", "tqx", "tqy", "tqz"};

}  // namespace

formats::CaseFiles case_files(const model::Stack& stack) {
  formats::CaseFiles f;
  // LIGGGHTS puts the step number in place of '*' and the rank in place of '%'.
  const auto& spec = stack.spec();
  const std::string stem = spec.dump_files == model::DumpFiles::per_step   ? "dumps/dump.*"
                           : spec.dump_files == model::DumpFiles::per_rank ? "dumps/dump.%"
                                                                            : "dumps/dump";
  f.dump = stem + (spec.dump_format == model::DumpFormat::binary ? ".bin" : ".txt");
  f.dump_columns = kDumpColumns;
  f.series_columns = {"step"};
  for (const auto& g : model::series_groups(stack)) {
    f.series_columns.push_back("ke_trans_" + g.name);
    f.series_columns.push_back("ke_rot_" + g.name);
  }
  for (auto& c : model::series_contact_columns(stack)) f.series_columns.push_back(std::move(c));
  if (spec.bottom == model::Boundary::wall) f.series_columns.push_back(model::kBottomWallForceColumn);
  if (spec.has_plate()) f.series_columns.insert(f.series_columns.end(), model::kPlateColumns.begin(), model::kPlateColumns.end());
  return f;
}

formats::DataFile data_file(const model::Stack& stack, const std::string& case_name) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  const auto types = stack.type_materials();
  formats::DataFile d;
  d.title = fmt::format("granstack {} case {}: LIGGGHTS data file for atom_style granular, SI units", version(), case_name);
  d.atom_types = stack.atom_types();
  d.box = stack.box();
  for (const auto& s : stack.spheres()) {
    formats::DataAtom a;
    a.id = s.id;
    a.type = s.atom_type;
    a.diameter = 2.0 * s.radius;
    a.density = lib.at(types[static_cast<std::size_t>(s.atom_type - 1)]).density;
    a.x = s.x;
    a.y = s.y;
    a.z = s.z;
    if (s.block == 0) a.vz = -spec.striker_speed;  // every striker
    d.atoms.push_back(a);
  }
  return d;
}

json derived_json(const model::Stack& stack, const model::Resolution& r) {
  return {{"sphere_count", stack.spheres().size()},
          {"striker_mass", stack.striker_mass()},
          {"e_in", stack.incident_energy()},
          {"dt", r.dt},
          {"dt_auto", r.dt_auto},
          {"dt_rule", fmt::format("dt = (shortest Hertz contact time at the striker speed) / {}", model::normal_law(stack.spec().normal_model).steps_per_contact)},
          {"duration", r.duration},
          {"duration_auto", r.duration_auto},
          {"duration_rule", fmt::format("duration = {} x sum over blocks of ({} rows + {}) x (equal-pair Hertz contact "
                                        "time of the block at the striker speed){}",
                                        r.soft_cavity ? model::kCavityDurationPerArrival : model::kDurationPerArrival,
                                        model::kRowTransitPerContact, model::kBlockEntryPerContact,
                                        r.soft_cavity ? " (a soft block between stiffer ones)" : "")},
          {"soft_cavity", r.soft_cavity},
          {"steps", r.steps},
          {"dump_every", r.dump_every},
          {"series_every", r.series_every},
          {"thermo_every", r.thermo_every},
          {"min_contact_time", r.min_contact_time},
          {"min_contact_pair", r.min_contact_pair},
          {"dt_over_min_contact_time", r.dt / r.min_contact_time},
          {"min_rayleigh_time", r.min_rayleigh_time},
          {"dt_over_min_rayleigh_time", r.dt / r.min_rayleigh_time},
          {"arrival_estimate", r.arrival_estimate},
          {"skin", r.skin}};
}

json layout_json(const model::Stack& stack) {
  json blocks = json::array();
  for (const auto& b : stack.blocks()) {
    blocks.push_back({{"block", b.index}, {"material", b.material}, {"radius", b.radius}, {"rows", b.rows},
                      {"columns", b.columns}, {"depth", b.depth}, {"first_id", b.first_id}, {"last_id", b.last_id()},
                      {"atom_type", b.atom_type}, {"sphere_mass", b.sphere_mass}});
  }
  json types = json::array();
  const auto mats = stack.type_materials();
  for (std::size_t i = 0; i < mats.size(); ++i) {
    const int t = static_cast<int>(i) + 1;
    const char* role = t == stack.striker_type() ? "striker"
                       : t == stack.wall_type()  ? "wall"
                       : t == stack.matrix_type() ? "matrix"
                                                  : "block";
    types.push_back({{"type", t}, {"material", mats[i]}, {"role", role}});
  }
  const auto& striker = stack.sphere(model::Stack::striker_id());
  const auto bottom = stack.bottom_row_ids();
  json layout = {{"geometry", model::to_string(stack.spec().geometry)},
          {"id_order", "id 1 = striker; then blocks top to bottom, rows (layers) top to bottom, y-columns by increasing "
                       "y, columns by increasing x: id = first_id + (row - 1) * columns * depth + (column_y - 1) * "
                       "columns + (column - 1)"},
          {"striker", {{"id", striker.id}, {"atom_type", striker.atom_type}, {"radius", striker.radius},
                       {"mass", stack.striker_mass()}, {"x", striker.x}, {"z", striker.z}}},
          {"output_sphere_id", stack.output_sphere_id()},
          {"bottom_row_ids", {bottom.front(), bottom.back()}},
          {"blocks", blocks},
          {"atom_types", types},
          {"wall_type", stack.wall_type()},
          {"half_width", stack.half_width()},
          {"half_depth", stack.half_depth()}};
  if (stack.container()) {
    json chains = json::array();
    for (const auto& b : stack.blocks()) {
      const auto c = stack.chain_beside(b);
      chains.push_back({{"block", b.index}, {"count", c.count}, {"radius", c.radius},
                        {"offset", c.offset}});
    }
    layout["panels"] = {{"count", stack.panels()},
                        {"impact_panel", stack.impact_panel()},
                        {"strikers", stack.strikers()},
                        {"pitch", 2.0 * stack.block(1).radius},
                        {"separator", model::to_string(stack.spec().separator)},
                        {"matrix_type", stack.matrix_type()},
                        {"first_matrix_id", stack.has_matrix() ? stack.first_matrix_id() : 0},
                        {"matrix_chains", chains}};
  }
  return layout;
}

namespace {
struct PreparedCase {
  std::string name;
  std::string deck;
  std::string data;
  std::string manifest;
  formats::CaseFiles files;
};

void write_case(const fs::path& dir, const PreparedCase& c) {
  fs::create_directories(dir / "dumps");
  formats::write_file_atomically(dir / c.files.data, c.data);
  formats::write_file_atomically(dir / c.files.deck, c.deck);
  formats::write_file_atomically(dir / "manifest.json", c.manifest);
}
}  // namespace

model::Cost total_cost(const std::vector<model::Cost>& costs) {
  model::Cost total;
  for (const auto& c : costs) {
    total.spheres += c.spheres;
    total.steps += c.steps;
    total.frames += c.frames;
    total.dump_bytes += c.dump_bytes;
    total.series_bytes += c.series_bytes;
    total.liggghts_seconds += c.liggghts_seconds;
  }
  return total;
}

GenerateResult generate(const std::vector<CaseSpec>& cases, const GenerateOptions& options) {
  if (cases.empty()) throw std::runtime_error("no case to generate");
  const std::string tmpl = options.deck_template_path ? formats::read_file(*options.deck_template_path)
                                                      : std::string(default_deck_template());
  const std::string tmpl_name = options.deck_template_path.value_or("templates/in.granstack.tmpl");

  // Everything is rendered in memory first: a bad spec or template writes nothing.
  const fs::path out = fs::absolute(options.output).lexically_normal();
  const fs::path target = out.filename().empty() ? out.parent_path() : out;
  std::vector<PreparedCase> prepared;
  GenerateResult result;
  const auto created = formats::utc_timestamp();
  for (const auto& sc : cases) {
    // A single case is named after its directory; a sweep's cases after their swept values.
    CaseSpec c = sc;
    if (cases.size() == 1) c.name = target.filename().string();
    const auto stack = model::Stack::build(c.spec);
    const auto res = model::resolve(stack);
    auto issues = model::check_resolution(stack, res);
    if (!issues.empty()) {
      if (cases.size() > 1) {
        for (auto& i : issues) i.message += fmt::format(" (in the sweep case {})", c.name);
      }
      throw model::SpecError(std::move(issues));
    }
    if (res.stops_at_blow_end && options.deck_template_path && !uses_placeholder(tmpl, "run")) {
      throw model::SpecError({{"stop", fmt::format("{} has no {{{{run}}}} placeholder, so its deck would run all {} steps "
                                                   "of the cap: end the template with {{{{run}}}}, or use stop = 'duration'",
                                                   tmpl_name, res.steps)}});
    }
    if (c.spec.has_plate() && options.deck_template_path &&
        !(uses_placeholder(tmpl, "plate") && uses_placeholder(tmpl, "particles"))) {
      throw model::SpecError({{"plate_mass", fmt::format("{} lacks {{{{plate}}}} (after fix nve/sphere: the plate's motion) or "
                                                         "{{{{particles}}}} (the dump's group, without the plate's body), "
                                                         "so its deck would hold the plate still or dump its body: add both, "
                                                         "as templates/in.granstack.tmpl has them",
                                                         tmpl_name)}});
    }
    const auto cost = model::estimate_cost(stack, res);
    if (const auto why = model::why_large(cost); !why.empty() && !options.allow_large) {
      const auto capped = res.stops_at_blow_end
                              ? fmt::format(" if it runs to its cap of {:g} automatic durations (it stops at its blow's end, "
                                            "often far sooner: a lower cap_durations lowers this)",
                                            c.spec.cap_durations)
                              : std::string();
      throw model::SpecError({{"size", fmt::format("{}{} is large: {}{}; pass --large if you mean it",
                                                   cases.size() > 1 ? "the sweep case " : "the case ", c.name, why, capped)}});
    }
    result.costs.push_back(cost);
    result.resolutions.push_back(res);
    PreparedCase p;
    p.name = c.name;
    p.files = case_files(stack);
    p.data = formats::format_data_file(data_file(stack, c.name));
    formats::Manifest m;
    m.case_name = c.name;
    m.spec = c.spec;
    m.files = p.files;
    m.granstack_version = std::string(version());
    m.git_commit = std::string(git_commit());
    m.created = created;
    m.command_line = options.command_line;
    m.derived = derived_json(stack, res);
    for (const auto& [key, value] : m.derived->items()) {
      if (value.is_number_float() && !std::isfinite(value.get<double>())) {
        throw std::runtime_error(fmt::format("case {}: the derived value {} is not finite; please report this spec", c.name, key));
      }
    }
    m.layout = layout_json(stack);
    p.deck = options.deck_template_path ? render_template(tmpl, deck_variables(stack, res, p.files, c.name), tmpl_name)
                                        : default_deck(m);
    m.rendered = {formats::sha256_hex(p.deck), formats::sha256_hex(p.data), ""};
    p.manifest = formats::manifest_to_json(m).dump(2) + "\n";
    prepared.push_back(std::move(p));
    if (options.on_progress) options.on_progress(static_cast<long>(prepared.size()), 2 * static_cast<long>(cases.size()));
  }
  if (const auto why = model::why_large(total_cost(result.costs)); cases.size() > 1 && !why.empty() && !options.allow_large) {
    throw model::SpecError({{"size", fmt::format("the sweep of {} cases is large in all: {}; pass --large if you mean it",
                                                 cases.size(), why)}});
  }

  fs::create_directories(target.parent_path());
  // One generate at a time in this folder: what is there is checked, and replaced, in one step
  // (concurrent --force runs each write whole and report what they wrote, the last one's staying).
  const os::FolderLock folder(target.parent_path());
  std::vector<os::CaseLock> locks;
  if (fs::exists(fs::symlink_status(target))) {
    // --force replaces only what granstack made; anything else is refused whatever the flags.
    if (const auto why = formats::why_not_replaceable(options.output, formats::kGenerate); !why.empty()) {
      throw RefusedError(fmt::format("{} exists and is not replaced: {}; choose a new directory with -o", options.output.string(), why));
    }
    if (!options.force) {
      throw ExistsError(fmt::format("{} exists (a granstack {}); pass --force to replace it (its runs and results "
                                    "would be lost)",
                                    options.output.string(), fs::exists(target / "sweep.json") ? "sweep" : "case"));
    }
    if (const auto foreign = formats::foreign_entries(target); !foreign.empty()) {
      throw RefusedError(fmt::format("{} holds what granstack did not write there: {}{}; --force replaces only what "
                                     "granstack wrote: move those out first, or choose a new directory with -o",
                                     options.output.string(), fmt::join(foreign, ", "),
                                     foreign.size() == 10 ? ", ..." : ""));
    }
    // Every case in it is locked until it is gone: one a run or validate works in is refused.
    for (const auto& dir : formats::expand_case_dirs({target.string()})) {
      if (fs::is_directory(dir)) locks.emplace_back(dir, "granstack generate --force");
    }
  }
  const auto stamp = fmt::format("{}", ::getpid());
  // The siblings' names are kept within NAME_MAX (255 bytes) whatever the case's name is: a case
  // may be named with 255 bytes, and its temporary names are at most 214 (the folder lock makes
  // them unique: one generate at a time writes in this folder).
  const auto short_name = target.filename().string().substr(0, 200);
  const fs::path tmp = target.parent_path() / fmt::format(".{}.tmp-{}", short_name, stamp);
  const fs::path old = target.parent_path() / fmt::format(".{}.old-{}", short_name, stamp);
  result.sweep = prepared.size() > 1;
  try {
    fs::remove_all(tmp);
    if (!result.sweep) {
      write_case(tmp, prepared.front());
      result.case_dirs.push_back(target);
    } else {
      json index = {{"schema", formats::kManifestSchema}, {"created", created},
                    {"command_line", options.command_line}, {"cases", json::array()}};
      for (std::size_t i = 0; i < prepared.size(); ++i) {
        write_case(tmp / prepared[i].name, prepared[i]);
        if (options.on_progress) options.on_progress(static_cast<long>(prepared.size() + i + 1), 2 * static_cast<long>(prepared.size()));
        index["cases"].push_back({{"dir", prepared[i].name}, {"spec", formats::spec_to_json(cases[i].spec)}});
        result.case_dirs.push_back(target / prepared[i].name);
      }
      formats::write_file_atomically(tmp / "sweep.json", index.dump(2) + "\n");
    }
    if (fs::exists(target)) fs::rename(target, old);
    fs::rename(tmp, target);
    fs::remove_all(old);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    if (fs::exists(old, ec) && !fs::exists(target, ec)) fs::rename(old, target, ec);
    throw;
  }
  return result;
}

}  // namespace granstack::generator
