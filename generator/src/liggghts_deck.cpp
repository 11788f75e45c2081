// The LIGGGHTS input deck of a case: the variables granstack's template (templates/in.granstack.tmpl)
// is rendered with, and the deck that template gives for a manifest.
#include "deck_parts.hpp"

#include <granstack/formats/files.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/version.hpp>
#include <granstack/model/yield.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace granstack::generator {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPlateMesh = "plate.stl";      // written by the deck's print lines
constexpr const char* kPlateMountFix = "plate_mount";  // the addforce that pushes the plate's body

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

// The plate's travel from its start as the deck reads it: its body's z less the body's start
// (the mount's spring and the series' plate_z; refsim's Plate::body_start follows it).
std::string body_travel(const model::PlateBody& b) { return fmt::format("z[{}]+{}", b.id, -b.start[2]); }

// The protected plate's mesh, body and wall (model::plate_body): the mesh written to plate.stl by
// the deck itself (so that the deck holds all of it), the body created after the data file's
// spheres, the wall acting on the spheres alone.
std::string plate_wall(const model::Stack& stack, const std::string& model_words) {
  const auto b = model::plate_body(stack);
  const auto& spec = stack.spec();
  std::string out = fmt::format(
      "# The protected plate (plate_mass {} kg on a mount of {} N/m and {} N s/m, docs/physics.md section 7): a\n"
      "# mesh of one triangle at z = 0 that moves with its body, atom {}, of the plate's mass, {} m under it,\n"
      "# which fix nve/sphere integrates as every sphere; the wall's force on the spheres and the mount push it\n"
      "# (fix {}, after the integrator). The body is in no group of the spheres', the dump's or the blow's end's.\n",
      spec.plate_mass, spec.mount_stiffness, spec.mount_damping, b.id, -b.start[2], kPlateMountFix);
  const auto line = [&](std::string_view text, bool first) {
    out += fmt::format("print           \"{}\" {} {} screen no\n", text, first ? "file" : "append", kPlateMesh);
  };
  line("solid plate", true);
  line("facet normal 0 0 1", false);
  line("outer loop", false);
  for (const auto& v : b.mesh) line(fmt::format("vertex {} {} {}", v[0], v[1], v[2]), false);
  for (const auto* end : {"endloop", "endfacet", "endsolid plate"}) line(end, false);
  out += fmt::format(
      "create_atoms    {0} single {1} {2} {3} units box\n"
      "set             atom {4} diameter {5}\n"
      "set             atom {4} mass {6}\n"
      "group           plate_body id {4}\n"
      "group           spheres subtract all plate_body\n"
      "fix             plate all mesh/surface file {7} type {0}\n"
      "fix             {8} spheres wall/gran {9} mesh n_meshes 1 meshes plate store_force yes\n",
      b.type, b.start[0], b.start[1], b.start[2], b.id, 2.0 * b.radius, b.mass, kPlateMesh, model::kBottomWallName,
      model_words);
  return out;
}

// The plate's motion, after the integrator (which moves its body first): the mesh at the body's
// velocity, the body pushed by model::plate_force (z: the body's travel from its start).
std::string plate_motion(const model::Stack& stack) {
  if (!stack.spec().has_plate()) return "# no protected plate (plate_mass): the bottom wall, if any, stands still";
  const auto b = model::plate_body(stack);
  const auto& spec = stack.spec();
  return fmt::format(
      "variable        gs_plate_still equal 0\n"
      "variable        gs_plate_vz equal vz[{0}]\n"
      "variable        gs_plate_force equal -c_fwb-{1}*({2})-{3}*vz[{0}]\n"
      "fix             plate_motion all move/mesh mesh plate linear/variable v_gs_plate_still v_gs_plate_still v_gs_plate_vz\n"
      "fix             {4} plate_body addforce 0 0 v_gs_plate_force",
      b.id, spec.mount_stiffness, body_travel(b), spec.mount_damping, kPlateMountFix);
}

}  // namespace

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
    if (w.name == model::kBottomWallName && spec.has_plate()) {
      walls += plate_wall(stack, model::liggghts_model_words(model));
      continue;
    }
    // The bottom wall keeps each sphere's force from it, for the series' wall force.
    walls += fmt::format("fix             {} {} {} {}plane {}{}\n", w.name, wall_fix, stack.wall_type(), "xyz"[w.axis],
                         w.position, w.name == model::kBottomWallName ? " store_force yes" : "");
  }
  v["walls"] = walls.empty() ? "# free bottom and free sides: no walls" : walls.substr(0, walls.size() - 1);
  v["plate"] = plate_motion(stack);
  v["particles"] = spec.has_plate() ? "spheres" : "all";
  v["gravity"] = spec.gravity > 0.0 ? fmt::format("fix             gravity all gravity {} vector 0 0 -1", spec.gravity)
                                    : std::string("# no gravity");
  v["processors"] = processors_lines(stack, "LIGGGHTS");
  v["contact_distance_factor"] = fmt::format("{}", model::kContactDistanceFactor);
  v["dt"] = fmt::format("{}", res.dt);
  v["steps"] = std::to_string(res.steps);
  v["run"] = res.stops_at_blow_end ? blow_end_run(stack, res, kLiggghtsDialect, v["particles"]) : fmt::format("run             {}", res.steps);
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
  if (spec.has_plate()) {  // model::kPlateColumns: the body's travel, velocity and acceleration
    const auto b = model::plate_body(stack);
    values += fmt::format(" $({1}) $(vz[{0}]) $(fz[{0}]/mass[{0}])", b.id, body_travel(b));
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

}  // namespace granstack::generator
