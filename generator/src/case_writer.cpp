#include <granstack/formats/data_file.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/generator/case_writer.hpp>
#include "deck_parts.hpp"
#include <granstack/model/contact.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/version.hpp>
#include <granstack/model/yield.hpp>
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

// The deck's selection of a series group: by atom type, or by id (a range where consecutive).
std::string group_command(const model::SeriesGroup& g) {
  if (g.atom_type != 0) return fmt::format("group           {} type {}\n", g.name, g.atom_type);
  const bool consecutive = g.ids.back() - g.ids.front() + 1 == static_cast<int>(g.ids.size());
  if (g.ids.size() == 1) return fmt::format("group           {} id {}\n", g.name, g.ids.front());
  if (consecutive) return fmt::format("group           {} id <> {} {}\n", g.name, g.ids.front(), g.ids.back());
  return fmt::format("group           {} id {}\n", g.name, fmt::join(g.ids, " "));
}

namespace {

// thornton_ning's properties (normal_model_thornton_ning.h): the yield ratios that give every
// contact one yield radius (model::thornton_ning_plan, refused where none do), no surface energy,
// and in comments the yield pressure each kind of contact then has against the intended one.
std::string thornton_ning_fixes(const model::Stack& stack, std::size_t types) {
  const auto plan = model::thornton_ning_plan(stack);
  if (!plan.refusal.empty()) throw std::invalid_argument("normal_model = 'thornton_ning': " + plan.refusal);
  std::string out = fmt::format("\nfix             m7 all property/global coefficientYieldRatio peratomtype {}",
                                fmt::join(plan.ratio, " "));
  out += fmt::format("\nfix             m8 all property/global surfaceEnergy peratomtypepair {}", types);
  for (std::size_t k = 0; k < types * types; ++k) out += " 0";
  out += fmt::format("\n# thornton_ning yields where sqrt(R* delta) reaches a_y = {:.6g} m for every contact ({}); a_y "
                     "gives {} its intended p_y. Each kind's p_y = 2 E* a_y / (pi R*), against {:g} Y of its softer "
                     "body:",
                     plan.yield_radius,
                     plan.order_dependent.empty()
                         ? "r * coefficientYieldRatio the same for every type, so which sphere LIGGGHTS calls i does not "
                           "matter"
                         : "but where the type below makes it depend on which sphere LIGGGHTS calls i",
                     plan.honoured, stack.spec().yield_pressure_factor);
  for (const auto& k : plan.kinds) {
    out += fmt::format("\n#   {:<22} {:.4g} Pa (intended {:.4g} Pa)", k.what, k.effective, k.intended);
  }
  if (!plan.order_dependent.empty()) {
    out += fmt::format("\n# Accepted by the spec's order_dependent_yield = 'accept': {}.", plan.order_dependent);
  }
  return out;
}

// The properties the contact model needs beyond hertz/history's (each on a line of its own,
// after the four material fixes): hooke's characteristic velocity (normal_model_hooke.h) and
// a rolling model's friction per type pair (epsd2's and cdt's coefficientRollingFriction).
std::string contact_model_fixes(const model::Stack& stack, const std::vector<std::string>& types) {
  const auto& spec = stack.spec();
  std::string out;
  if (spec.normal_model == model::NormalModel::thornton_ning) out += thornton_ning_fixes(stack, types.size());
  if (spec.normal_model == model::NormalModel::hooke) {
    out += fmt::format("\nfix             m5 all property/global characteristicVelocity scalar {}",
                       spec.contact_model().characteristic_velocity);
  }
  if (spec.rolling_model != model::RollingModel::off) {
    std::string matrix;
    for (const auto& a : types) {
      for (const auto& b : types) matrix += fmt::format(" {}", spec.rolling_friction.get(a, b));
    }
    out += fmt::format("\nfix             m6 all property/global coefficientRollingFriction peratomtypepair {}{}",
                       types.size(), matrix);
  }
  return out;
}

}  // namespace

// The run of a case that stops at the blow's end (model::BlowEnd, docs/physics.md section 7):
// one dump interval at a time (`pre no`: one run's trajectory, bit for bit), the frame judged after
// each by what refsim judges, in the same arithmetic (over the footprint, momentum summed in atom
// order; the output sphere's neighbours and their straight-line courses), and the run ended at the
// frame where the condition has held for the hold, at most res.steps (the cap).
namespace {
// Atom-style variables and a compute `gs_<name>_aim`: whether any other sphere is on course to hit
// sphere `id` (model::threatened, in its arithmetic: d and u the other's position and velocity
// less the sphere's), and, when `touch`, `gs_<name>_touch`: whether any touches it.
std::string on_course_lines(std::string_view name, int id, double radius, const DeckDialect& dialect, bool touch) {
  std::string out = fmt::format(
      "variable        gs_{0}_dx atom x-x[{1}]\nvariable        gs_{0}_dy atom y-y[{1}]\nvariable        gs_{0}_dz atom z-z[{1}]\n"
      "variable        gs_{0}_ux atom vx-vx[{1}]\nvariable        gs_{0}_uy atom vy-vy[{1}]\nvariable        gs_{0}_uz atom vz-vz[{1}]\n"
      "variable        gs_{0}_dd atom v_gs_{0}_dx*v_gs_{0}_dx+v_gs_{0}_dy*v_gs_{0}_dy+v_gs_{0}_dz*v_gs_{0}_dz\n"
      "variable        gs_{0}_du atom v_gs_{0}_dx*v_gs_{0}_ux+v_gs_{0}_dy*v_gs_{0}_uy+v_gs_{0}_dz*v_gs_{0}_uz\n"
      "variable        gs_{0}_uu atom v_gs_{0}_ux*v_gs_{0}_ux+v_gs_{0}_uy*v_gs_{0}_uy+v_gs_{0}_uz*v_gs_{0}_uz\n"
      "# (uu==0) keeps the program from dividing by 0 where du = 0 already rules the sphere out.\n"
      "variable        gs_{0}_aim atom (id!={1})*(v_gs_{0}_du<0)*(v_gs_{0}_dd-v_gs_{0}_du*v_gs_{0}_du/(v_gs_{0}_uu+(v_gs_{0}_uu==0))<({4}+{2})*({4}+{2}))\n"
      "compute         gs_{0}_aim all reduce{3} max v_gs_{0}_aim\n",
      name, id, radius, dialect.reduce_options, dialect.radius);
  if (touch) {
    out += fmt::format(
        "variable        gs_{0}_touch atom (id!={1})*(v_gs_{0}_dd<({4}+{2})*({4}+{2}))\n"
        "compute         gs_{0}_touch all reduce{3} max v_gs_{0}_touch\n",
        name, id, radius, dialect.reduce_options, dialect.radius);
  }
  return out;
}

// Each striker still coming (model::striker_coming): on course to hit a sphere, or, against a
// wall, moving down over the footprint; `gs_coming` counts them. `computes` gains the computes read.
std::string striker_lines(const model::Stack& stack, const DeckDialect& dialect, std::vector<std::string>& computes) {
  std::string out;
  std::string coming = "0";
  const bool wall = stack.spec().bottom == model::Boundary::wall;
  for (int k = 1; k <= stack.strikers(); ++k) {
    const auto name = fmt::format("s{}", k);
    out += on_course_lines(name, k, stack.spheres()[static_cast<std::size_t>(k - 1)].radius, dialect, false);
    computes.push_back(fmt::format("c_gs_{}_aim", name));
    coming += fmt::format("+c_gs_{}_aim", name);
    if (wall) coming += fmt::format("+(vz[{0}]<0)*(abs(x[{0}])<={1})*(abs(y[{0}])<={2})", k, stack.half_width(), stack.half_depth());
  }
  return out + fmt::format("variable        gs_coming equal {}\n", coming);
}
}  // namespace

// The run of a case that stops at the blow's end (model::BlowEnd, docs/physics.md section 7):
// one dump interval at a time (`pre no`: one run's trajectory, bit for bit), the frame judged after
// each by what refsim judges, in the same arithmetic (over the footprint, momentum summed in atom
// order; the output sphere's neighbours and their straight-line courses; the strikers' courses),
// and the run ended at the frame where the condition has held for the hold, at most res.steps (the cap).
std::string blow_end_run(const model::Stack& stack, const model::Resolution& res, const DeckDialect& dialect) {
  std::vector<std::string> computes;
  std::string judge = striker_lines(stack, dialect, computes);
  if (stack.spec().bottom == model::Boundary::wall) {
    const auto over = fmt::format("(abs(x)<={})*(abs(y)<={})", stack.half_width(), stack.half_depth());
    judge += fmt::format(
        "variable        gs_pz atom mass*vz*{0}\n"
        "variable        gs_press atom {0}*(z-{2}<0)\n"
        "compute         gs_pz all reduce{1} sum v_gs_pz\n"
        "compute         gs_press all reduce{1} max v_gs_press\n"
        "variable        gs_holds equal (v_gs_coming==0)&&(c_gs_pz>=0)&&(c_gs_press==0)\n",
        over, dialect.reduce_options, dialect.radius);
    computes.insert(computes.begin(), {"c_gs_pz", "c_gs_press"});
  } else {
    const int o = stack.output_sphere_id();
    judge += on_course_lines("o", o, stack.spheres()[static_cast<std::size_t>(o - 1)].radius, dialect, true);
    judge += "variable        gs_holds equal (v_gs_coming==0)&&(c_gs_o_touch==0)&&(c_gs_o_aim==0)\n";
    computes.insert(computes.begin(), {"c_gs_o_touch", "c_gs_o_aim"});
  }
  judge = dialect.radius_setup + judge;
  if (dialect.judge_in_thermo) {
    judge += fmt::format("thermo_style    custom step atoms ke c_gs_erot cpu {}\n"
                         "thermo_modify   lost error norm no format float %.15g\n",
                         fmt::join(computes, " "));
  }
  model::BlowEnd start(stack, res);
  model::judge_start(start, stack);
  // After each interval (the judge's computes are brought up to date at the end of every run, so
  // the deck reads them between runs; `run ... every` would also change when LIGGGHTS tallies
  // energies, and with it the last bit of some torques): whether the condition holds, the first
  // frame of its current run (-1: none), whether it has held for the hold, whether the cap is ahead.
  const auto judge_frame = fmt::format(
      "variable        gs_h equal $(v_gs_holds)\n"
      "variable        gs_since equal $(v_gs_h*((v_gs_since>=0)*v_gs_since+(v_gs_since<0)*step)-(1-v_gs_h))\n"
      "variable        gs_ended equal $(v_gs_since>=0&&step-v_gs_since>={})\n"
      "variable        gs_more equal $(step<{})\n",
      model::blow_end_hold_steps(res), res.steps);
  return fmt::format(
      "# The run stops at the dump frame where the blow has ended (docs/physics.md section 7), at most\n"
      "# {0} steps: it holds once {1}.\n"
      "# Frame 0, judged by granstack from the stack as generated (LIGGGHTS reads its computes\n"
      "# between runs only after a run of at least one step): the condition {5} there.\n"
      "{2}variable        gs_since equal {6}\n"
      "label           gs_frame\n"
      "run             {4} pre no post no\n"
      "{3}"
      "if              \"${{gs_ended}} == 0 && ${{gs_more}} == 1\" then \"jump SELF gs_frame\"\n"
      "print           \"granstack: the run ended at step $(step), the blow ${{gs_ended}} (1: ended)\"",
      res.steps, start.rule(), judge, judge_frame, res.dump_every, start.holding_since() ? "holds" : "does not hold",
      start.holding_since() ? 0 : -1);
}

// The processor grid: `granstack run --np N` chooses one for the stack and passes it with -var
// (runner/decomposition.hpp); the defaults are for a run by hand, where LIGGGHTS factors the
// ranks over the free directions.
std::string processors_lines(const model::Stack& stack, std::string_view program) {
  const bool strip = !stack.three_d() && !stack.container();
  return fmt::format(
      "# MPI ranks: `granstack run --np N` passes the processor grid it chose for this stack\n"
      "# (-var gs_ranks_x X -var gs_ranks_y Y -var gs_ranks_z Z; run.json's \"decomposition\" gives its loads). Run by\n"
      "# hand, {} chooses: {}.\n"
      "variable        gs_ranks_x index *\n"
      "variable        gs_ranks_y index {}\n"
      "variable        gs_ranks_z index {}\n"
      "processors      ${{gs_ranks_x}} ${{gs_ranks_y}} ${{gs_ranks_z}}",
      program, strip ? "the strip is one sphere thick in y, so x and z are split" : "x and y are split, never z",
      strip ? "1" : "*", strip ? "*" : "1");
}


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
  return f;
}

TemplateVars deck_variables(const model::Stack& stack, const model::Resolution& res, const formats::CaseFiles& files,
                            const std::string& case_name) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  const auto types = stack.type_materials();
  const int nt = static_cast<int>(types.size());
  TemplateVars v;
  v["case_name"] = case_name;
  v["granstack_version"] = std::string(version());
  v["git_commit"] = std::string(git_commit());
  v["data_file"] = files.data;

  // LIGGGHTS refuses Y > 1e9 Pa without hard_particles and Y < 5e6 Pa without soft_particles
  // (global_properties.cpp:361-374).
  bool hard = false, soft = false;
  for (const auto& name : types) {
    const double y = lib.at(name).youngs_modulus;
    hard = hard || y > 1e9;
    soft = soft || y < 5e6;
  }
  std::string hardness;
  if (hard) hardness += "hard_particles  yes\n";
  if (soft) hardness += "soft_particles  yes\n";
  if (hardness.empty()) hardness = "# every Young's modulus is within 5e6..1e9 Pa: no hard/soft_particles needed\n";
  hardness.pop_back();
  v["particle_hardness"] = hardness;

  v["skin"] = fmt::format("{}", res.skin);
  std::string y_list, nu_list, e_matrix, mu_matrix;
  for (const auto& name : types) {
    y_list += fmt::format(" {}", lib.at(name).youngs_modulus);
    nu_list += fmt::format(" {}", lib.at(name).poisson_ratio);
  }
  for (const auto& a : types) {
    for (const auto& b : types) {
      e_matrix += fmt::format(" {}", spec.restitution.get(a, b));
      mu_matrix += fmt::format(" {}", spec.friction.get(a, b));
    }
  }
  v["material_fixes"] = fmt::format(
      "fix             m1 all property/global youngsModulus peratomtype{}\n"
      "fix             m2 all property/global poissonsRatio peratomtype{}\n"
      "fix             m3 all property/global coefficientRestitution peratomtypepair {}{}\n"
      "fix             m4 all property/global coefficientFriction peratomtypepair {}{}{}",
      y_list, nu_list, nt, e_matrix, nt, mu_matrix, contact_model_fixes(stack, types));
  const auto model = spec.contact_model();
  v["contact_model"] = model::liggghts_model_words(model);
  if (const auto why = model::liggghts_refusal(model); !why.empty()) {
    // The deck names the spec's model all the same, and LIGGGHTS stops at it; say why beforehand.
    v["material_fixes"] += fmt::format("\n# LIGGGHTS cannot run this case: {}.", why);
  }

  std::string walls;
  const std::string wall_fix = fmt::format("all wall/gran {} primitive type", model::liggghts_model_words(model));
  for (const auto& w : stack.walls()) {
    // The bottom wall keeps each sphere's force from it, for the series' wall force.
    walls += fmt::format("fix             {} {} {} {}plane {}{}\n", w.name, wall_fix, stack.wall_type(), "xyz"[w.axis],
                         w.position, w.name == model::kBottomWallName ? " store_force yes" : "");
  }
  v["walls"] = walls.empty() ? "# free bottom and free sides: no walls" : walls.substr(0, walls.size() - 1);
  v["gravity"] = spec.gravity > 0.0 ? fmt::format("fix             gravity all gravity {} vector 0 0 -1", spec.gravity)
                                    : std::string("# no gravity");
  v["processors"] = processors_lines(stack, "LIGGGHTS");
  v["contact_distance_factor"] = fmt::format("{}", model::kContactDistanceFactor);
  v["dt"] = fmt::format("{}", res.dt);
  v["steps"] = std::to_string(res.steps);
  v["run"] = res.stops_at_blow_end ? blow_end_run(stack, res, kLiggghtsDialect) : fmt::format("run             {}", res.steps);
  v["thermo_every"] = std::to_string(res.thermo_every);
  v["dump_every"] = std::to_string(res.dump_every);
  v["dump_file"] = files.dump;
  v["dump_columns"] = fmt::format("{}", fmt::join(files.dump_columns, " "));
  // Sorted by id, except per rank: LIGGGHTS 3.8 then writes each rank's own atom count in its
  // header but the atoms the sort handed it (measured: 36 announced, 25 written), so the pieces
  // are left unsorted and the reader maps the ids.
  const std::string sort = spec.dump_files == model::DumpFiles::per_rank ? "" : " sort id";
  if (spec.dump_format == model::DumpFormat::binary) {
    v["dump_modify"] = sort.empty() ? "# binary dump: no dump_modify needed" : "dump_modify     stack" + sort;
  } else {
    std::string format;
    for (const auto& c : files.dump_columns) {
      if (!format.empty()) format += ' ';
      format += c == "id" || c == "type" ? "%d" : "%.17g";
    }
    v["dump_modify"] = fmt::format("dump_modify     stack{} format \"{}\"", sort, format);
  }

  std::string groups;
  const auto series = model::series_groups(stack);
  for (const auto& g : series) groups += group_command(g);
  groups.pop_back();  // the template ends the line
  v["groups"] = groups;

  std::string computes, values;
  for (const auto& g : series) {
    computes += fmt::format("compute         kt{} {} ke\ncompute         kr{} {} erotate/sphere\n", g.tag, g.name, g.tag,
                            g.name);
    values += fmt::format(" $(c_kt{}) $(c_kr{})", g.tag, g.tag);
  }
  if (spec.bottom == model::Boundary::wall) {
    computes += fmt::format("compute         fwb all reduce sum f_force_{}[3]\n", model::kBottomWallName);
    values += " $(c_fwb)";
  }
  v["energy_series"] = fmt::format(
      "{}fix             energy all print {} \"$(step){}\" file {} screen no title \"# {}\"", computes,
      res.series_every, values, files.series, fmt::join(files.series_columns, " "));
  return v;
}

std::string default_deck(const formats::Manifest& m) {
  const auto stack = model::Stack::build(m.spec);
  auto vars = deck_variables(stack, model::resolve(stack), m.files, m.case_name);
  vars["granstack_version"] = m.granstack_version;
  vars["git_commit"] = m.git_commit;
  return render_template(default_deck_template(), vars, "templates/in.granstack.tmpl");
}

bool has_default_deck(const std::string& case_dir, const formats::Manifest& m) {
  return formats::read_file(fs::path(case_dir) / m.files.deck) == default_deck(m);
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
