// granstack: the one program. It only wires the pipeline's libraries together:
// generate (generator) -> run (runner) -> reduce (postproc).
#include "progress.hpp"

#include <granstack/formats/error.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/generator/spec_input.hpp>
#include <granstack/model/version.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/postproc/plot.hpp>
#include <granstack/postproc/table.hpp>
#include <granstack/postproc/reduce.hpp>
#include <granstack/runner/runner.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <map>

namespace {

// Exit codes (documented in the README).
constexpr int kOk = 0;
constexpr int kCaseFailed = 1;   // a run failed, or a case could not be reduced
constexpr int kBadInput = 2;     // invalid spec, flag or value
constexpr int kExists = 3;       // output exists and --force was not given
constexpr int kBadFile = 4;      // an input file is missing, malformed or inconsistent
constexpr int kDisagree = 5;     // validate: the engines differ by more than the tolerance

using namespace granstack;

struct GenerateFlags {
  std::map<std::string, std::string> values;  // field -> flag text
  std::vector<std::string> restitution_pairs, friction_pairs, custom_materials;
  std::string config, output, deck_template;
  bool force = false;
};

void add_generate(CLI::App& app, GenerateFlags& g) {
  auto* cmd = app.add_subcommand("generate", "Write a case directory (or a sweep of them) from a spec");
  cmd->add_option("-o,--output", g.output, "Case directory to write (a sweep writes one subdirectory per case)")->required();
  cmd->add_option("--config", g.config, "TOML spec file; flags override its fields")->check(CLI::ExistingFile);
  struct Flag {
    const char* name;
    const char* field;
    const char* help;
  };
  const Flag flags[] = {
      {"--blocks", "blocks", "Number of blocks N_B (sweepable: 1,2,3,4) [4]"},
      {"--rows", "rows", "Rows (spheres per column) in every block (sweepable) [8]"},
      {"--top-columns", "top_columns", "Columns of the top block, even (sweepable) [2]"},
      {"--bottom-radius", "bottom_radius", "Radius of the bottom block's spheres, m (sweepable) [0.001]"},
      {"--radius-ratio", "radius_ratio", "Radius ratio between consecutive blocks, whole number [2]"},
      {"--materials", "materials", "Material per block, top first, comma list; one name for all [steel]"},
      {"--restitution", "restitution", "Coefficient of restitution e, 0.05 < e <= 1 (sweepable) [1]"},
      {"--friction", "friction", "Coulomb friction coefficient mu >= 0 (sweepable) [0]"},
      {"--striker-speed", "striker_speed", "Striker speed, m/s (sweepable) [1]"},
      {"--bottom", "bottom", "Bottom boundary: free | wall [free]"},
      {"--sides", "sides", "Side boundaries: free | wall [free]"},
      {"--wall-material", "wall_material", "Material of the walls [the bottom block's]"},
      {"--dt", "dt", "Time step, s, or auto [auto]"},
      {"--duration", "duration", "Simulated time, s, or auto [auto]"},
      {"--dump-every", "dump_every", "Steps between dump frames, or auto [auto: 250 frames, at least every 0.2 t_c]"},
      {"--series-every", "series_every", "Steps between in-situ energy samples, or auto [auto]"},
      {"--dump-format", "dump_format", "Dump format: text | binary [text]"},
      {"--dump-files", "dump_files", "single | per_step (LIGGGHTS '*') | per_rank (LIGGGHTS '%', with --np) [single]"},
  };
  for (const auto& f : flags) cmd->add_option(f.name, g.values[f.field], f.help);
  cmd->add_option("--gravity", g.values["gravity"], "Gravity along -z, m/s^2; the bare flag means 9.80665 [off]")
      ->expected(0, 1);
  cmd->add_option("--restitution-pair", g.restitution_pairs, "Restitution of one material pair: A:B=E (repeatable)");
  cmd->add_option("--friction-pair", g.friction_pairs, "Friction of one material pair: A:B=MU (repeatable)");
  cmd->add_option("--custom-material", g.custom_materials,
                  "Define a material: NAME:DENSITY:YOUNGS_MODULUS:POISSON_RATIO (SI, repeatable)");
  cmd->add_option("--template", g.deck_template, "Input-deck template to render instead of templates/in.granstack.tmpl")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--force", g.force, "Replace an existing output directory");
}

int do_generate(CLI::App& cmd, const GenerateFlags& g, const std::vector<std::string>& argv) {
  generator::RawSpec raw;
  if (!g.config.empty()) raw = generator::read_spec_file(g.config);
  for (const auto& [field, text] : g.values) {
    const auto flag = "--" + [&] {
      std::string f = field;
      std::replace(f.begin(), f.end(), '_', '-');
      return f;
    }();
    if (cmd.count(flag) == 0) continue;
    if (field == "gravity" && text.empty()) {
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
  append("custom_materials", g.custom_materials);

  const auto sweep = generator::build_sweep(raw);
  const auto cases = generator::expand(sweep);
  generator::GenerateOptions options;
  options.output = g.output;
  options.force = g.force;
  options.command_line = argv;
  if (!g.deck_template.empty()) options.deck_template_path = g.deck_template;
  const auto result = generator::generate(cases, options);
  if (result.sweep) {
    fmt::print("wrote a sweep of {} cases in {}\n", result.case_dirs.size(), g.output);
  } else {
    const auto m = formats::read_manifest(result.case_dirs.front().string());
    fmt::print("wrote case {} ({} spheres, dt = {:.4g} s, {} steps, {:.4g} s simulated)\n", g.output,
               m.derived.value("sphere_count", 0), m.derived.value("dt", 0.0), m.derived.value("steps", 0L),
               m.derived.value("duration", 0.0));
  }
  return kOk;
}

struct RunFlags {
  std::vector<std::string> cases;
  std::string engine = "liggghts";
  int jobs = 1;
  int ranks = 1;
  int threads = 1;
  std::string kernel = "auto";
  bool force = false;
  std::string liggghts = "liggghts";
};

int do_run(const RunFlags& f) {
  const auto dirs = formats::expand_case_dirs(f.cases);
  runner::RunOptions o;
  o.jobs = f.jobs;
  o.ranks = f.ranks;
  o.threads = f.threads;
  o.kernel = f.kernel;
  o.force = f.force;
  o.liggghts = f.liggghts;
  o.engine = f.engine == "refsim" ? runner::Engine::refsim : runner::Engine::liggghts;
  if (o.engine == runner::Engine::refsim && f.ranks > 1) {
    fmt::print(stderr, "note: refsim runs in this process and does not use MPI ranks (--np); use --threads {}\n", f.ranks);
  }
  if (o.engine == runner::Engine::liggghts && f.threads > 1) {
    fmt::print(stderr, "note: --threads is for --engine refsim; LIGGGHTS runs in parallel with --np\n");
  }
  app::StatusLine status;
  if (status.active()) {
    o.on_progress = [&status](const runner::ProgressSnapshot& s) {
      std::string line = fmt::format("run: {}/{} cases finished", s.finished, s.total);
      for (const auto& c : s.running) {
        const double frac = c.total_steps > 0 ? static_cast<double>(c.step) / static_cast<double>(c.total_steps) : 0.0;
        line += fmt::format(" | {} step {}/{} ({:.0f}%) ETA {}", c.name, c.step, c.total_steps, 100 * frac,
                            app::eta(c.elapsed, frac));
      }
      status.show(line);
    };
  }
  const auto outcomes = runner::run_cases(dirs, o);
  status.clear();
  int rc = kOk;
  for (const auto& r : outcomes) {
    switch (r.status) {
      case runner::RunStatus::done:
        fmt::print("done     {}  ({:.1f} s wall, loop {:.3g} s, {:.3g} particle-steps/s)\n", r.case_dir, r.wall_seconds,
                   r.loop_seconds, r.particle_steps_per_second);
        break;
      case runner::RunStatus::skipped:
        fmt::print("skipped  {}  ({})\n", r.case_dir, r.message);
        break;
      case runner::RunStatus::failed:
        fmt::print(stderr, "FAILED   {}  {}\n", r.case_dir, r.message);
        rc = kCaseFailed;
        break;
    }
  }
  return rc;
}

struct ReduceFlags {
  std::vector<std::string> cases;
  bool json = false;
  int threads = 0;
};

// Reduces every case, with frame progress on a terminal; a failure is reported and the case
// left out. Returns the exit code so far.
int reduce_all(const std::vector<std::string>& dirs, std::vector<postproc::CaseReduction>& results, int threads = 0) {
  app::StatusLine status;
  int rc = kOk;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    postproc::ReduceOptions o;
    o.threads = threads;
    if (status.active()) {
      long total = 0;
      try {
        const auto m = formats::read_manifest(dirs[i]);
        total = m.derived.value("steps", 0L) / std::max(1L, m.derived.value("dump_every", 1L)) + 1;
      } catch (const std::exception&) {
      }
      const auto t0 = std::chrono::steady_clock::now();
      o.on_frame = [&, total, t0, i](long frames) {
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double frac = total > 0 ? static_cast<double>(frames) / static_cast<double>(total) : 0.0;
        status.show(fmt::format("reduce: case {}/{} {} frame {}/{} ETA {}", i + 1, dirs.size(), dirs[i], frames, total,
                                app::eta(el, frac)));
      };
    }
    try {
      results.push_back(postproc::reduce_case(dirs[i], o));
    } catch (const formats::FormatError& e) {
      status.clear();
      fmt::print(stderr, "error: {}\n", e.what());
      rc = kBadFile;
    } catch (const std::runtime_error& e) {
      status.clear();
      fmt::print(stderr, "error: {}\n", e.what());
      rc = std::max(rc, kCaseFailed);
    }
  }
  status.clear();
  return rc;
}

int do_reduce(const ReduceFlags& f) {
  std::vector<postproc::CaseReduction> results;
  const int rc = reduce_all(formats::expand_case_dirs(f.cases), results, f.threads);
  if (f.json) {
    for (const auto& r : results) fmt::print("{}\n", postproc::to_json(r).dump());
  } else if (!results.empty()) {
    fmt::print("{}", postproc::format_table(results));
  }
  return rc;
}

struct TableFlags {
  std::vector<std::string> cases;
  std::string output;
  bool json = false;
};

int do_table(const TableFlags& f) {
  std::vector<postproc::CaseReduction> results;
  int rc = reduce_all(formats::expand_case_dirs(f.cases), results);
  if (results.empty()) return rc;
  const auto table = postproc::build_table(results);
  if (f.json) {
    fmt::print("{}\n", postproc::table_json(table).dump());
  } else {
    fmt::print("{}", postproc::table_markdown(table));
  }
  if (!f.output.empty()) {
    std::filesystem::create_directories(f.output);
    formats::write_file_atomically(std::filesystem::path(f.output) / "table.md", postproc::table_markdown(table));
    formats::write_file_atomically(std::filesystem::path(f.output) / "table.csv", postproc::table_csv(table));
    formats::write_file_atomically(std::filesystem::path(f.output) / "fits.csv", postproc::fits_csv(table));
    fmt::print(stderr, "wrote {0}/table.md, {0}/table.csv and {0}/fits.csv\n", f.output);
  }
  return rc;
}

struct PlotFlags {
  std::vector<std::string> cases;
  std::string output;
  std::string format = "png";
};

int do_plot(const PlotFlags& f) {
  const auto dirs = formats::expand_case_dirs(f.cases);
  std::vector<postproc::CaseReduction> results;
  int rc = reduce_all(dirs, results);
  postproc::PlotOptions o;
  o.format = f.format;
  for (const auto& r : results) fmt::print("{}\n", postproc::plot_block_energy(r.case_dir, f.output, o));
  if (!results.empty()) {
    const auto table = postproc::build_table(results);
    const bool any_fit = std::any_of(table.groups.begin(), table.groups.end(), [](const auto& g) { return g.cases.size() > 1; });
    if (any_fit) fmt::print("{}\n", postproc::plot_decay(table, f.output, o));
  }
  return rc;
}

struct ValidateFlags {
  std::vector<std::string> cases;
  double tolerance = 1e-6;
  int jobs = 1;
  std::string liggghts = "liggghts";
};

// Runs LIGGGHTS and refsim on copies of each case (CASE/validate/liggghts, CASE/validate/refsim)
// and compares them.
int do_validate(const ValidateFlags& f) {
  const auto dirs = formats::expand_case_dirs(f.cases);
  std::vector<std::string> liggghts_dirs, refsim_dirs;
  for (const auto& d : dirs) {
    liggghts_dirs.push_back(d + "/validate/liggghts");
    refsim_dirs.push_back(d + "/validate/refsim");
    runner::clone_case_inputs(d, liggghts_dirs.back());
    runner::clone_case_inputs(d, refsim_dirs.back());
  }
  runner::RunOptions o;
  o.jobs = f.jobs;
  o.force = true;
  o.liggghts = f.liggghts;
  int rc = kOk;
  for (const auto engine : {runner::Engine::liggghts, runner::Engine::refsim}) {
    o.engine = engine;
    for (const auto& r : runner::run_cases(engine == runner::Engine::liggghts ? liggghts_dirs : refsim_dirs, o)) {
      if (r.status == runner::RunStatus::failed) {
        fmt::print(stderr, "FAILED   {}  {}\n", r.case_dir, r.message);
        rc = kCaseFailed;
      }
    }
  }
  if (rc != kOk) return rc;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const auto c = postproc::compare_runs(liggghts_dirs[i], refsim_dirs[i]);
    fmt::print("{}{}\n", postproc::format_comparison(c, "liggghts", "refsim", f.tolerance),
               c.worst() <= f.tolerance ? "agree" : "DISAGREE");
    if (c.worst() > f.tolerance) rc = kDisagree;
  }
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv, argv + argc);
  CLI::App app{fmt::format("granstack {}: impact decimation in nested granular lattices with LIGGGHTS", version())};
  app.require_subcommand(1);
  app.set_version_flag("--version", fmt::format("granstack {} (commit {})", version(), git_commit()));

  GenerateFlags gen;
  add_generate(app, gen);

  RunFlags run;
  auto* run_cmd = app.add_subcommand("run", "Run LIGGGHTS on case directories (or sweep directories)");
  run_cmd->add_option("cases", run.cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  run_cmd->add_option("-j,--jobs", run.jobs, "Cases run at the same time")->check(CLI::Range(1, 256));
  run_cmd->add_option("--np", run.ranks, "MPI ranks per case (mpirun when > 1)")->check(CLI::Range(1, 4096));
  run_cmd->add_option("--threads", run.threads, "Threads per case for --engine refsim (results do not depend on it)")
      ->check(CLI::Range(1, 256));
  run_cmd->add_option("--kernel", run.kernel,
                      "refsim's contact kernel: auto (AVX-512 where the CPU has it), reference (scalar) or avx512; "
                      "all give the same bits")
      ->check(CLI::IsMember({"auto", "reference", "avx512"}));
  run_cmd->add_option("--liggghts", run.liggghts, "The LIGGGHTS executable");
  run_cmd->add_option("--engine", run.engine, "liggghts (the real DEM code) or refsim (the in-house reference integrator)")
      ->check(CLI::IsMember({"liggghts", "refsim"}));
  run_cmd->add_flag("--force", run.force, "Run cases again even if they finished");

  ReduceFlags red;
  auto* red_cmd = app.add_subcommand("reduce", "Per-block energies and output fractions of run cases");
  red_cmd->add_option("cases", red.cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  red_cmd->add_flag("--json", red.json, "One JSON object per case per line");
  red_cmd->add_option("--threads", red.threads, "Threads that parse and analyse the dump frames (default: one per core)")
      ->check(CLI::Range(1, 256));

  TableFlags tab;
  auto* tab_cmd = app.add_subcommand("table", "Output fraction against N_B per group of cases, with exponential fits");
  tab_cmd->add_option("cases", tab.cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  tab_cmd->add_option("-o,--output", tab.output, "Also write table.md, table.csv and fits.csv into this directory");
  tab_cmd->add_flag("--json", tab.json, "Print the table and fits as one JSON object");

  PlotFlags plt;
  auto* plt_cmd = app.add_subcommand("plot", "Figures with gnuplot: per-block energy of each case, output fraction against N_B");
  plt_cmd->add_option("cases", plt.cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  plt_cmd->add_option("-o,--output", plt.output, "Directory for the images, their data and gnuplot scripts")->required();
  plt_cmd->add_option("--format", plt.format, "png or svg")->check(CLI::IsMember({"png", "svg"}));

  ValidateFlags val;
  auto* val_cmd = app.add_subcommand("validate", "Run LIGGGHTS and refsim on the same cases and compare them");
  val_cmd->add_option("cases", val.cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  val_cmd->add_option("--tolerance", val.tolerance,
                      "Largest accepted relative difference (per-block KE over time / peak, output fraction, "
                      "positions / smallest radius, velocities / striker speed)")
      ->check(CLI::PositiveNumber);
  val_cmd->add_option("-j,--jobs", val.jobs, "Cases run at the same time")->check(CLI::Range(1, 256));
  val_cmd->add_option("--liggghts", val.liggghts, "The LIGGGHTS executable");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kBadInput;
  }

  try {
    if (app.got_subcommand("generate")) return do_generate(*app.get_subcommand("generate"), gen, args);
    if (app.got_subcommand("run")) return do_run(run);
    if (app.got_subcommand("reduce")) return do_reduce(red);
    if (app.got_subcommand("validate")) return do_validate(val);
    if (app.got_subcommand("table")) return do_table(tab);
    if (app.got_subcommand("plot")) return do_plot(plt);
  } catch (const model::SpecError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadInput;
  } catch (const generator::ExistsError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExists;
  } catch (const formats::FormatError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadFile;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadInput;
  }
  return kOk;
}
