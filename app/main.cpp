// granstack: the one program, a table of subcommands. Each command lives in its own file in
// app/ and only wires the pipeline's libraries together: generate (generator) -> run (runner)
// -> reduce, table, plot, export (postproc); validate (runner, refsim, postproc); reproduce
// (study); submit, status (cluster: SLURM).
#include "commands.hpp"

#include <granstack/formats/error.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/model/version.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/os/interrupt.hpp>

#include <granstack/cluster/slurm.hpp>
#include <granstack/design/space.hpp>
#include <granstack/design/store.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cerrno>
#include <filesystem>

using namespace granstack;

namespace {

// A file system error as a sentence naming the file, not the C++ library's text.
std::string io_message(const std::filesystem::filesystem_error& e) {
  std::string files = e.path1().string();
  if (!e.path2().empty()) files += fmt::format(" (to {})", e.path2().string());
  const int code = e.code().value();
  const char* hint = code == ENOSPC                    ? ": free some space, or write elsewhere"
                     : code == EACCES || code == EPERM ? ": check its permissions, or write elsewhere"
                     : code == EROFS                   ? ": the file system is read-only; write elsewhere"
                                                       : "";
  return fmt::format("cannot {} {}: {}{}", e.path2().empty() ? "use" : "move", files.empty() ? "a file" : files,
                     e.code().message(), hint);
}

// Every argument that may become a path must be printable: a newline in a case's directory
// name would start a new command in its deck, data file or job script.
std::string control_character_in(const std::vector<std::string>& args) {
  for (std::size_t i = 1; i < args.size(); ++i) {
    for (const unsigned char c : args[i]) {
      if (c < 0x20 || c == 0x7f) {
        return fmt::format("argument {} ({:?}) holds a control character (byte 0x{:02x}): granstack refuses them, since a "
                           "path holding one could start a command in a deck, data file or job script; rename it",
                           i, args[i], c);
      }
    }
  }
  return "";
}

// Every argument must be UTF-8: paths and names are recorded in JSON (manifests, run records,
// sweep indexes), which holds UTF-8 text only.
std::string invalid_utf8_in(const std::vector<std::string>& args) {
  for (std::size_t i = 1; i < args.size(); ++i) {
    const auto& a = args[i];
    for (std::size_t k = 0; k < a.size();) {
      const auto c = static_cast<unsigned char>(a[k]);
      const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e ? 4 : 0;
      bool ok = n != 0 && k + n <= a.size() && !(n == 2 && c < 0xc2);
      for (std::size_t j = 1; ok && j < n; ++j) ok = (static_cast<unsigned char>(a[k + j]) >> 6) == 0x2;
      if (!ok) {
        return fmt::format("argument {} is not valid UTF-8 (byte 0x{:02x} at {}): granstack records paths and names in "
                           "JSON files, which hold UTF-8 text only; rename it",
                           i, c, k);
      }
      k += n;
    }
  }
  return "";
}

// An option the command given does not have, named before CLI11 reads the line: CLI11 would
// take the value after it for a case path ("Directory does not exist: liggghts"). "" when every
// option is the command's.
std::string option_not_of_command(const CLI::App& app, const std::vector<std::string>& args) {
  const CLI::App* cmd = &app;
  std::size_t i = 1;
  for (; i < args.size(); ++i) {
    const auto subs = cmd->get_subcommands([&](const CLI::App* a) { return a->check_name(args[i]); });
    if (subs.empty()) break;
    cmd = subs.front();
  }
  if (cmd == &app) return "";
  std::string path;
  for (const auto* c = cmd; c != nullptr && c != &app; c = c->get_parent()) path = c->get_name() + (path.empty() ? "" : " " + path);
  for (; i < args.size(); ++i) {
    const auto& a = args[i];
    if (a == "--") break;
    double number = 0.0;
    if (a.size() < 2 || a[0] != '-' || CLI::detail::lexical_cast(a, number)) continue;
    const auto name = a[1] == '-' ? a.substr(0, a.find('=')) : a.substr(0, 2);
    const auto* opt = cmd->get_option_no_throw(name);
    if (opt == nullptr) {
      std::vector<std::string> known;
      for (const auto* o : cmd->get_options()) {
        if (!o->get_lnames().empty()) known.push_back("--" + o->get_lnames().front());
      }
      return fmt::format("'{}' is not an option of 'granstack {}' (its options: {}); 'granstack {} --help' says what each "
                         "does",
                         name, path, fmt::join(known, ", "), path);
    }
    if (opt->get_expected_min() > 0 && a.find('=') == std::string::npos && (a[1] == '-' || a.size() == 2)) ++i;
  }
  return "";
}

// Says what went wrong and gives the exit code for it.
int said(const std::string& message, int code) {
  fmt::print(stderr, "error: {}\n", message);
  return code;
}

// Runs a parsed command, turning what it throws into the documented exit codes.
int guarded(const std::function<int()>& run) {
  try {
    return run();
  } catch (const model::SpecError& e) {
    return said(e.what(), app::kBadInput);
  } catch (const design::SpaceError& e) {
    return said(fmt::format("the design space cannot be searched:\n  {}", fmt::join(e.problems(), "\n  ")), app::kBadInput);
  } catch (const design::StoreIoError& e) {
    return said(e.what(), app::kIoError);
  } catch (const design::StoreError& e) {
    return said(e.what(), app::kBadFile);
  } catch (const cluster::SubmitError& e) {
    return said(e.what(), app::kCaseFailed);
  } catch (const formats::OutputError& e) {
    return said(e.what(), app::kExists);
  } catch (const formats::FormatError& e) {
    return said(e.what(), app::kBadFile);
  } catch (const os::LockedError& e) {
    return said(e.what(), app::kCaseFailed);
  } catch (const formats::IoError& e) {
    return said(e.what(), app::kIoError);
  } catch (const os::LockFileError& e) {
    return said(e.what(), app::kIoError);
  } catch (const std::filesystem::filesystem_error& e) {
    return said(io_message(e), app::kIoError);
  } catch (const std::exception& e) {
    return said(e.what(), app::kBadInput);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  CLI::App app{fmt::format("granstack {}: impact decimation in nested granular lattices with LIGGGHTS", version())};
  app.require_subcommand(1);
  app.set_version_flag("--version", fmt::format("granstack {} (commit {})", version(), git_commit()));
  const app::Command commands[] = {app::add_generate(app, args), app::add_run(app),   app::add_adopt(app),
                                   app::add_decompose(app),      app::add_reduce(app),
                                   app::add_table(app),          app::add_plot(app),  app::add_validate(app),
                                   app::add_reproduce(app),      app::add_submit(app), app::add_status(app),
                                   app::add_export(app),         app::add_fields(app),  app::add_design(app)};
  if (const auto why = option_not_of_command(app, args); !why.empty()) return said(why, app::kBadInput);
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
  if (const auto why = control_character_in(args); !why.empty()) return said(why, app::kBadInput);
  if (const auto why = invalid_utf8_in(args); !why.empty()) return said(why, app::kBadInput);
  os::install_interrupt_handlers();
  for (const auto& c : commands) {
    if (c.parser->parsed()) return app::unless_interrupted(guarded(c.run));
  }
  return app::kOk;
}
