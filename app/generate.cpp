// granstack generate: a spec (flags, TOML) -> a case directory or a sweep of them.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/formats/manifest.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/generator/spec_input.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <memory>

namespace granstack::app {

namespace {

struct GenerateFlags {
  std::map<std::string, std::string> values;  // field -> flag text
  std::vector<std::string> restitution_pairs, friction_pairs, rolling_friction_pairs, custom_materials;
  std::string config, output, deck_template;
  bool force = false;
  bool large = false;
};

std::string bytes_text(double b) {
  return b >= 1e9 ? fmt::format("{:.3g} GB", b / 1e9) : b >= 1e6 ? fmt::format("{:.3g} MB", b / 1e6) : fmt::format("{:.3g} kB", b / 1e3);
}

std::string seconds_text(double s) {
  return s >= 3600 ? fmt::format("{:.3g} h", s / 3600) : s >= 60 ? fmt::format("{:.3g} min", s / 60) : fmt::format("{:.2g} s", s);
}

generator::RawSpec raw_spec(CLI::App& cmd, const GenerateFlags& g) {
  generator::RawSpec raw;
  if (!g.config.empty()) raw = generator::read_spec_file(g.config);
  for (const auto& [field, text] : g.values) {
    std::string flag = "--" + field;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (cmd.count(flag) == 0) continue;
    if (field == "gravity" && text.empty()) {  // the bare flag
      raw[field] = {"true"};
    } else if (field == "materials" || generator::is_sweepable(field)) {
      raw[field] = generator::split_list(text);
    } else {
      raw[field] = {text};
    }
  }
  auto append = [&](const char* field, const std::vector<std::string>& items) {
    for (const auto& i : items) raw[field].push_back(i);
  };
  append("restitution_pairs", g.restitution_pairs);
  append("friction_pairs", g.friction_pairs);
  append("rolling_friction_pairs", g.rolling_friction_pairs);
  append("custom_materials", g.custom_materials);
  return raw;
}

int generate(CLI::App& cmd, const GenerateFlags& g, const std::vector<std::string>& argv) {
  const auto sweep = generator::build_sweep(raw_spec(cmd, g));
  const auto cases = generator::expand(sweep);
  generator::GenerateOptions options;
  options.output = g.output;
  options.force = g.force;
  options.allow_large = g.large;
  options.command_line = argv;
  if (!g.deck_template.empty()) options.deck_template_path = g.deck_template;
  StatusLine status;
  if (cases.size() > 1) options.on_progress = [&](long done, long total) { status.count("generate: render and write", done, total); };
  const auto result = generator::generate(cases, options);
  status.clear();
  auto total = generator::total_cost(result.costs);
  total.dump_bytes += total.series_bytes;
  if (result.sweep) {
    fmt::print("wrote a sweep of {} cases in {} ({} spheres and {} steps in all)\n", result.case_dirs.size(), g.output,
               total.spheres, total.steps);
  } else {
    const auto m = formats::read_manifest(result.case_dirs.front().string());
    fmt::print("wrote case {} ({} spheres, dt = {:.4g} s, {} steps, {:.4g} s simulated)\n", g.output, total.spheres,
               m.derived.value("dt", 0.0), total.steps, m.derived.value("duration", 0.0));
  }
  fmt::print("cost: about {} of dumps and series, about {} of LIGGGHTS on one core\n", bytes_text(total.dump_bytes),
             seconds_text(total.liggghts_seconds));
  return kOk;
}

}  // namespace

Command add_generate(CLI::App& app, const std::vector<std::string>& argv) {
  auto g = std::make_shared<GenerateFlags>();
  auto* cmd = app.add_subcommand("generate", "Write a case directory (or a sweep of them) from a spec");
  cmd->add_option("-o,--output", g->output, "Case directory to write (a sweep writes one subdirectory per case)")->required();
  cmd->add_option("--config", g->config, "TOML spec file; flags override its fields")->check(CLI::ExistingFile);
  struct Flag {
    const char* name;
    const char* field;
    const char* help;
  };
  const Flag flags[] = {
      {"--geometry", "geometry",
       "strip (the study's, one sphere thick) | nested3d (cubic blocks, C x C columns) | panels (the study's container) [strip]"},
      {"--panels", "panels", "geometry = panels: strips side by side along y, 2..64"},
      {"--impact-panel", "impact_panel",
       "geometry = panels: the panel the striker hits, 1 = smallest y, or all (a striker on each) [the centre one]"},
      {"--separator", "separator", "geometry = panels: matrix (soft sphere chains) | walls (rigid) | none [matrix]"},
      {"--matrix-material", "matrix_material", "geometry = panels: the matrix's material [teflon]"},
      {"--blocks", "blocks", "Number of blocks N_B (sweepable: 1,2,3,4) [4]"},
      {"--rows", "rows", "Rows (spheres per column) in every block (sweepable) [8]"},
      {"--top-columns", "top_columns", "Columns of the top block, even (sweepable) [2]"},
      {"--bottom-radius", "bottom_radius", "Radius of the bottom block's spheres, m, 1e-6..1 (sweepable) [0.001]"},
      {"--radius-ratio", "radius_ratio", "Radius ratio between consecutive blocks, whole number [2]"},
      {"--materials", "materials", "Material per block, top first, comma list; one name for all [steel]"},
      {"--restitution", "restitution", "Coefficient of restitution e, 0.05 < e <= 1 (sweepable) [1]"},
      {"--friction", "friction", "Coulomb friction coefficient mu, 0..10 (sweepable) [0]"},
      {"--striker-speed", "striker_speed", "Striker speed, m/s (sweepable) [1]"},
      {"--striker-radius-ratio", "striker_radius_ratio", "Striker radius over the top spheres', 1..16 [1]"},
      {"--striker-material", "striker_material", "Material of the striker [the top block's]"},
      {"--bottom", "bottom", "Bottom boundary: free | wall [free]"},
      {"--sides", "sides", "Side boundaries: free | wall [free]"},
      {"--wall-material", "wall_material", "Material of the walls [the bottom block's]"},
      {"--dt", "dt", "Time step, s, at most 1/20 of the shortest contact time, or auto [auto: 1/100]"},
      {"--duration", "duration", "Simulated time, s, or auto [auto]"},
      {"--dump-every", "dump_every", "Steps between dump frames, or auto [auto: the smaller of a 250th of the run and 0.2 t_c]"},
      {"--series-every", "series_every", "Steps between in-situ energy samples, or auto [auto]"},
      {"--dump-format", "dump_format", "Dump format: text | binary [text]"},
      {"--dump-files", "dump_files", "single | per_step (LIGGGHTS '*') | per_rank (LIGGGHTS '%', with --np) [single]"},
      {"--normal-model", "normal_model", "Normal contact: hertz | hooke (a linear spring, Hertz's overlap at the "
                                         "characteristic velocity) [hertz]"},
      {"--tangential-model", "tangential_model", "Tangential contact: history (Coulomb spring) | no_history (viscous) [history]"},
      {"--rolling-model", "rolling_model", "Rolling friction: off | epsd2 (elastic-plastic torque spring) [off]"},
      {"--rolling-friction", "rolling_friction", "Rolling friction coefficient mu_r, 0..1, rolling_model = epsd2 (sweepable) [0]"},
      {"--characteristic-velocity", "characteristic_velocity", "normal_model = hooke: its calibration speed, m/s, or auto [auto: the striker speed]"},
  };
  for (const auto& f : flags) cmd->add_option(f.name, g->values[f.field], f.help);
  cmd->add_option("--gravity", g->values["gravity"], "Gravity along -z, m/s^2, 0..1000; the bare flag means 9.80665 [0]")
      ->expected(0, 1);
  cmd->add_option("--restitution-pair", g->restitution_pairs, "Restitution of one material pair: A:B=E (repeatable)");
  cmd->add_option("--friction-pair", g->friction_pairs, "Friction of one material pair: A:B=MU (repeatable)");
  cmd->add_option("--rolling-friction-pair", g->rolling_friction_pairs, "Rolling friction of one material pair: A:B=MU_R (repeatable)");
  cmd->add_option("--custom-material", g->custom_materials,
                  "Define a material: NAME:DENSITY:YOUNGS_MODULUS:POISSON_RATIO (SI, repeatable; not a built-in name)");
  cmd->add_option("--template", g->deck_template, "Input-deck template to render instead of templates/in.granstack.tmpl")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--force", g->force, "Replace an existing output directory that granstack made (never anything else)");
  cmd->add_flag("--large", g->large, "Generate cases above the size limits (20 GB of outputs, 24 h of LIGGGHTS)");
  return {cmd, [cmd, g, argv] { return generate(*cmd, *g, argv); }};
}

}  // namespace granstack::app
