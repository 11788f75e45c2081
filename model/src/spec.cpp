#include <granstack/model/spec.hpp>
#include <granstack/model/spec_fields.hpp>
#include <granstack/model/stack.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <regex>

namespace granstack::model {

std::string_view to_string(Boundary b) { return b == Boundary::wall ? "wall" : "free"; }
std::string_view to_string(DumpFormat f) { return f == DumpFormat::binary ? "binary" : "text"; }

std::optional<Boundary> parse_boundary(std::string_view s) {
  if (s == "free") return Boundary::free_surface;
  if (s == "wall") return Boundary::wall;
  return std::nullopt;
}

std::string_view to_string(Geometry g) {
  return g == Geometry::nested3d ? "nested3d" : g == Geometry::panels ? "panels" : "strip";
}

std::optional<Geometry> parse_geometry(std::string_view s) {
  if (s == "strip") return Geometry::strip;
  if (s == "nested3d") return Geometry::nested3d;
  if (s == "panels") return Geometry::panels;
  return std::nullopt;
}

std::string_view to_string(Separator s) {
  return s == Separator::walls ? "walls" : s == Separator::none ? "none" : "matrix";
}

std::optional<Separator> parse_separator(std::string_view s) {
  if (s == "matrix") return Separator::matrix;
  if (s == "walls") return Separator::walls;
  if (s == "none") return Separator::none;
  return std::nullopt;
}

std::string_view to_string(Stacking s) {
  return s == Stacking::nested ? "nested" : s == Stacking::aligned ? "aligned" : "by_ratio";
}

std::optional<Stacking> parse_stacking(std::string_view s) {
  if (s == "by_ratio") return Stacking::by_ratio;
  if (s == "nested") return Stacking::nested;
  if (s == "aligned") return Stacking::aligned;
  return std::nullopt;
}

std::string_view to_string(OrderDependentYield o) { return o == OrderDependentYield::accept ? "accept" : "refuse"; }

std::optional<OrderDependentYield> parse_order_dependent_yield(std::string_view s) {
  if (s == "refuse") return OrderDependentYield::refuse;
  if (s == "accept") return OrderDependentYield::accept;
  return std::nullopt;
}

std::optional<DumpFormat> parse_dump_format(std::string_view s) {
  if (s == "text") return DumpFormat::text;
  if (s == "binary") return DumpFormat::binary;
  return std::nullopt;
}

std::string_view to_string(DumpFiles f) {
  return f == DumpFiles::per_step ? "per_step" : f == DumpFiles::per_rank ? "per_rank" : "single";
}

std::optional<DumpFiles> parse_dump_files(std::string_view s) {
  if (s == "single") return DumpFiles::single;
  if (s == "per_step") return DumpFiles::per_step;
  if (s == "per_rank") return DumpFiles::per_rank;
  return std::nullopt;
}

std::string_view to_string(StopRule r) { return r == StopRule::blow_end ? "blow_end" : "duration"; }

std::optional<StopRule> parse_stop_rule(std::string_view s) {
  if (s == "duration") return StopRule::duration;
  if (s == "blow_end") return StopRule::blow_end;
  return std::nullopt;
}

namespace {
std::pair<std::string, std::string> ordered(const std::string& a, const std::string& b) {
  return a <= b ? std::make_pair(a, b) : std::make_pair(b, a);
}
}  // namespace

double PairTable::get(const std::string& a, const std::string& b) const {
  auto it = pairs.find(ordered(a, b));
  return it == pairs.end() ? value : it->second;
}

void PairTable::set(const std::string& a, const std::string& b, double v) { pairs[ordered(a, b)] = v; }

const std::string& StackSpec::block_material(int k) const {
  return materials.size() == 1 ? materials.front() : materials.at(static_cast<std::size_t>(k - 1));
}

int StackSpec::rows_of(int k) const {
  return block_rows.empty() ? rows : block_rows.at(static_cast<std::size_t>(k - 1));
}

int StackSpec::ratio_below(int k) const {
  return radius_ratios.empty() ? radius_ratio : radius_ratios.at(static_cast<std::size_t>(k - 1));
}

double StackSpec::radius_factor(int k) const {
  if (radius_ratios.empty()) return std::pow(static_cast<double>(radius_ratio), blocks - k);
  double factor = 1.0;
  for (int j = k; j < blocks; ++j) factor *= ratio_below(j);
  return factor;
}

const std::string& StackSpec::effective_wall_material() const {
  return wall_material.empty() ? block_material(blocks) : wall_material;
}

const std::string& StackSpec::effective_striker_material() const {
  return striker_material.empty() ? block_material(1) : striker_material;
}

const std::string& StackSpec::effective_matrix_material() const {
  static const std::string teflon = "teflon";
  return matrix_material.empty() ? teflon : matrix_material;
}

ContactModel StackSpec::contact_model() const {
  return {normal_model, tangential_model, rolling_model, characteristic_velocity.value_or(striker_speed),
          yield_pressure_factor};
}

StackSpec liggghts_counterpart(const StackSpec& spec) {
  const auto law = normal_law(spec.normal_model).on_liggghts;
  if (law == spec.normal_model) return spec;
  auto out = spec;
  out.normal_model = law;
  out.dt.reset();
  out.dump_every.reset();
  out.series_every.reset();
  return out;
}

int StackSpec::measured_panel() const {
  if (geometry != Geometry::panels) return 1;
  return impact_panel > 0 ? impact_panel : (panels + 1) / 2;
}

bool StackSpec::has_walls() const {
  return bottom == Boundary::wall || sides == Boundary::wall ||
         (geometry == Geometry::panels && separator == Separator::walls);
}

bool StackSpec::strikes_every_panel() const { return geometry == Geometry::panels && impact_panel == kAllPanels; }

MaterialLibrary StackSpec::material_library() const {
  auto lib = MaterialLibrary::builtin();
  for (const auto& m : custom_materials) lib.add(m);
  return lib;
}

namespace {
std::string join_issues(const std::vector<SpecIssue>& issues) {
  std::string out = "invalid spec:";
  for (const auto& i : issues) out += fmt::format("\n  {}: {}", i.field, i.message);
  return out;
}
}  // namespace

SpecError::SpecError(std::vector<SpecIssue> issues) : std::runtime_error(join_issues(issues)), issues_(std::move(issues)) {}

namespace {
// The spheres of the stack, counted in floating point (exact below 2^53; a stack far too large
// to build does not overflow).
double spheres(const StackSpec& spec) {
  const bool container = spec.geometry == Geometry::panels;
  const double panels = container ? spec.panels : 1.0;
  double count = spec.strikes_every_panel() ? panels : 1.0, columns = spec.top_columns, radius = 1.0;
  for (int k = 1; k <= spec.blocks; ++k) {
    count += columns * (spec.geometry == Geometry::nested3d ? columns : panels) * spec.rows_of(k);
    if (container && spec.separator == Separator::matrix) {
      count += (panels - 1.0) * (spec.rows_of(k) - 1) * (columns - 1.0) * matrix_chain(radius, 1.0).count;
    }
    if (k < spec.blocks) {
      const bool odd = std::fmod(columns, 2.0) == 1.0;
      columns = columns * spec.ratio_below(k) + (extra_column_below(spec, k, odd) ? 1.0 : 0.0);
      radius /= spec.ratio_below(k);
    }
  }
  return count;
}
}  // namespace

long sphere_count(const StackSpec& spec) {
  const double count = spheres(spec);
  return count > static_cast<double>(kMaxSpheres) ? kMaxSpheres + 1 : static_cast<long>(count);
}

bool PairTable::everywhere(double v) const {
  return value == v && std::all_of(pairs.begin(), pairs.end(), [v](const auto& p) { return p.second == v; });
}

bool only_the_law_dissipates(const StackSpec& s) {
  // A rolling model dissipates (epsd2's torque spring also stores energy that no dump shows).
  const bool rolling = s.rolling_model != RollingModel::off && !s.rolling_friction.everywhere(0.0);
  return s.restitution.everywhere(1.0) && s.friction.everywhere(0.0) && s.gravity == 0.0 && !rolling &&
         s.mount_damping == 0.0;  // a plate's dashpot dissipates too
}

bool is_conservative(const StackSpec& s) { return only_the_law_dissipates(s) && !normal_law(s.normal_model).dissipative; }

namespace {
// The container's fields: refused on any other geometry (naming the field), in range on it.
template <typename Bad, typename Known>
void validate_container(const StackSpec& s, Bad&& bad, Known&& known, const std::string& known_list) {
  if (s.geometry != Geometry::panels) {
    const auto only = [&](const char* field) {
      bad(field, fmt::format("applies to geometry = panels only (this spec's geometry is {}): remove it, or set "
                             "geometry = panels",
                             to_string(s.geometry)));
    };
    if (s.panels != 0) only("panels");
    if (s.impact_panel != 0) only("impact_panel");
    if (s.separator != Separator::matrix) only("separator");
    if (!s.matrix_material.empty()) only("matrix_material");
    return;
  }
  if (s.panels < 2 || s.panels > kMaxPanels) {
    bad("panels", fmt::format("{} must be in [2, {}] (the panels side by side; one panel is geometry = strip)", s.panels,
                              kMaxPanels));
  } else if (s.impact_panel < kAllPanels || s.impact_panel > s.panels) {
    bad("impact_panel", fmt::format("{} must be in [1, {}] (the panel the striker hits, 1 = smallest y), or 'all' (a "
                                    "striker on every panel)",
                                    s.impact_panel, s.panels));
  }
  if (s.impact_panel == kAllPanels && s.striker_radius_ratio > 1.0) {
    bad("striker_radius_ratio", fmt::format("{} with a striker on every panel: strikers wider than the top spheres would "
                                            "overlap across the pitch (2 R_1); use 1, or hit one panel",
                                            s.striker_radius_ratio));
  }
  if (s.separator != Separator::matrix && !s.matrix_material.empty()) {
    bad("matrix_material", fmt::format("applies to separator = matrix only (this spec's separator is {})",
                                       to_string(s.separator)));
  } else if (!known(s.effective_matrix_material())) {
    bad("matrix_material", fmt::format("unknown material '{}' (known: {})", s.matrix_material, known_list));
  }
  if (s.separator == Separator::matrix && s.gravity > 0.0) {
    bad("gravity", "the matrix's chains hang between the panels on contacts at zero load, and the inner spheres of a "
                   "chain rest on nothing: with gravity use separator = walls or none");
  }
}
}  // namespace

namespace {
// Per-block rows and per-interface ratios: one per block, and one per interface.
template <typename Bad>
void validate_block_lists(const StackSpec& s, Bad&& bad) {
  if (!s.block_rows.empty() && s.block_rows.size() != static_cast<std::size_t>(s.blocks)) {
    bad("block_rows", fmt::format("{} rows listed for {} blocks: list one per block, top first (or give rows for all)",
                                  s.block_rows.size(), s.blocks));
  }
  if (!s.radius_ratios.empty() && s.radius_ratios.size() + 1 != static_cast<std::size_t>(s.blocks)) {
    bad("radius_ratio", fmt::format("{} ratios listed for {} blocks: list one per interface ({}), top first, or one "
                                    "for all",
                                    s.radius_ratios.size(), s.blocks, s.blocks - 1));
  }
  if (s.stacking != Stacking::by_ratio && s.geometry != Geometry::strip) {
    bad("stacking", fmt::format("{} applies to geometry = strip only (this spec's geometry is {}): leave it out for the "
                                "ratio's own stacking",
                                to_string(s.stacking), to_string(s.geometry)));
  } else if (s.stacking != Stacking::by_ratio && s.sides == Boundary::wall) {
    bad("stacking", fmt::format("{} with side walls: where a block gets a column more, the blocks' widths differ by a "
                                "sphere and no pair of walls holds them all; use sides = free",
                                to_string(s.stacking)));
  }
}

// The elastic-plastic laws: their yield pressure factor in range (and refused on the others), no
// viscous damping (they dissipate by yielding), and a yield strength for every material they meet.
template <typename Bad>
void validate_yield_law(const StackSpec& s, Bad&& bad) {
  const auto& law = normal_law(s.normal_model);
  const double f = s.yield_pressure_factor;
  if (s.order_dependent_yield != OrderDependentYield::refuse && s.normal_model != NormalModel::thornton_ning) {
    bad("order_dependent_yield", fmt::format("applies to normal_model = 'thornton_ning' only (LIGGGHTS's yield radius "
                                             "of atom i alone; this spec's is {}): remove it",
                                             to_string(s.normal_model)));
  }
  if (!law.needs_yield) {
    if (f != kDefaultYieldPressureFactor) {
      bad("yield_pressure_factor", fmt::format("applies to the elastic-plastic laws only (normal_model = 'thornton' or "
                                               "'thornton_ning'; this spec's is {}): remove it",
                                               to_string(s.normal_model)));
    }
    return;
  }
  if (!(std::isfinite(f) && f >= kMinYieldPressureFactor && f <= kMaxYieldPressureFactor)) {
    bad("yield_pressure_factor", fmt::format("{} is outside {:g}..{:g} (p_y / Y: {:g} at first yield, about 3 fully "
                                             "plastic)",
                                             f, kMinYieldPressureFactor, kMaxYieldPressureFactor,
                                             kDefaultYieldPressureFactor));
  }
  if (s.normal_model == NormalModel::thornton_ning && s.rolling_model == RollingModel::cdt) {
    bad("rolling_model", "cdt's torque is mu_r R* k_n delta, and LIGGGHTS's thornton_ning sets no k_n for it: use "
                         "rolling_model = 'epsd2' or 'off' with it");
  }
  if (!s.restitution.everywhere(1.0)) {
    bad("restitution", fmt::format("normal_model = '{}' dissipates by yielding and has no viscous damping (LIGGGHTS's "
                                   "thornton_ning would turn a restitution below 1 into a negative tangential "
                                   "damping): set restitution = 1 everywhere",
                                   to_string(s.normal_model)));
  }
  MaterialLibrary lib;
  try {
    lib = s.material_library();
  } catch (const std::exception&) {
    return;  // an unknown material is reported on its own field
  }
  std::vector<std::string> names;
  for (int k = 1; k <= s.blocks; ++k) names.push_back(s.block_material(k));
  names.push_back(s.effective_striker_material());
  if (s.has_walls()) names.push_back(s.effective_wall_material());
  if (s.geometry == Geometry::panels) names.push_back(s.effective_matrix_material());
  for (const auto& name : names) {
    const Material* m = lib.find(name);
    if (m != nullptr && !m->yield_strength) {
      bad("normal_model", fmt::format("'{}' needs every material's yield strength, and '{}' has none (a brittle "
                                      "material cracks rather than yields); use another material there, give it a "
                                      "yield_strength under [custom_materials], or use normal_model = 'hertz'",
                                      to_string(s.normal_model), name));
      return;
    }
  }
}

// The contact model's own fields: each refused where the chosen model does not use it.
template <typename Bad>
void validate_contact_model(const StackSpec& s, Bad&& bad) {
  const bool rolling_given = s.rolling_friction.value != 0.0 || !s.rolling_friction.pairs.empty();
  if (s.rolling_model == RollingModel::off && rolling_given) {
    const auto models = keyword_list<RollingModel>(true);
    bad("rolling_friction", fmt::format("applies to rolling_model = {} only (this spec has no rolling friction "
                                        "model): set a rolling_model ({}), or remove it",
                                        models, models));
  }
  validate_yield_law(s, bad);
  if (s.characteristic_velocity) {
    const double v = *s.characteristic_velocity;
    if (s.normal_model != NormalModel::hooke) {
      bad("characteristic_velocity", fmt::format("applies to normal_model = hooke only (this spec's is {}): remove it, "
                                                 "or set normal_model = \"hooke\"",
                                                 to_string(s.normal_model)));
    } else if (!(std::isfinite(v) && v >= kMinCharacteristicVelocity)) {
      bad("characteristic_velocity", fmt::format("{} must be at least {:g} m/s (LIGGGHTS's bound), or 'auto' (the "
                                                 "striker speed)",
                                                 v, kMinCharacteristicVelocity));
    }
  }
}
}  // namespace

namespace {
// The protected plate: under a bottom wall, without gravity (its rest on the mount under the stack's
// weight is not set up), its mount given only with it.
template <typename Bad>
void validate_plate(const StackSpec& s, Bad& bad) {
  if (!s.has_plate()) {
    if (s.mount_stiffness != 0.0 || s.mount_damping != 0.0) {
      bad(s.mount_stiffness != 0.0 ? "mount_stiffness" : "mount_damping",
          "mounts the protected plate: give it with plate_mass > 0 (and bottom = 'wall')");
    }
    return;
  }
  if (s.bottom != Boundary::wall) {
    bad("plate_mass", "is the mass of the bottom wall, a plate the stack strikes: give it with bottom = 'wall'");
  }
  if (s.gravity > 0.0) {
    bad("plate_mass", "with gravity the stack and the plate would first settle on the mount, which granstack does not "
                      "set up: use gravity 0 with a plate, or a rigid wall (plate_mass 0)");
  }
}
}  // namespace

std::vector<SpecIssue> validate(const StackSpec& s) {
  std::vector<SpecIssue> issues;
  auto bad = [&](std::string field, std::string message) { issues.push_back({std::move(field), std::move(message)}); };
  auto finite_positive = [](double v) { return std::isfinite(v) && v > 0.0; };

  static const std::regex name_re("[a-z][a-z0-9_]*");
  auto within = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  for (const auto& m : s.custom_materials) {
    const auto field = fmt::format("custom_materials.{}", m.name);
    if (!std::regex_match(m.name, name_re)) {
      bad(field, "a material name is lower-case letters, digits and '_', starting with a letter");
    }
    if (is_study_material(m.name)) {
      bad(field, fmt::format("'{}' is a built-in material and cannot be redefined (it is the study's); give yours "
                             "another name", m.name));
    }
    if (!within(m.density, kMinDensity, kMaxDensity)) {
      bad(field + ".density", fmt::format("{} must be in [{:g}, {:g}] kg/m^3", m.density, kMinDensity, kMaxDensity));
    }
    if (!within(m.youngs_modulus, kMinYoungsModulus, kMaxYoungsModulus)) {
      bad(field + ".youngs_modulus", fmt::format("{} must be in [{:g}, {:g}] Pa", m.youngs_modulus, kMinYoungsModulus,
                                                 kMaxYoungsModulus));
    }
    if (!(m.poisson_ratio >= 0.0 && m.poisson_ratio < 0.5)) {
      bad(field + ".poisson_ratio", fmt::format("{} must be in [0, 0.5)", m.poisson_ratio));
    }
    if (m.yield_strength && !(*m.yield_strength > 0.0 && *m.yield_strength < m.youngs_modulus)) {
      bad(field + ".yield_strength", fmt::format("{} Pa must be positive and below its Young's modulus ({:g} Pa)",
                                                 *m.yield_strength, m.youngs_modulus));
    }
  }

  // Each field's own range (spec_fields.cpp), then what holds across fields.
  for (const auto& f : spec_fields()) {
    if (f.check) f.check(s, issues);
  }
  validate_block_lists(s, bad);
  if (issues.empty() && !(s.bottom_radius * s.radius_factor(1) <= kMaxRadius)) {
    bad("bottom_radius", fmt::format("with radius_ratio {} and {} blocks the top spheres would be {:g} m in radius, more "
                                     "than {:g} m",
                                     s.radius_ratios.empty() ? fmt::format("{}", s.radius_ratio)
                                                             : fmt::format("{}", fmt::join(s.radius_ratios, ", ")),
                                     s.blocks, s.bottom_radius * s.radius_factor(1), kMaxRadius));
  }
  // Counted only for an otherwise valid spec (its blocks, rows and columns in range).
  if (const double count = issues.empty() ? spheres(s) : 0.0; count > static_cast<double>(kMaxSpheres)) {
    bad("blocks", fmt::format("this stack would have {:.3g} spheres, more than the {} granstack builds; refsim alone "
                              "would need about {:.3g} GB ({} GB per million spheres, measured); use fewer blocks, rows or "
                              "columns",
                              count, kMaxSpheres, count * kRefsimGigabytesPerMillionSpheres / 1e6,
                              kRefsimGigabytesPerMillionSpheres));
  }

  const auto lib = s.material_library();
  auto known = [&](const std::string& name) { return lib.find(name) != nullptr; };
  const auto known_list = fmt::format("{}", fmt::join(lib.names(), ", "));
  if (s.materials.empty()) {
    bad("materials", "give one material for every block, or one for all (known: " + known_list + ")");
  } else if (s.materials.size() != 1 && s.blocks >= 1 && s.materials.size() != static_cast<std::size_t>(s.blocks)) {
    bad("materials", fmt::format("{} materials listed for {} blocks: list one per block (top block first) or a "
                                 "single one for all",
                                 s.materials.size(), s.blocks));
  }
  for (const auto& name : s.materials) {
    if (!known(name)) bad("materials", fmt::format("unknown material '{}' (known: {})", name, known_list));
  }
  if (!s.wall_material.empty() && !known(s.wall_material)) {
    bad("wall_material", fmt::format("unknown material '{}' (known: {})", s.wall_material, known_list));
  }
  if (!s.striker_material.empty() && !known(s.striker_material)) {
    bad("striker_material", fmt::format("unknown material '{}' (known: {})", s.striker_material, known_list));
  }
  if (!within(s.striker_radius_ratio, 1.0, kMaxStrikerRadiusRatio)) {
    bad("striker_radius_ratio", fmt::format("{} must be in [1, {:g}] (the striker's radius over the top spheres')",
                                            s.striker_radius_ratio, kMaxStrikerRadiusRatio));
  } else if (s.sides == Boundary::wall && !(s.striker_radius_ratio + 2 * std::abs(s.impact_offset) < s.top_columns)) {  // x and, in 3D, y
    bad("striker_radius_ratio", fmt::format("{}{} would make the striker touch the side walls (at -+{} top radii): use "
                                            "a smaller striker, {}more top columns or free sides",
                                            s.striker_radius_ratio,
                                            s.impact_offset != 0 ? fmt::format(" at impact_offset {}", s.impact_offset) : "",
                                            s.top_columns, s.impact_offset != 0 ? "a blow nearer the centre, " : ""));
  }

  validate_container(s, bad, known, known_list);

  // The materials the stack is made of: its blocks, its striker, its walls and its matrix.
  std::vector<std::string> used = s.materials;
  if (!s.striker_material.empty()) used.push_back(s.striker_material);
  if (s.geometry == Geometry::panels && s.separator == Separator::matrix) used.push_back(s.effective_matrix_material());
  if (s.has_walls()) {
    used.push_back(!s.wall_material.empty() ? s.wall_material : s.materials.empty() ? "" : s.materials.back());
  }
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  auto in_stack = [&](const std::string& name) { return std::find(used.begin(), used.end(), name) != used.end(); };
  auto check_pairs = [&](const PairTable& t, const std::string& field, auto&& value_ok, const std::string& range) {
    if (!value_ok(t.value)) bad(field, fmt::format("{} must be {}", t.value, range));
    for (const auto& [key, v] : t.pairs) {
      const auto pf = fmt::format("{}_pairs.\"{}:{}\"", field, key.first, key.second);
      if (!known(key.first) || !known(key.second)) {
        bad(pf, fmt::format("names an unknown material (known: {})", known_list));
      } else if (!in_stack(key.first) || !in_stack(key.second)) {
        bad(pf, fmt::format("names a material this stack does not use (it uses: {}): the entry would have no effect",
                            fmt::join(used, ", ")));
      }
      if (!value_ok(v)) bad(pf, fmt::format("{} must be {}", v, range));
    }
  };
  // LIGGGHTS refuses e <= 0.05 (global_properties.cpp:488-489; docs/liggghts.md section 1).
  check_pairs(s.restitution, "restitution", [](double e) { return e > 0.05 && e <= 1.0; }, "in (0.05, 1]");
  check_pairs(s.friction, "friction", [&](double mu) { return within(mu, 0.0, kMaxFriction); },
              fmt::format("in [0, {:g}]", kMaxFriction));

  check_pairs(s.rolling_friction, "rolling_friction", [&](double mu) { return within(mu, 0.0, kMaxRollingFriction); },
              fmt::format("in [0, {:g}]", kMaxRollingFriction));
  validate_contact_model(s, bad);

  if (s.stop == StopRule::blow_end && s.duration) {
    bad("duration", "a run that stops at the blow's end lasts until then, at most cap_durations automatic durations: "
                    "leave duration 'auto' and set cap_durations, or use stop = 'duration'");
  }
  if (s.stop == StopRule::blow_end && s.gravity > 0.0) {
    bad("stop", "with gravity the stack comes to rest on its support, so the blow has no end to stop at: use stop = "
                "'duration' (the default), or gravity 0");
  }
  validate_plate(s, bad);
  if (s.stop == StopRule::duration && s.cap_durations != kBlowEndCapDurations) {
    bad("cap_durations", "caps a run that stops at the blow's end: give it with stop = 'blow_end'");
  }
  if (s.dt && s.duration && finite_positive(*s.dt) && *s.dt >= *s.duration) {
    bad("dt", fmt::format("{} must be smaller than the duration {}", *s.dt, *s.duration));
  }
  return issues;
}

void require_valid(const StackSpec& spec) {
  auto issues = validate(spec);
  if (!issues.empty()) throw SpecError(std::move(issues));
}

}  // namespace granstack::model
