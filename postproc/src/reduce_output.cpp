// A reduction as the commands present it: its JSON (summary.json, reduce --json) and reduce's
// table, beside table.cpp's tables of many cases.
#include <granstack/formats/case.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/reduce.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <utility>

namespace granstack::postproc {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
// The protected plate's largest acceleration, either way, m/s^2, and when (s): none without a plate.
std::optional<std::pair<double, double>> peak_plate_acceleration(const CaseReduction& r) {
  std::optional<std::pair<double, double>> peak;
  for (std::size_t i = 0; i < r.plate_acceleration.size(); ++i) {
    const double a = std::fabs(r.plate_acceleration[i]);
    if (!peak || a > peak->first) peak = {{a, static_cast<double>(i + 1) * r.wall_force_interval}};
  }
  return peak;
}
json waves_json(const std::vector<BlockWaves>& waves) {
  auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  json out = json::array();
  for (const auto& w : waves) {
    out.push_back({{"block", w.block},
                   {"peaks", w.peaks},
                   {"pulses", w.pulses},
                   {"column", w.column},
                   {"middle_peak_ke_J", w.middle_peak_ke},
                   {"middle_leading_ke_J", w.middle_leading_ke},
                   {"rows_timed", w.rows_used},
                   {"rows_entrance", w.rows_entrance},
                   {"leading_speed", opt(w.speed)},
                   {"peak_force", w.peak_force},
                   {"nesterenko_speed", opt(w.nesterenko_speed)},
                   {"speed_over_nesterenko", w.speed && w.nesterenko_speed ? json(*w.speed / *w.nesterenko_speed)
                                                                            : json(nullptr)},
                   {"width_diameters", opt(w.width)},
                   {"no_solitary_wave", w.no_solitary_wave},
                   {"note", w.note}});
  }
  return out;
}

// What the run shows past its blow's end (a run stops only where courses to a striker through
// other spheres are gone too): the frames that held the end, the wall's largest force there.
template <class Out>
void after_blow_end(Out out, const CaseReduction& r) {
  fmt::format_to(out, "the run went on to t = {:.4g} s (its stop waits on courses to the striker that run through other "
                      "spheres too): the blow's end held at each of the {} frames after it",
                 r.final_time, r.frames_after_blow_end);
  // The series' samples at or after the end (sample k is at (k + 1) intervals).
  const auto from = r.wall_force_interval > 0.0
                        ? static_cast<std::size_t>(std::max(0.0, std::ceil(*r.blow_end_time / r.wall_force_interval - 1.0 - 1e-9)))
                        : r.wall_force.size();
  if (from < r.wall_force.size()) {
    fmt::format_to(out, ", the wall carrying at most {:.3g} N", *std::max_element(r.wall_force.begin() + static_cast<long>(from),
                                                                                  r.wall_force.end()));
  }
  fmt::format_to(out, "\n");
}
}  // namespace

// The run's largest contact pressure over first yield in words, for the terminal.
std::string yield_line(const CaseReduction& r) {
  if (!r.yield_ratio) return fmt::format("contacts not judged for first yield: {}", r.yield_not_judged);
  std::string line = fmt::format("largest contact pressure: {:.4g} Pa, {:.3g} times first yield (1.6 Y), {} at t = {:.4g} s",
                                 r.yield.pressure, *r.yield_ratio, r.yield_contact, r.yield_time);
  if (*r.yield_ratio > 1.0) {
    const auto& law = model::normal_law(r.spec.normal_model);
    line += law.dissipative ? fmt::format(": the Hertz pressure there passes first yield, where the contact law ({}) "
                                          "yields and dissipates instead",
                                          law.name)
                            : std::string(": the contact yields, and the elastic result is a model there");
  }
  if (!r.yield_unjudged_materials.empty()) {
    line += fmt::format(" (no yield strength, not judged against each other: {})", fmt::join(r.yield_unjudged_materials, ", "));
  }
  return line;
}

// The run's largest contact pressure over first yield (model::YieldMeter): where and when, or why
// its contacts are not judged.
json yield_json(const CaseReduction& r) {
  json j = {{"ratio", r.yield_ratio ? json(*r.yield_ratio) : json(nullptr)},
            {"first_yield_pressure_per_yield_strength", model::kFirstYieldPressurePerYield},
            {"unjudged_materials", r.yield_unjudged_materials}};
  if (!r.yield_ratio) {
    j["not_judged"] = r.yield_not_judged;
    return j;
  }
  j["pressure_pa"] = r.yield.pressure;
  j["time_s"] = r.yield_time;
  j["sphere_ids"] = r.yield.id_b == 0 ? json::array({r.yield.id_a}) : json::array({r.yield.id_a, r.yield.id_b});
  j["wall"] = r.yield.id_b == 0 ? json(r.yield.wall) : json(nullptr);
  j["contact"] = r.yield_contact;
  return j;
}

json to_json(const CaseReduction& r) {
  json peaks = json::array(), norm = json::array(), times = json::array();
  for (const auto& b : r.blocks) {
    peaks.push_back(b.peak_ke);
    norm.push_back(b.normalised);
    times.push_back(b.peak_time);
  }
  json j = {{"case", r.case_name},
          {"case_dir", r.case_dir},
          {"engine", r.engine},
          {"deck_additions", r.deck_additions},
          {"blocks", r.spec.blocks},
          {"restitution", r.spec.restitution.value},
          {"friction", r.spec.friction.value},
          {"striker_speed", r.spec.striker_speed},
          {"materials", r.spec.materials},
          {"e_in", r.e_in},
          {"output_fraction", r.output_fraction},
          {"output_fraction_bottom_row", r.output_fraction_bottom_row},
          {"output_fraction_bottom_row_per_sphere", r.output_fraction_bottom_row_per_sphere},
          {"output_fraction_bottom_row_max", r.output_fraction_bottom_row_max},
          {"peak_wall_force", r.peak_wall_force ? nlohmann::json(*r.peak_wall_force) : nlohmann::json(nullptr)},
          {"peak_wall_force_time", r.peak_wall_force ? nlohmann::json(r.peak_wall_force_time) : nlohmann::json(nullptr)},
          {"peak_plate_acceleration", peak_plate_acceleration(r) ? nlohmann::json(peak_plate_acceleration(r)->first) : nlohmann::json(nullptr)},
          {"final_momentum_ratio", r.final_momentum_ratio},
          {"crush_m", r.crush},
          {"penetration_m", r.penetration},
          {"yield", yield_json(r)},
          {"blow_end_time", r.blow_end_time ? nlohmann::json(*r.blow_end_time) : nlohmann::json(nullptr)},
          {"blow_not_ended", r.blow_not_ended},
          {"output_definition", r.output_definition},
          {"output_separated", r.output_separated},
          {"output_peak_fraction", r.output_peak_fraction},
          {"block_peak_ke", peaks},
          {"block_peak_ke_normalised", norm},
          {"block_peak_time", times},
          {"peak_source", r.peak_source},
          {"frames", r.frames},
          {"final_time", r.final_time},
          {"striker_velocity_ratio", r.striker_velocity_ratio},
          {"output_last_change_time", r.output_last_change_time},
          {"energy_drift", r.energy_drift ? json(*r.energy_drift) : json(nullptr)},
          {"dissipated_fraction", r.dissipated_fraction ? json(*r.dissipated_fraction) : json(nullptr)},
          {"plastic_work_fraction", r.plastic_work_fraction ? json(*r.plastic_work_fraction) : json(nullptr)},
          {"block_plastic_work_fraction", r.block_plastic_work_fraction},
          {"striker_plastic_work_fraction",
           r.striker_plastic_work_fraction ? json(*r.striker_plastic_work_fraction) : json(nullptr)},
          {"top_row_sideways_peak", r.top_row_sideways_peak},
          {"top_row_downward_peak", r.top_row_downward_peak},
          {"waves", waves_json(r.waves)},
          {"warnings", r.warnings}};
  if (r.spec.geometry == model::Geometry::panels) {
    j["panel_final_fraction"] = r.panel_final_fraction;
    j["panel_peak_fraction"] = r.panel_peak_fraction;
    j["matrix_final_fraction"] = r.matrix_final_fraction;
    j["matrix_peak_fraction"] = r.matrix_peak_fraction;
    j["leaked_final_fraction"] = r.leaked_final_fraction;
    j["leaked_peak_fraction"] = r.leaked_peak_fraction;
  }
  return j;
}

std::vector<std::string> unique_case_labels(const std::vector<std::string>& dirs) {
  std::vector<std::vector<std::string>> parts;  // each path's components, last first
  for (const auto& d : dirs) {
    std::vector<std::string> p;
    for (const auto& c : fs::weakly_canonical(fs::absolute(d))) {
      if (!c.empty() && c != "/") p.insert(p.begin(), c.string());
    }
    if (p.empty()) p.push_back(d);
    parts.push_back(std::move(p));
  }
  std::vector<std::size_t> depth(dirs.size(), 1);
  auto label = [&](std::size_t i) {
    std::string l;
    for (std::size_t k = std::min(depth[i], parts[i].size()); k-- > 0;) l += (l.empty() ? "" : "/") + parts[i][k];
    return l;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      for (std::size_t j = i + 1; j < dirs.size(); ++j) {
        if (label(i) != label(j)) continue;
        for (const auto k : {i, j}) {
          if (depth[k] < parts[k].size()) {
            ++depth[k];
            changed = true;
          }
        }
      }
    }
  }
  std::vector<std::string> out;
  for (std::size_t i = 0; i < dirs.size(); ++i) out.push_back(label(i));
  return out;
}

std::string format_table(const std::vector<CaseReduction>& rs) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  std::size_t w = 4;
  for (const auto& r : rs) w = std::max(w, r.case_name.size());
  // Containers add what leaked out of the impacted panel (into the matrix and the other panels).
  const bool containers = std::any_of(rs.begin(), rs.end(), [](const auto& r) { return !r.panel_frames.empty(); });
  // Cases run on different engines (or refsim by different rules) say which ran each.
  const bool engines = std::any_of(rs.begin(), rs.end(), [&](const auto& r) { return r.engine != rs.front().engine; });
  std::size_t we = 6;
  for (const auto& r : rs) we = std::max(we, r.engine.size());
  const auto engine_cell = [&](const std::string& text) { return engines ? fmt::format("  {:<{}}", text, we) : std::string(); };
  fmt::format_to(out, "{:<{}}{}  {:>3}  {:>6}  {:>6}  {:>7}  {:>11}  {:>12}  {:>12}  {:>12}{}\n", "case", w, engine_cell("engine"),
                 "N_B", "e", "mu", "v(m/s)", "E_in (J)", "output", "bottom row", "per sphere", containers ? "        leaked" : "");
  for (const auto& r : rs) {
    fmt::format_to(out, "{:<{}}{}  {:>3}  {:>6}  {:>6}  {:>7}  {:>11.5g}  {:>12.6g}  {:>12.6g}  {:>12.6g}{}{}\n", r.case_name, w,
                   engine_cell(r.engine), r.spec.blocks, r.spec.restitution.value, r.spec.friction.value, r.spec.striker_speed,
                   r.e_in, r.output_fraction, r.output_fraction_bottom_row, r.output_fraction_bottom_row_per_sphere,
                   !containers ? "" : r.panel_frames.empty() ? fmt::format("  {:>12}", "-")
                                                             : fmt::format("  {:>12.6g}", r.leaked_final_fraction),
                   r.output_separated || r.spec.bottom == model::Boundary::wall ? "" : "  (not separated)");
  }
  if (rs.size() == 1) {
    const auto& r = rs.front();
    fmt::format_to(out, "\nper block ({}, run on {}; peaks from the {}):\n", r.case_name, r.engine,
                   r.peak_source == "series" ? "in-situ series" : "dump frames");
    fmt::format_to(out, "{:>5}  {:>8}  {:>14}  {:>10}  {:>13}  {:>5}  {:>6}  {:>12}  {:>10}\n", "block", "material",
                   "peak KE (J)", "peak/top", "t_peak (µs)", "peaks", "pulses", "wave (m/s)", "/Nesterenko");
    for (const auto& bp : r.blocks) {
      const BlockWaves* wave =
          static_cast<std::size_t>(bp.block) <= r.waves.size() ? &r.waves[static_cast<std::size_t>(bp.block - 1)] : nullptr;
      const std::string speed = wave && wave->speed ? fmt::format("{:.1f}", *wave->speed) : "-";
      const std::string ratio =
          wave && wave->speed && wave->nesterenko_speed ? fmt::format("{:.3f}", *wave->speed / *wave->nesterenko_speed) : "-";
      fmt::format_to(out, "{:>5}  {:>8}  {:>14.6e}  {:>10.6f}  {:>13.3f}  {:>5}  {:>6}  {:>12}  {:>10}\n", bp.block,
                     r.spec.block_material(bp.block), bp.peak_ke, bp.normalised, bp.peak_time * 1e6, wave ? wave->peaks : 0,
                     wave ? wave->pulses : 0, speed, ratio);
    }
    for (const auto& wave : r.waves) {
      if (!wave.note.empty()) fmt::format_to(out, "note: block {}: {}\n", wave.block, wave.note);
    }
    fmt::format_to(out, "output fraction: {:.6g} ({})\n", r.output_fraction, r.output_definition);
    if (r.blow_end_time) {
      fmt::format_to(out, "the blow ended at t = {:.4g} s (model::BlowEnd): the measures are final\n", *r.blow_end_time);
      if (r.frames_after_blow_end > 0 && r.spec.stop == model::StopRule::blow_end) after_blow_end(out, r);
    } else {
      fmt::format_to(out, "the blow had not ended by the run's end: {}{}\n", r.blow_not_ended,
                     r.spec.gravity > 0.0 ? ""
                     : r.spec.stop == model::StopRule::blow_end
                         ? fmt::format(" (censored at the cap of {:g} automatic durations)", r.spec.cap_durations)
                         : "; generate the case with --stop blow_end to run it until then");
    }
    if (r.peak_wall_force) {
      fmt::format_to(out, "peak bottom-wall force: {:.6g} N at t = {:.4g} s\n", *r.peak_wall_force, r.peak_wall_force_time);
    }
    if (const auto a = peak_plate_acceleration(r)) {
      fmt::format_to(out, "the protected plate ({:g} kg): peak acceleration {:.6g} m/s^2 at t = {:.4g} s (unfiltered, at the "
                     "series' samples)\n", r.spec.plate_mass, a->first, a->second);
    }
    if (r.spec.bottom == model::Boundary::wall) {
      fmt::format_to(out, "crush (the stack's loss of height): {:.6g} m; penetration (the striker below the initial top "
                     "surface): {:.6g} m\n", r.crush, r.penetration);
    }
    fmt::format_to(out, "{}\n", yield_line(r));
    if (r.plastic_work_fraction) {
      fmt::format_to(out, "work dissipated by the contact law: {:.6g} of E_in at the last frame (blocks from the top: "
                     "{:.4g}; strikers: {:.4g}){}\n",
                     *r.plastic_work_fraction, fmt::join(r.block_plastic_work_fraction, ", "), *r.striker_plastic_work_fraction,
                     r.energy_drift ? fmt::format("; kinetic + elastic + dissipated stays within {:.2g} of E_in", *r.energy_drift)
                                    : std::string());
    }
  }
  for (const auto& r : rs) {
    if (r.deck_additions.empty()) continue;
    fmt::format_to(out, "{}the deck of {} added what its spec's deck_additions lists: {}\n", rs.size() == 1 ? "" : "note: ",
                   r.case_name, fmt::join(r.deck_additions, "; "));
  }
  // A container's panels one by one (the blocks' figures sum every panel), for each container case.
  for (const auto& r : rs) {
    if (r.panel_frames.empty()) continue;
    const int hit = r.spec.strikes_every_panel() ? 0 : r.spec.measured_panel();
    fmt::format_to(out, "\nper panel ({}), kinetic energy / E_in at the last frame (peak):\n", r.case_name);
    for (std::size_t p = 0; p < r.panel_final_fraction.size(); ++p) {
      fmt::format_to(out, "  panel {:>2}{}  {:.6g} ({:.6g})\n", p + 1, static_cast<int>(p) + 1 == hit ? " (hit)" : "      ",
                     r.panel_final_fraction[p], r.panel_peak_fraction[p]);
    }
    fmt::format_to(out, "  matrix    {:>6}  {:.6g} ({:.6g})\n", "", r.matrix_final_fraction, r.matrix_peak_fraction);
    fmt::format_to(out, "leaked into the matrix and the other panels: {:.6g} of E_in at the last frame (peak {:.6g})\n",
                   r.leaked_final_fraction, r.leaked_peak_fraction);
  }
  for (const auto& r : rs) {
    for (const auto& warn : r.warnings) fmt::format_to(out, "warning: {}: {}\n", r.case_name, warn);
  }
  return fmt::to_string(b);
}

}  // namespace granstack::postproc
