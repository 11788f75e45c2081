#include <granstack/design/objectives.hpp>
#include <granstack/design/search.hpp>
#include <granstack/design/space.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/generator/spec_input.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/shock.hpp>
#include <granstack/model/spec_fields.hpp>
#include <granstack/runner/engines.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <granstack/model/toml_input.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

namespace granstack::design {

namespace {
// The spec fields a design varies: [fixed] may not set them.
const std::vector<std::string> kVaried{"blocks", "rows", "block_rows", "materials", "radius_ratio", "bottom_radius"};
// The study's top block (8 rows of 8 mm spheres over 4 blocks with a 1 mm bottom radius).
constexpr const char* kStudyMaterial = "steel";

std::string joined(const std::vector<std::string>& v) { return fmt::format("{}", fmt::join(v, ", ")); }

// A whole number or a [min, max] pair, into lo..hi.
void int_range(const toml::table& t, const char* key, int& lo, int& hi, int floor, int ceiling,
               std::vector<std::string>& problems) {
  const auto* n = t.get(key);
  if (n == nullptr) {
    problems.push_back(fmt::format("[vary] {} is missing: give a whole number or [min, max]", key));
    return;
  }
  if (const auto v = n->value<std::int64_t>()) {
    lo = hi = static_cast<int>(*v);
  } else if (const auto* a = n->as_array(); a != nullptr && a->size() == 2 && a->get(0)->value<std::int64_t>() &&
                                            a->get(1)->value<std::int64_t>()) {
    lo = static_cast<int>(*a->get(0)->value<std::int64_t>());
    hi = static_cast<int>(*a->get(1)->value<std::int64_t>());
  } else {
    problems.push_back(fmt::format("[vary] {}: a whole number or [min, max] of whole numbers", key));
    return;
  }
  if (lo > hi) problems.push_back(fmt::format("[vary] {} = [{}, {}]: the minimum is above the maximum", key, lo, hi));
  if (lo < floor || hi > ceiling) problems.push_back(fmt::format("[vary] {}: from {} to {}", key, floor, ceiling));
}

template <typename T>
std::vector<T> list_of(const toml::table& t, const char* key, std::vector<std::string>& problems) {
  std::vector<T> out;
  const auto* a = t.get_as<toml::array>(key);
  if (a == nullptr) {
    problems.push_back(fmt::format("[vary] {}: a list is needed", key));
    return out;
  }
  for (const auto& e : *a) {
    if (const auto v = e.value<T>()) {
      if (std::find(out.begin(), out.end(), *v) != out.end()) {
        problems.push_back(fmt::format("[vary] {}: {} is listed twice; list each choice once", key, *v));
      }
      out.push_back(*v);
    } else {
      problems.push_back(fmt::format("[vary] {}: every entry must be a {}", key, std::is_same_v<T, std::string> ? "name" : "whole number"));
    }
  }
  if (out.empty()) problems.push_back(fmt::format("[vary] {} is empty: nothing to choose from", key));
  return out;
}

// A design is a protector: its stack stands between rigid side walls unless the space says
// sides = "free" (a free strip splays sideways: 70-92 % of E_in went into the blocks' sideways
// motion, and its front was a property of the splay). Spaces stored before 2026-11-28 were read
// with free sides where they named none (`free_sides_by_default`), and are still read so.
void read_fixed(const toml::table* fixed, const std::string& source, Space& s, std::vector<std::string>& problems,
                bool free_sides_by_default) {
  toml::table spec = fixed != nullptr ? *fixed : toml::table{};
  if (!spec.contains("sides") && !free_sides_by_default) spec.insert("sides", "wall");
  if (const auto* r = spec.get("top_radius")) {
    if (const auto v = r->value<double>(); v && *v > 0) s.top_radius = *v;
    else problems.push_back("[fixed] top_radius: a radius in m, > 0");
    spec.erase("top_radius");
  }
  for (const auto& key : kVaried) {
    if (spec.contains(key)) problems.push_back(fmt::format("[fixed] {}: the search varies it; set its range in [vary] instead", key));
    spec.erase(key);
  }
  std::ostringstream os;
  os << spec;
  try {
    const auto sweep = generator::build_sweep(generator::parse_spec_toml(os.str(), source + " [fixed]"));
    if (!sweep.axes.empty()) problems.push_back(fmt::format("[fixed] {}: one value, not a list (a design space is not a sweep)", sweep.axes.front().field));
    s.fixed = sweep.base;
    // The striker and the wall belong to the test, not the design: they stay the study's steel
    // unless fixed otherwise (left empty they would follow the top and bottom blocks); a stack
    // without a wall has no wall material.
    if (s.fixed.striker_material.empty()) s.fixed.striker_material = kStudyMaterial;
    if (s.fixed.wall_material.empty() && s.fixed.has_walls()) s.fixed.wall_material = kStudyMaterial;
    // The search runs refsim by LIGGGHTS's rules: a model LIGGGHTS lacks cannot be searched.
    if (const auto why = runner::model_refusal(runner::Engine::refsim, s.fixed.contact_model()); !why.empty()) {
      problems.push_back(fmt::format("[fixed] {}: the search runs refsim by LIGGGHTS's contact rules, and {}", why.substr(0, why.find(" =")),
                                     why));
    }
  } catch (const model::SpecError& e) {
    for (const auto& i : e.issues()) problems.push_back(fmt::format("[fixed] {}: {}", i.field, i.message));
  }
}

void read_vary(const toml::table* vary, Space& s, std::vector<std::string>& problems) {
  if (vary == nullptr) {
    problems.push_back("[vary] is missing: give blocks, materials, radius_ratio and rows");
    return;
  }
  for (const auto& [k, v] : *vary) {
    const std::string key(k.str());
    if (key != "blocks" && key != "materials" && key != "radius_ratio" && key != "rows") {
      problems.push_back(fmt::format("[vary] {}: unknown; the search varies blocks, materials, radius_ratio and rows", key));
    }
  }
  int_range(*vary, "blocks", s.min_blocks, s.max_blocks, 1, 12, problems);
  int_range(*vary, "rows", s.min_rows, s.max_rows, 1, 4096, problems);
  s.materials = list_of<std::string>(*vary, "materials", problems);
  for (const auto r : list_of<std::int64_t>(*vary, "radius_ratio", problems)) {
    if (r < 1 || r > 16) problems.push_back(fmt::format("[vary] radius_ratio: {} is not a whole number from 1 to 16", r));
    s.radius_ratios.push_back(static_cast<int>(r));
  }
  std::sort(s.radius_ratios.begin(), s.radius_ratios.end());
  s.radius_ratios.erase(std::unique(s.radius_ratios.begin(), s.radius_ratios.end()), s.radius_ratios.end());
  const auto lib = s.fixed.material_library();
  for (const auto& m : s.materials) {
    if (lib.find(m) == nullptr) {
      problems.push_back(fmt::format("[vary] materials: '{}' is unknown; the built-in ones are {}, or define it under "
                                     "[fixed.custom_materials.{}]", m, joined(model::MaterialLibrary::builtin().names()), m));
    }
  }
}

std::vector<std::string> objective_names() {
  std::vector<std::string> names;
  for (const auto& o : objective_table()) names.emplace_back(o.name);
  return names;
}

void read_objectives(const toml::table& root, Space& s, std::vector<std::string>& problems) {
  const auto* a = root.get_as<toml::array>("objectives");
  if (a == nullptr) {
    const auto* given = root.get("objectives");
    problems.push_back(given == nullptr
                           ? fmt::format("objectives is missing: a list of two or more of {}", joined(objective_names()))
                           : fmt::format("objectives = {}: a list of two or more of {}, e.g. objectives = [\"{}\", "
                                         "\"areal_mass\"]",
                                         model::toml_text(*given), joined(objective_names()),
                                         given->value<std::string>().value_or("peak_wall_force")));
    return;
  }
  for (const auto& e : *a) {
    const auto o = e.value<std::string>() ? find_objective(*e.value<std::string>()) : nullptr;
    if (const auto retired = retired_measure(e.value_or<std::string>("")); !retired.empty()) problems.push_back(fmt::format("objectives: {}", retired));
    else if (o == nullptr) problems.push_back(fmt::format("objectives: '{}' is not one of {}", e.value_or<std::string>("?"), joined(objective_names())));
    else if (std::find(s.objectives.begin(), s.objectives.end(), o) != s.objectives.end()) problems.push_back(fmt::format("objectives: {} twice", to_string(o)));
    else s.objectives.push_back(o);
  }
  if (a->size() < 2) problems.push_back("objectives: at least two (the search is multi-objective; one objective has one best design, no front)");
}

// [measures] keys of what the protected object feels: true when `key` is one (read, or its problem said).
bool read_shock_measure(const std::string& key, const toml::node& v, Space& s, std::vector<std::string>& problems) {
  const auto number = v.value<double>();
  if (key == "cfc") {
    if (!number || !model::is_channel_class(static_cast<int>(*number)) || *number != std::floor(*number)) {
      problems.push_back("[measures] cfc: an SAE J211-1 channel frequency class, 60, 180, 600 or 1000 (the force's filter: "
                         "3 dB down at 5/3 of it, in Hz)");
    } else {
      s.cfc = static_cast<int>(*number);
    }
  } else if (key == "protected_mass") {
    if (!number || !(*number > 0.0) || !std::isfinite(*number)) problems.push_back("[measures] protected_mass: a mass in kg, > 0");
    else s.protected_mass = *number;
  } else if (key == "srs_damping") {
    if (!number || !(*number >= 0.0) || !(*number < 1.0)) problems.push_back("[measures] srs_damping: a damping ratio, 0 <= zeta < 1 (0.05 is usual)");
    else s.srs_damping = *number;
  } else if (key == "srs_band") {
    const auto* a = v.as_array();
    const auto lo = a != nullptr && a->size() == 2 ? (*a)[0].value<double>() : std::nullopt;
    const auto hi = a != nullptr && a->size() == 2 ? (*a)[1].value<double>() : std::nullopt;
    if (!lo || !hi || !(*lo > 0.0) || !(*hi > *lo) || !std::isfinite(*hi)) {
      problems.push_back("[measures] srs_band: [low, high], the natural frequencies (Hz) the shock response spectrum spans, "
                         "0 < low < high");
    } else {
      s.srs_low = *lo;
      s.srs_high = *hi;
    }
  } else {
    return false;
  }
  return true;
}

// The settings each measure of what the protected object feels needs, for the objectives and
// constraints that name it.
// A setting given with a value refused is not also said to be missing (`given`: the [measures]
// keys the file names).
void require_shock_settings(Space& s, const std::set<std::string>& given, std::vector<std::string>& problems) {
  const auto named = [&](std::string_view m) {
    return std::find(s.objectives.begin(), s.objectives.end(), find_objective(m)) != s.objectives.end() ||
           s.constraints.max_measures.count(std::string(m)) > 0;
  };
  const auto missing = [&](const char* key, bool unset) { return unset && given.count(key) == 0; };
  for (const char* m : {"filtered_wall_force", "protected_acceleration"}) {
    if (named(m) && missing("cfc", s.cfc == 0)) {
      problems.push_back(fmt::format("{} needs its filter: set [measures] cfc (SAE J211-1's channel frequency class: 60, 180, "
                                     "600 or 1000)", m));
    }
  }
  // Over a protected plate in the run the measures read its own acceleration: the plate is the
  // protected object, and a second mass beside it would say something else.
  if (s.fixed.has_plate() && s.protected_mass > 0.0) {
    problems.push_back(fmt::format("[measures] protected_mass: the protected object is the plate of [fixed] plate_mass "
                                   "({:g} kg), whose own acceleration the measures read; leave protected_mass out",
                                   s.fixed.plate_mass));
  }
  for (const char* m : {"protected_acceleration", "srs_peak"}) {
    if (named(m) && !s.fixed.has_plate() && missing("protected_mass", s.protected_mass <= 0.0)) {
      problems.push_back(fmt::format("{} needs [measures] protected_mass (kg), or a protected plate in the run ([fixed] "
                                     "bottom = \"wall\" with plate_mass)", m));
    }
  }
  if (named("srs_peak") && missing("srs_band", s.srs_high <= 0.0)) {
    problems.push_back("srs_peak needs [measures] srs_band = [low, high] (Hz), e.g. [100, 10000]");
  }
}

std::set<std::string> keys_of(const toml::table* t) {
  std::set<std::string> keys;
  if (t != nullptr) {
    for (const auto& [k, v] : *t) keys.insert(std::string(k.str()));
  }
  return keys;
}

// [measures]: the settings of measures that take one (wall_impulse's window).
void read_measures(const toml::table* t, Space& s, std::vector<std::string>& problems) {
  if (t != nullptr) {
    for (const auto& [k, v] : *t) {
      const std::string key(k.str());
      const auto number = v.value<double>();
      if (read_shock_measure(key, v, s, problems)) continue;
      if (key == "cap_durations") {
        if (!number || !(*number >= model::kMinBlowEndCapDurations) || !(*number <= 1000.0)) {
          problems.push_back(fmt::format("[measures] cap_durations: from {:g} to 1000 automatic durations (a run stops when "
                                         "its blow has ended, at most this long; a shorter cap leaves the blow's end no "
                                         "time to be seen, and every design censored)", model::kMinBlowEndCapDurations));
        } else {
          s.cap_durations = *number;
        }
      } else if (key != "impulse_window") {
        problems.push_back(fmt::format("[measures] {}: unknown; impulse_window (s, the window of wall_impulse), "
                                       "cap_durations (a run's cap, in automatic durations), cfc, protected_mass, srs_band "
                                       "or srs_damping", key));
      } else if (!number || !(*number > 0) || !std::isfinite(*number)) {
        problems.push_back("[measures] impulse_window: a time in s, > 0 (the window wall_impulse integrates the wall's force over)");
      } else {
        s.impulse_window = *number;
      }
    }
  }
  const auto wants = std::find(s.objectives.begin(), s.objectives.end(), find_objective("wall_impulse")) != s.objectives.end();
  if (wants && s.impulse_window <= 0.0) {
    problems.push_back("objectives: wall_impulse needs its window: set [measures] impulse_window (s), e.g. 1e-4 for the "
                       "load a body behind the wall feels over 0.1 ms");
  }
}

// [scenarios]: lists of striker speeds, striker radius ratios, impact offsets and an
// elastic-plastic law's yield pressure factors (their product), and how each objective is taken
// over them.
void read_scenarios(const toml::table* t, const toml::table* fixed, Space& s, std::vector<std::string>& problems) {
  if (t == nullptr) return;
  std::vector<double> speeds{s.fixed.striker_speed}, ratios{s.fixed.striker_radius_ratio},
      offsets{static_cast<double>(s.fixed.impact_offset)};
  const auto list = [&](const char* key, double lo, double hi, std::vector<double>& out) {
    const auto* node = t->get(key);
    if (node == nullptr) return;
    if (fixed != nullptr && fixed->contains(key)) {
      problems.push_back(fmt::format("[fixed] {}: [scenarios] lists it; set it in one place", key));
    }
    const auto* a = node->as_array();
    out.clear();
    if (a == nullptr || a->empty()) {
      problems.push_back(fmt::format("[scenarios] {}: a non-empty list of numbers from {:g} to {:g}", key, lo, hi));
      return;
    }
    for (const auto& e : *a) {
      const auto v = e.value<double>();
      if (!v || !std::isfinite(*v) || *v < lo || *v > hi) {
        problems.push_back(fmt::format("[scenarios] {}: {} is not a number from {:g} to {:g}", key,
                                       v ? fmt::format("{}", *v) : std::string("an entry"), lo, hi));
      } else if (std::find(out.begin(), out.end(), *v) != out.end()) {
        problems.push_back(fmt::format("[scenarios] {}: {} is listed twice", key, *v));
      } else {
        out.push_back(*v);
      }
    }
  };
  list("striker_speed", 1e-6, 1e4, speeds);
  list("striker_radius_ratio", 1.0, 16.0, ratios);
  // Off-centre blows: whole numbers of top-sphere diameters, within the footprint's top row.
  const double most = std::max(0, s.fixed.top_columns / 2 - 1);
  if (most == 0 && t->contains("impact_offset")) {
    problems.push_back(fmt::format("[scenarios] impact_offset: the footprint's {} top columns leave no room off centre; "
                                   "give [fixed] top_columns = 4 or more", s.fixed.top_columns));
  } else {
    list("impact_offset", -most, most, offsets);
  }
  for (const double k : offsets) {
    if (k != std::floor(k)) problems.push_back(fmt::format("[scenarios] impact_offset: {} is not a whole number", k));
  }
  // How hard the contacts yield: a search robust to where between first yield and full
  // plasticity the material's p_y lies (the worst over them, as over the speeds).
  std::vector<double> factors;  // none: the fixed spec's
  list("yield_pressure_factor", model::kMinYieldPressureFactor, model::kMaxYieldPressureFactor, factors);
  if (!factors.empty() && !model::normal_law(s.fixed.normal_model).needs_yield) {
    problems.push_back(fmt::format("[scenarios] yield_pressure_factor: applies to the elastic-plastic laws ([fixed] "
                                   "normal_model = 'thornton' or 'thornton_ning'; this space's is {})",
                                   model::to_string(s.fixed.normal_model)));
  }
  for (const auto& [k, v] : *t) {
    const std::string key(k.str());
    if (key == "striker_speed" || key == "striker_radius_ratio" || key == "impact_offset" || key == "yield_pressure_factor") {
      continue;
    }
    if (key != "aggregate") {
      problems.push_back(fmt::format("[scenarios] {}: unknown; striker_speed, striker_radius_ratio, impact_offset, "
                                     "yield_pressure_factor (lists) and aggregate", key));
      continue;
    }
    const auto parse = [&](const toml::node& n, const std::string& what) -> std::optional<Aggregate> {
      const auto text = n.value<std::string>();
      if (text == "worst") return Aggregate::worst;
      if (text == "mean") return Aggregate::mean;
      problems.push_back(fmt::format("[scenarios] aggregate{}: \"worst\" or \"mean\"", what));
      return std::nullopt;
    };
    if (const auto* per = v.as_table()) {
      for (const auto& [name, how] : *per) {
        const auto o = find_objective(name.str());
        if (const auto retired = retired_measure(name.str()); !retired.empty()) {
          problems.push_back(fmt::format("[scenarios.aggregate] {}", retired));
        } else if (o == nullptr || o->from_run == nullptr) {
          problems.push_back(fmt::format("[scenarios.aggregate] {}: not a run measure ({})", name.str(), joined(run_measure_names())));
        } else if (const auto a = parse(how, fmt::format(".{}", name.str()))) {
          s.aggregate[std::string(name.str())] = *a;
        }
      }
    } else if (const auto a = parse(v, "")) {
      for (const auto& name : run_measure_names()) s.aggregate[name] = *a;
    }
  }
  std::vector<std::optional<double>> yields(factors.begin(), factors.end());
  if (yields.empty()) yields.emplace_back();
  for (const double v : speeds) {
    for (const double r : ratios) {
      for (const double k : offsets) {
        for (const auto& f : yields) {
          const int off = static_cast<int>(k);
          s.scenarios.push_back({fmt::format("{:g} m/s, striker {:g} R_1{}{}", v, r,
                                             off == 0 ? "" : fmt::format(", {} diameter{} off centre", off, std::abs(off) == 1 ? "" : "s"),
                                             f ? fmt::format(", p_y {:g} Y", *f) : ""),
                                 v, r, off, f});
        }
      }
    }
  }
}

// [confirm]: geometry = "nested3d" and/or sides = "wall" | "free".
void read_confirm(const toml::table* t, Space& s, std::vector<std::string>& problems) {
  static const toml::table none;
  for (const auto& [k, v] : t != nullptr ? *t : none) {
    const std::string key(k.str());
    const auto text = v.value<std::string>();
    if (key == "geometry") {
      if (text == "nested3d") s.confirm_variant.geometry = model::Geometry::nested3d;
      else problems.push_back("[confirm] geometry: \"nested3d\" (the strip's blocks as a 3D nest)");
    } else if (key == "sides") {
      const auto b = text ? model::parse_boundary(*text) : std::nullopt;
      if (b) s.confirm_variant.sides = *b;
      else problems.push_back("[confirm] sides: \"wall\" or \"free\"");
    } else {
      problems.push_back(fmt::format("[confirm] {}: unknown; geometry and sides", key));
    }
  }
  if (const auto why = s.confirm_variant.problem(s.fixed); !why.empty()) problems.push_back("[confirm] " + why);
  // Free sides: confirm also runs each design between side walls, so that the report can say what
  // confining changes (where walls can stand: not beside a striker as wide as the footprint).
  if (s.confirm_variant.empty() && s.fixed.sides == model::Boundary::free_surface) {
    ConfirmVariant walls;
    walls.sides = model::Boundary::wall;
    if (walls.problem(s.fixed).empty()) s.confirm_variant = walls;
  }
}

// Whether a space varies the bottom spheres' radius: the footprint is fixed, so any choice of
// blocks or ratios beyond one changes R_N = R_1 / (product of the ratios).
bool varies_bottom_radius(const Space& s) {
  return s.max_blocks > 1 && (s.min_blocks != s.max_blocks || s.radius_ratios.size() > 1);
}

// Objectives a geometry cannot measure; and (into `unsound`) measures its designs would win by
// shrinking, or runs a fixed duration could cut before the blow arrives.
void check_measurable(const Space& s, std::vector<std::string>& problems, std::vector<std::string>& unsound) {
  const bool wall = s.fixed.bottom == model::Boundary::wall;
  for (const auto o : s.objectives) {
    if (o->needs == Needs::free_bottom && wall) {
      problems.push_back(fmt::format("objectives: {} needs a free bottom (the output spheres must leave); set [fixed] "
                                     "bottom = \"free\", or minimise peak_wall_force against the wall", to_string(o)));
    }
    if (o->needs == Needs::wall && !wall) {
      problems.push_back(fmt::format("objectives: {} is measured on the protected object, the bottom wall; set [fixed] "
                                     "bottom = \"wall\"", to_string(o)));
    }
    if (o->gameable_by_bottom_radius && varies_bottom_radius(s)) {
      unsound.push_back(fmt::format(
          "objectives: {} is the energy of the outgoing layer's spheres, whose mass falls as the bottom radius R_1 / "
          "(product of the ratios) shrinks; this space varies it ({} to {} blocks, ratios {}), so the search would win "
          "by making the measured spheres lighter, not by protecting. Measure protection on the protected object "
          "([fixed] bottom = \"wall\" with peak_wall_force, wall_impulse and crush), or fix the bottom radius (one "
          "number of blocks and one radius_ratio)",
          to_string(o), s.min_blocks, s.max_blocks, fmt::join(s.radius_ratios, ", ")));
    }
  }
  for (const auto& [name, bound] : s.constraints.max_measures) {
    const auto o = find_objective(name);
    if ((o->needs == Needs::wall && !wall) || (o->needs == Needs::free_bottom && wall)) {
      problems.push_back(fmt::format("[constraints] max_{}: {} needs {}", name, name, to_string(o->needs)));
    }
  }
  if (s.fixed.geometry == model::Geometry::panels) {
    problems.push_back("[fixed] geometry = \"panels\": a container's designs are its panels' designs; search the strip "
                       "(geometry = \"strip\") and set the winners side by side");
  }
  if (s.fixed.duration) {
    unsound.push_back("[fixed] duration: each design runs for its own automatic duration, checked to leave its output or "
                       "its load final; one fixed duration can end before the blow arrives (every design then scores 0). "
                       "Remove it");
  }
}

void read_constraints(const toml::table* c, Space& s, std::vector<std::string>& problems) {
  if (c == nullptr) return;
  for (const auto& [k, v] : *c) {
    const std::string key(k.str());
    const auto number = v.value<double>();
    if (!number || !(*number > 0)) {
      problems.push_back(fmt::format("[constraints] {}: a positive number", key));
      continue;
    }
    if (key == "max_spheres" && *number != std::floor(*number)) {
      problems.push_back(fmt::format("[constraints] max_spheres = {}: a whole number of spheres", *number));
    } else if (key == "max_spheres") s.constraints.max_spheres = static_cast<long>(*number);
    else if (key == "max_height") s.constraints.max_height = *number;
    else if (key == "max_areal_mass") s.constraints.max_areal_mass = *number;
    else if (const auto o = key.rfind("max_", 0) == 0 ? find_objective(key.substr(4)) : nullptr; o != nullptr && o->from_run != nullptr) {
      s.constraints.max_measures[std::string(o->name)] = *number;
    } else if (const auto retired = key.rfind("max_", 0) == 0 ? retired_measure(key.substr(4)) : std::string_view{}; !retired.empty()) {
      problems.push_back(fmt::format("[constraints] {}: {}", key, retired));
    } else {
      problems.push_back(fmt::format("[constraints] {}: unknown; max_spheres, max_height (m), max_areal_mass (kg/m^2), or "
                                     "max_ and a run measure ({})", key, joined(run_measure_names())));
    }
  }
}

void read_seeds(const toml::array& a, Space& s, std::vector<std::string>& problems);

// [search]'s operator settings, each within what pagmo2's operators take.
void read_operator(const std::string& key, const toml::node& v, Space& s, std::vector<std::string>& problems) {
  const auto x = v.value<double>();
  const bool eta = key == "crossover_eta" || key == "mutation_eta";
  const bool ok = x && (eta ? *x >= 1.0 && *x < 100.0 : key == "crossover_probability" ? *x >= 0.0 && *x < 1.0 : *x >= 0.0 && *x <= 1.0);
  if (!ok) {
    problems.push_back(fmt::format("[search] {}: {}", key, eta ? "a distribution index from 1 to below 100"
                                                          : key == "crossover_probability" ? "a probability from 0 to below 1"
                                                                                           : "a probability from 0 to 1"));
    return;
  }
  if (key == "crossover_probability") s.search.crossover_probability = *x;
  else if (key == "front_parents" || key == "step_mutation") {
    (key == "front_parents" ? s.search.front_parents : s.search.step_mutation) = *x;
    s.search.breeding_given = true;
  } else if (key == "crossover_eta") s.search.crossover_eta = *x;
  else if (key == "mutation_eta") s.search.mutation_eta = *x;
  else s.search.mutation_probability = *x;
}

// [search]'s whole-number keys: population, generations, seed, max_designs, stagnation.
void read_search_count(const std::string& key, const toml::node& v, Space& s, std::vector<std::string>& problems) {
  const auto n = v.value_exact<std::int64_t>();
  const long most = key == "population" ? kMaxPopulation : key == "generations" ? kMaxGenerations
                    : key == "stagnation" ? kMaxGenerations : -1;
  const long least = key == "max_designs" ? kLeastMaxDesigns : 0;
  if (!n || *n < least || (most >= 0 && *n > most)) {
    problems.push_back(most >= 0 ? fmt::format("[search] {}: a whole number from {} to {}", key, least, most)
                                 : fmt::format("[search] {}: a whole number >= {}{}", key, least,
                                               key == "max_designs" ? fmt::format(" ({})", kLeastMaxDesignsWhy) : ""));
  } else if (key == "population") s.search.population = static_cast<int>(*n);
  else if (key == "generations") s.search.generations = static_cast<int>(*n);
  else if (key == "stagnation") s.search.stagnation = static_cast<int>(*n);
  else if (key == "max_designs") s.search.max_designs = static_cast<long>(*n);
  else {
    s.search.seed = static_cast<std::uint64_t>(*n);
    s.search.seeds = {s.search.seed};
  }
}

// [search] seed = [N, M, ...]: one run of the search per seed, into one store.
void read_seeds(const toml::array& a, Space& s, std::vector<std::string>& problems) {
  std::vector<std::uint64_t> seeds;
  for (const auto& e : a) {
    const auto n = e.value_exact<std::int64_t>();
    if (!n || *n < 0) {
      problems.push_back("[search] seed: a whole number >= 0, or a list of them (a run per seed)");
      return;
    }
    if (std::find(seeds.begin(), seeds.end(), static_cast<std::uint64_t>(*n)) != seeds.end()) {
      problems.push_back(fmt::format("[search] seed: {} is listed twice; list each seed once", *n));
      return;
    }
    seeds.push_back(static_cast<std::uint64_t>(*n));
  }
  if (seeds.empty() || seeds.size() > kMaxSeeds) {
    problems.push_back(fmt::format("[search] seed: a list of 1 to {} seeds", kMaxSeeds));
    return;
  }
  s.search.seeds = seeds;
  s.search.seed = seeds.front();
}

void read_search(const toml::table* t, Space& s, std::vector<std::string>& problems) {
  if (t == nullptr) return;
  for (const auto& [k, v] : *t) {
    const std::string key(k.str());
    if (key == "evaluation") {
      const auto name = v.value_exact<std::string>();
      if (name == "asynchronous" || name == "generational") {
        s.search.schedule = *name == "asynchronous" ? Schedule::asynchronous : Schedule::generational;
        s.search.schedule_given = true;
      } else {
        problems.push_back("[search] evaluation: \"asynchronous\" (a design starts whenever one ends: every core busy) or "
                           "\"generational\" (a generation at a time: the same search on any number of cores)");
      }
    } else if (key == "algorithm") {
      const auto name = v.value_exact<std::string>().value_or("");
      const std::vector<std::pair<std::string, Algorithm>> known{
          {"nsga2", Algorithm::nsga2}, {"nsga3", Algorithm::nsga3}, {"sms-emoa", Algorithm::sms_emoa}, {"moead", Algorithm::moead}};
      const auto it = std::find_if(known.begin(), known.end(), [&](const auto& entry) { return entry.first == name; });
      if (it != known.end()) s.search.algorithm = it->second;
      else problems.push_back(fmt::format("[search] algorithm = \"{}\": \"nsga2\", \"nsga3\", \"sms-emoa\" or \"moead\"", name));
    } else if (key == "start") {
      const auto* a = v.as_array();
      for (std::size_t i = 0; a != nullptr && i < a->size(); ++i) {
        if (const auto name = a->get(i)->value_exact<std::string>()) s.search.start_files.push_back(*name);
      }
      if (a == nullptr || s.search.start_files.size() != a->size()) {
        problems.push_back("[search] start: a list of spec files (granstack generate --config's), relative to the space file");
      }
    } else if (key == "crossover_probability" || key == "crossover_eta" || key == "mutation_eta" || key == "mutation_probability" ||
               key == "front_parents" || key == "step_mutation") {
      read_operator(key, v, s, problems);
    } else if (key == "shortcuts") {
      const auto on = v.value_exact<bool>();
      if (!on) problems.push_back("[search] shortcuts: true (settle a design once its scenarios so far decide it) or false (run every scenario)");
      else s.search.shortcuts = *on;
    } else if (key == "time_limit") {
      const auto x = v.value<double>();
      if (!x || !(*x > 0.0) || !std::isfinite(*x)) problems.push_back("[search] time_limit: seconds, above 0 (the search starts no design after it)");
      else s.search.time_limit = *x;
    } else if (key == "stagnation_tolerance") {
      const auto x = v.value<double>();
      if (!x || !(*x >= 0.0 && *x < 1.0)) problems.push_back("[search] stagnation_tolerance: a fraction from 0 to below 1");
      else s.search.stagnation_tolerance = *x;
    } else if (key == "screening") {
      const auto n = v.value_exact<std::int64_t>();
      if (!n || *n < 1 || *n > kMaxScreening) {
        problems.push_back(fmt::format("[search] screening: a whole number from 1 (no screening) to {}, the designs drawn for "
                                       "each one run",
                                       kMaxScreening));
      } else {
        s.search.screening = static_cast<int>(*n);
      }
    } else if (key == "seed" && v.is_array()) {
      read_seeds(*v.as_array(), s, problems);
    } else if (key == "population" || key == "generations" || key == "seed" || key == "max_designs" || key == "stagnation") {
      read_search_count(key, v, s, problems);
    } else {
      problems.push_back(fmt::format("[search] {}: unknown; evaluation, algorithm, population, generations, seed, "
                                     "max_designs, stagnation, stagnation_tolerance, time_limit, shortcuts, start, crossover_probability, "
                                     "crossover_eta, mutation_eta, mutation_probability, front_parents, step_mutation or "
                                     "screening", key));
    }
  }
  if (s.search.population < 8 || s.search.population % 4 != 0) {
    problems.push_back(fmt::format("[search] population = {}: a multiple of 4, at least 8 (NSGA-II's pairs)", s.search.population));
  }
  if (s.search.algorithm != Algorithm::nsga2 && s.search.schedule == Schedule::generational) {
    problems.push_back(fmt::format("[search] algorithm = \"{}\": the generational search is pagmo2's NSGA-II; leave out "
                                   "algorithm, or make the search asynchronous", to_string(s.search.algorithm)));
  }
  if (s.search.screening > 1 && s.search.schedule == Schedule::generational) {
    problems.push_back("[search] screening: the generational search is pagmo2's NSGA-II, which runs every design it breeds; "
                       "leave it out, or make the search asynchronous");
  }
  if (s.search.breeding_given && s.search.schedule == Schedule::generational) {
    problems.push_back("[search] front_parents, step_mutation: the generational search is pagmo2's NSGA-II, which breeds "
                       "from its population with its own mutation; leave them out, or make the search asynchronous");
  }
}

// [search] start's spec files, each a design of the space, as genes.
void read_start(Space& s, const std::string& source, std::vector<std::string>& problems) {
  for (const auto& name : s.search.start_files) {
    const auto path = std::filesystem::path(source).parent_path() / name;
    try {
      const auto text = formats::read_file(path);
      const auto sweep = generator::build_sweep(generator::parse_spec_toml(text, path.string()));
      const auto given = toml::parse(text);
      const bool names_stack = given.contains("blocks") || given.contains("materials") || given.contains("rows") ||
                               given.contains("block_rows") || given.contains("radius_ratio");
      if (!sweep.axes.empty()) {
        problems.push_back(fmt::format("[search] start: {}: a design, not a sweep ({} has a list)", path.string(), sweep.axes.front().field));
      } else if (!names_stack) {
        problems.push_back(fmt::format("[search] start: {}: it names no design (none of blocks, materials, rows, block_rows, "
                                       "radius_ratio): give the design's stack",
                                       path.string()));
      } else if (const auto x = s.encode(sweep.base)) {
        s.search.start.push_back(*x);
      } else {
        problems.push_back(fmt::format("[search] start: {}: {} is not one of the space's designs ({} to {} blocks of {}, ratios {}, "
                                       "rows {} to {})", path.string(), describe(sweep.base), s.min_blocks, s.max_blocks,
                                       joined(s.materials), fmt::join(s.radius_ratios, ", "), s.min_rows, s.max_rows));
      }
    } catch (const model::SpecError& e) {
      problems.push_back(fmt::format("[search] start: {}: {}: {}", path.string(), e.issues().front().field, e.issues().front().message));
    } catch (const formats::FormatError& e) {  // its message names the file already
      problems.push_back(fmt::format("[search] start: {}", e.what()));
    } catch (const std::exception& e) {
      problems.push_back(fmt::format("[search] start: {}: {}", path.string(), e.what()));
    }
  }
}

// The least any design in the space can have of each constrained measure: a contradictory space
// (nothing meets its constraints) is refused before anything runs.
void check_not_empty(const Space& s, std::vector<std::string>& problems) {
  const auto lib = s.fixed.material_library();
  std::string lightest = s.materials.front();
  for (const auto& m : s.materials) {
    if (lib.find(m) && lib.find(lightest) && lib.at(m).density < lib.at(lightest).density) lightest = m;
  }
  auto smallest = [&](int ratio, const std::string& material) {
    std::vector<double> x(s.genes(), 0.0);
    x[0] = s.min_blocks;
    const auto r = std::find(s.radius_ratios.begin(), s.radius_ratios.end(), ratio) - s.radius_ratios.begin();
    const auto m = std::find(s.materials.begin(), s.materials.end(), material) - s.materials.begin();
    for (int k = 0; k < s.max_blocks; ++k) {
      x[1 + static_cast<std::size_t>(k)] = static_cast<double>(m);
      if (k + 1 < s.max_blocks) x[1 + static_cast<std::size_t>(s.max_blocks + k)] = static_cast<double>(r);
      x[static_cast<std::size_t>(2 * s.max_blocks + k)] = s.min_rows;
    }
    return s.decode(x);
  };
  const auto fewest = measure(s, smallest(s.radius_ratios.front(), lightest));
  const auto least = measure(s, smallest(s.radius_ratios.back(), lightest));
  if (const auto issues = model::validate(smallest(s.radius_ratios.back(), lightest)); !issues.empty()) {
    problems.push_back(fmt::format("the space's designs are not valid stacks: {}: {}", issues.front().field, issues.front().message));
  }
  const auto& c = s.constraints;
  if (c.max_spheres && fewest.spheres > *c.max_spheres) {
    problems.push_back(fmt::format("[constraints] max_spheres = {}: no design meets it (the fewest any has is {})", *c.max_spheres, fewest.spheres));
  }
  if (c.max_height && least.height > *c.max_height) {
    problems.push_back(fmt::format("[constraints] max_height = {} m: no design meets it (the lowest is {:.4g} m)", *c.max_height, least.height));
  }
  if (c.max_areal_mass && least.areal_mass > *c.max_areal_mass) {
    problems.push_back(fmt::format("[constraints] max_areal_mass = {} kg/m^2: no design meets it (the lightest is {:.4g})",
                                   *c.max_areal_mass, least.areal_mass));
  }
}
}  // namespace

SpaceError::SpaceError(std::vector<std::string> problems)
    : std::runtime_error(problems.empty() ? "bad design space" : problems.front()), problems_(std::move(problems)) {}

std::string ConfirmVariant::label() const {
  std::string out = geometry ? "3D nest" : "";
  if (sides) out += fmt::format("{}{}", out.empty() ? "" : ", ", *sides == model::Boundary::wall ? "side walls" : "free sides");
  return out;
}

std::string ConfirmVariant::suffix() const {
  std::string out = geometry ? "_3d" : "";
  if (sides) out += *sides == model::Boundary::wall ? "_walls" : "_free";
  return out;
}

model::StackSpec ConfirmVariant::applied_to(model::StackSpec spec) const {
  if (geometry) spec.geometry = *geometry;
  if (sides) spec.sides = *sides;
  return spec;
}

std::string ConfirmVariant::problem(const model::StackSpec& fixed) const {
  if (empty()) return "";
  if (geometry && fixed.geometry != model::Geometry::strip) return "geometry: the variant makes a nest of the strip; this space's designs are not strips";
  if (geometry && *geometry == fixed.geometry && (!sides || *sides == fixed.sides)) return "the variant is the designs themselves";
  if (!geometry && sides && *sides == fixed.sides) return "sides: the designs have these sides already";
  if (const auto issues = model::validate(applied_to(fixed)); !issues.empty()) {
    return fmt::format("{}: {}", issues.front().field, issues.front().message);
  }
  return "";
}

model::StackSpec Scenario::applied_to(model::StackSpec spec) const {
  spec.striker_speed = striker_speed;
  spec.striker_radius_ratio = striker_radius_ratio;
  spec.impact_offset = impact_offset;
  if (yield_pressure_factor) spec.yield_pressure_factor = *yield_pressure_factor;
  return spec;
}

std::string_view to_string(Aggregate a) { return a == Aggregate::mean ? "mean" : "worst"; }

Aggregate Space::aggregate_of(std::string_view measure) const {
  const auto it = aggregate.find(std::string(measure));
  return it == aggregate.end() ? Aggregate::worst : it->second;
}

std::string_view to_string(Schedule s) { return s == Schedule::asynchronous ? "asynchronous" : "generational"; }

std::string_view to_string(Algorithm a) {
  switch (a) {
    case Algorithm::nsga2: return "nsga2";
    case Algorithm::nsga3: return "nsga3";
    case Algorithm::sms_emoa: return "sms-emoa";
    case Algorithm::moead: return "moead";
  }
  return "?";
}

std::string Space::digest() const {
  nlohmann::json j;
  j["fixed"] = model::spec_json(fixed);
  j["top_radius"] = top_radius;
  j["blocks"] = {min_blocks, max_blocks};
  j["rows"] = {min_rows, max_rows};
  j["materials"] = materials;
  j["radius_ratio"] = radius_ratios;
  j["constraints"] = {{"max_spheres", constraints.max_spheres.value_or(0)},
                      {"max_height", constraints.max_height.value_or(0.0)},
                      {"max_areal_mass", constraints.max_areal_mass.value_or(0.0)}};
  std::vector<std::string> objs;
  for (const auto o : objectives) objs.emplace_back(to_string(o));
  j["objectives"] = objs;
  if (impulse_window > 0.0) j["impulse_window"] = impulse_window;
  if (cap_durations != model::kBlowEndCapDurations) j["cap_durations"] = cap_durations;
  if (cfc != 0) j["cfc"] = cfc;
  if (protected_mass > 0.0) j["protected_mass"] = protected_mass;
  if (srs_high > 0.0) j["srs"] = {srs_low, srs_high, srs_damping};
  for (const auto& [name, bound] : constraints.max_measures) j["constraints"]["max_" + name] = bound;
  for (const auto& sc : scenarios) {
    auto one = nlohmann::json::array({sc.striker_speed, sc.striker_radius_ratio});
    // A space without offsets or yield factors keeps its key.
    if (sc.impact_offset != 0 || sc.yield_pressure_factor) one.push_back(sc.impact_offset);
    if (sc.yield_pressure_factor) one.push_back(*sc.yield_pressure_factor);
    j["scenarios"].push_back(one);
  }
  for (const auto& [name, a] : aggregate) j["aggregate"][name] = std::string(to_string(a));
  j["population"] = search.population;
  if (search.seeds.size() == 1) j["seed"] = search.seed;
  else j["seed"] = search.seeds;
  // A generational search keeps the digest it had before the asynchronous one existed.
  if (search.schedule != Schedule::generational) j["evaluation"] = std::string(to_string(search.schedule));
  if (search.algorithm != Algorithm::nsga2) j["algorithm"] = std::string(to_string(search.algorithm));
  // Operator settings at their defaults leave the digest as it was before they could be set.
  if (search.crossover_probability != 0.95) j["crossover_probability"] = search.crossover_probability;
  if (search.crossover_eta != 10.0) j["crossover_eta"] = search.crossover_eta;
  if (search.mutation_eta != 50.0) j["mutation_eta"] = search.mutation_eta;
  if (search.mutation_probability) j["mutation_probability"] = *search.mutation_probability;
  if (search.screening != 1) j["screening"] = search.screening;
  if (!search.start_files.empty()) j["start"] = search.start_files;
  return formats::sha256_hex(j.dump());
}

namespace {
// The shock measures inside what the designs' series resolve, judged before anything is written on
// the space's lightest and heaviest designs at each scenario (how finely a run samples the wall's
// force follows its time step and length); a design of another size whose series does not resolve
// them is infeasible, saying why (evaluate.cpp).
void check_shock_resolved(const Space& s, std::vector<std::string>& problems) {
  if (s.cfc == 0 && s.srs_high <= 0.0) return;
  const auto [light, heavy] = s.extreme_designs();
  for (const auto& design : {light, heavy}) {
    for (const auto& one : scenario_specs(s, design)) {
      const auto stack = model::Stack::build(first_run(s, one));
      const auto res = model::resolve(stack);
      const auto why = shock_measures_unresolved(s, res.dt * static_cast<double>(res.series_every));
      if (why.empty()) continue;
      problems.push_back(fmt::format("[measures]: {} for the design {} struck at {:g} m/s: a measure above what the series "
                                     "resolves reads the interpolation between its samples, not the blow; lower srs_band's "
                                     "top or cfc below {:.4g} Hz",
                                     why, describe(design), one.striker_speed,
                                     model::highest_resolved_frequency(res.dt * static_cast<double>(res.series_every))));
      return;
    }
  }
}
}  // namespace

Space parse_space(std::string_view text, const std::string& source, bool stored, bool free_sides_by_default) {
  const auto root = model::parse_toml(text, source);
  std::vector<std::string> problems;
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key != "fixed" && key != "vary" && key != "constraints" && key != "objectives" && key != "search" && key != "measures" &&
        key != "scenarios" && key != "confirm") {
      problems.push_back(fmt::format("{}: unknown; a design space has [fixed], [vary], [constraints], objectives, "
                                     "[measures], [scenarios], [confirm] and [search]", key));
    }
  }
  Space s;
  s.top_radius = kDefaultTopRadius;
  read_fixed(root.get_as<toml::table>("fixed"), source, s, problems, free_sides_by_default);
  read_vary(root.get_as<toml::table>("vary"), s, problems);
  read_objectives(root, s, problems);
  read_measures(root.get_as<toml::table>("measures"), s, problems);
  read_scenarios(root.get_as<toml::table>("scenarios"), root.get_as<toml::table>("fixed"), s, problems);
  read_constraints(root.get_as<toml::table>("constraints"), s, problems);
  require_shock_settings(s, keys_of(root.get_as<toml::table>("measures")), problems);
  read_confirm(root.get_as<toml::table>("confirm"), s, problems);
  read_search(root.get_as<toml::table>("search"), s, problems);
  if (problems.empty()) {
    std::vector<std::string> unsound;
    check_measurable(s, problems, unsound);
    auto& to = stored ? s.warnings : problems;
    to.insert(to.end(), unsound.begin(), unsound.end());
  }
  if (problems.empty()) check_not_empty(s, problems);
  if (problems.empty() && !stored) check_shock_resolved(s, problems);
  if (problems.empty() && !stored) read_start(s, source, problems);
  if (!problems.empty()) throw SpaceError(std::move(problems));
  return s;
}

Geometry measure(const Space& space, const model::StackSpec& spec) {
  Geometry g;
  g.spheres = model::sphere_count(spec);
  // A design granstack refuses as a case (a striker that would dent a soft top block beyond
  // Hertz's range, a stack above the size limits, ...) is one the search may not pick.
  if (const auto issues = model::validate(spec); !issues.empty()) {
    g.violations.push_back(fmt::format("not a valid stack: {}: {}", issues.front().field, issues.front().message));
    g.violation = 1.0;
    return g;
  }
  const auto stack = model::Stack::build(spec);
  // ... and what `generate` refuses of its run (the striker's Hertz overlap, dt, the step count),
  // in every scenario: the design could not be confirmed on LIGGGHTS, so the search may not rank it.
  for (const auto& sc : space.scenarios.empty() ? std::vector<Scenario>{{"", spec.striker_speed, spec.striker_radius_ratio,
                                                                         spec.impact_offset, std::nullopt}}
                                                : space.scenarios) {
    const auto scenario = sc.applied_to(spec);
    auto issues = model::validate(scenario);  // an off-centre blow's striker may reach a side wall
    if (issues.empty()) {
      const auto run = model::Stack::build(scenario);
      issues = model::check_resolution(run, model::resolve(run));
    }
    if (!issues.empty()) {
      g.violations.push_back(fmt::format("generate refuses it{}: {}: {}", sc.label.empty() ? "" : " at " + sc.label,
                                         issues.front().field, issues.front().message));
      g.violation = 1.0;
      return g;
    }
  }
  g.height = stack.lattice_height();
  g.areal_mass = stack.areal_mass();
  const auto& c = space.constraints;
  auto check = [&](const char* name, double value, std::optional<double> bound) {
    if (!bound || value <= *bound) return;
    g.violations.push_back(fmt::format("{} {:.4g} > {:.4g}", name, value, *bound));
    g.violation += (value - *bound) / *bound;
  };
  check("spheres", static_cast<double>(g.spheres),
        c.max_spheres ? std::optional<double>(static_cast<double>(*c.max_spheres)) : std::nullopt);
  check("height", g.height, c.max_height);
  check("areal_mass", g.areal_mass, c.max_areal_mass);
  return g;
}

}  // namespace granstack::design
