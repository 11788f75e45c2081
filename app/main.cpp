// granstack: the one program, a table of subcommands. Each command lives in its own file in
// app/ and only wires the pipeline's libraries together: generate (generator) -> run (runner)
// -> reduce, table, plot, export (postproc); validate (runner, refsim, postproc); reproduce
// (study); submit, status (cluster: SLURM).
#include "commands.hpp"

#include <granstack/formats/error.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/model/version.hpp>
#include <granstack/os/interrupt.hpp>

#include <fmt/format.h>

using namespace granstack;

namespace {

// Runs a parsed command, turning what it throws into the documented exit codes.
int guarded(const std::function<int()>& run) {
  try {
    return run();
  } catch (const model::SpecError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return app::kBadInput;
  } catch (const formats::OutputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return app::kExists;
  } catch (const formats::FormatError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return app::kBadFile;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return app::kBadInput;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  CLI::App app{fmt::format("granstack {}: impact decimation in nested granular lattices with LIGGGHTS", version())};
  app.require_subcommand(1);
  app.set_version_flag("--version", fmt::format("granstack {} (commit {})", version(), git_commit()));
  const app::Command commands[] = {app::add_generate(app, args), app::add_run(app),   app::add_reduce(app),
                                   app::add_table(app),          app::add_plot(app),  app::add_validate(app),
                                   app::add_reproduce(app),      app::add_submit(app), app::add_status(app),
                                   app::add_export(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return app::kBadInput;
  }
  os::install_interrupt_handlers();
  for (const auto& c : commands) {
    if (c.parser->parsed()) return app::unless_interrupted(guarded(c.run));
  }
  return app::kOk;
}
