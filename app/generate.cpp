// granstack generate: a spec (flags, TOML) -> a case directory or a sweep of them.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/formats/case.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/generator/spec_input.hpp>
#include <granstack/model/spec_fields.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/model/yield.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <memory>

namespace granstack::app {

namespace {

struct GenerateFlags {
  std::map<std::string, std::string> values;                // field -> flag text
  std::map<std::string, std::vector<std::string>> entries;  // repeatable fields -> their entries
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
  for (const auto& f : model::spec_fields()) {
    if (cmd.count(f.flag) == 0) continue;
    if (const auto entries = g.entries.find(f.name); entries != g.entries.end()) {
      for (const auto& e : entries->second) raw[f.name].push_back(e);
      continue;
    }
    const auto& text = g.values.at(f.name);
    if (!f.bare.empty() && text.empty()) {
      raw[f.name] = {f.bare};
    } else if (f.shape == model::FieldShape::list || f.sweepable()) {
      raw[f.name] = generator::split_list(text);
    } else {
      raw[f.name] = {text};
    }
  }
  return raw;
}

// A field's flag help: its line, whether it sweeps or repeats, and its default.
std::string flag_help(const model::SpecField& f) {
  std::string help = f.help;
  if (f.sweepable()) help += " (sweepable: a comma list)";
  if (f.shape == model::FieldShape::list) help += " (comma list)";
  if (f.shape == model::FieldShape::pair_entries || f.shape == model::FieldShape::material_entries) help += " (repeatable)";
  if (f.default_text != "none") help += fmt::format(" [{}]", f.default_text);
  return help;
}

// thornton_ning's one yield radius, and the yield pressure each kind of contact has at it.
// The protected plate as a user weighs it: its mass against the stack's, and its mount's frequency
// and damping ratio (the plate alone on it).
void print_plate(const model::StackSpec& spec) {
  const auto m = model::plate_mount(model::Stack::build(spec));
  fmt::print("protected plate: {:g} kg, {:.3g} times the stack's mass; ", spec.plate_mass, m.mass_ratio);
  if (m.damping_ratio) {
    fmt::print("on its mount {:.4g} Hz, damping ratio {:.3g} (the plate alone)\n", m.natural_frequency, *m.damping_ratio);
  } else {
    fmt::print("free (no mount)\n");
  }
}

void print_yield_plan(const model::YieldRadiusPlan& plan, const model::StackSpec& spec) {
  fmt::print("thornton_ning: one yield radius a_y = {:.4g} m for every contact ({}), at {} Y of "
             "{}; each kind of contact's yield pressure at it:\n",
             plan.yield_radius,
             plan.order_dependent.empty() ? "order-independent"
                                          : "order-dependent, accepted by order_dependent_yield: " + plan.order_dependent,
             spec.yield_pressure_factor, plan.honoured);
  for (const auto& k : plan.kinds) {
    fmt::print("  {:<22} p_y {:.4g} Pa, intended {:.4g} Pa ({:.3g} times)\n", k.what, k.effective, k.intended,
               k.effective / k.intended);
  }
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
    // What this command wrote (never read back: another generate --force may have replaced it since).
    const auto& d = result.resolutions.front();
    if (d.stops_at_blow_end) {
      fmt::print("wrote case {} ({} spheres, dt = {:.4g} s; it stops at its blow's end, at most {} steps, {:.4g} s "
                 "simulated)\n", g.output, total.spheres, d.dt, total.steps, d.duration);
    } else {
      fmt::print("wrote case {} ({} spheres, dt = {:.4g} s, {} steps, {:.4g} s simulated)\n", g.output, total.spheres, d.dt,
                 total.steps, d.duration);
    }
  }
  if (!result.sweep && cases.front().spec.has_plate()) print_plate(cases.front().spec);
  if (!result.sweep && cases.front().spec.normal_model == model::NormalModel::thornton_ning) {
    print_yield_plan(model::thornton_ning_plan(model::Stack::build(cases.front().spec)), cases.front().spec);
  }
  const bool capped = std::any_of(result.resolutions.begin(), result.resolutions.end(), [](const auto& r) { return r.stops_at_blow_end; });
  fmt::print("cost{}: about {} of dumps and series, about {} of LIGGGHTS on one core\n", capped ? ", if it runs to its cap" : "",
             bytes_text(total.dump_bytes), seconds_text(total.liggghts_seconds));
  return kOk;
}

}  // namespace

Command add_generate(CLI::App& app, const std::vector<std::string>& argv) {
  auto g = std::make_shared<GenerateFlags>();
  auto* cmd = app.add_subcommand("generate", "Write a case directory (or a sweep of them) from a spec");
  cmd->add_option("-o,--output", g->output, "Case directory to write (a sweep writes one subdirectory per case)")
      ->check(output_directory())->required();
  cmd->add_option("--config", g->config, "TOML spec file; flags override its fields")->check(CLI::ExistingFile);
  // Every spec field, from model/spec_fields.hpp.
  for (const auto& f : model::spec_fields()) {
    if (f.shape == model::FieldShape::pair_entries || f.shape == model::FieldShape::material_entries) {
      cmd->add_option(f.flag, g->entries[f.name], flag_help(f));
    } else if (!f.bare.empty()) {
      cmd->add_option(f.flag, g->values[f.name], flag_help(f))->expected(0, 1);
    } else {
      cmd->add_option(f.flag, g->values[f.name], flag_help(f));
    }
  }
  cmd->add_option("--template", g->deck_template, "Input-deck template to render instead of templates/in.granstack.tmpl")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--force", g->force, "Replace an existing output directory that granstack made (never anything else)");
  cmd->add_flag("--large", g->large, "Generate cases above the size limits (20 GB of outputs, 24 h of LIGGGHTS)");
  return {cmd, [cmd, g, argv] { return generate(*cmd, *g, argv); }};
}

}  // namespace granstack::app
