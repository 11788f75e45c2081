// granstack reduce, table and plot: cases -> energies, output fractions, fits and figures.
#include "commands.hpp"
#include "progress.hpp"

#include <granstack/formats/error.hpp>
#include <granstack/formats/case.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/postproc/plot.hpp>
#include <granstack/postproc/table.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <memory>
#include <set>

namespace granstack::app {

namespace fs = std::filesystem;

namespace {

long expected_frames(const std::string& dir) {
  try {
    return formats::frames_written(formats::Case::open(dir));
  } catch (const std::exception&) {
    return 0;
  }
}

// Reduces one case, reporting a failure; returns the exit code it makes.
int reduce_one(const std::string& dir, const std::string& label, postproc::ReduceOptions o,
               std::vector<postproc::CaseReduction>& results) {
  if (!o.output_dir.empty()) o.output_dir = (fs::path(o.output_dir) / label).string();
  try {
    results.push_back(postproc::reduce_case(dir, o));
    results.back().case_name = label;
    return kOk;
  } catch (const formats::FormatError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadFile;
  } catch (const postproc::PhysicsError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kPhysics;
  } catch (const fs::filesystem_error& e) {
    fmt::print(stderr, "error: {}: cannot write its results: {}; reduce it into another directory with "
                       "'granstack reduce -o DIR {}'\n", dir, e.code().message(), dir);
    return kIoError;
  } catch (const formats::IoError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kIoError;
  } catch (const os::LockFileError& e) {  // a read-only case: its reduce/ cannot be written
    fmt::print(stderr, "error: {}; reduce it into another directory with 'granstack reduce -o DIR {}'\n", e.what(), dir);
    return kIoError;
  } catch (const std::runtime_error& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kCaseFailed;
  }
}

}  // namespace

int reduce_all(const std::vector<std::string>& dirs, std::vector<postproc::CaseReduction>& results,
               const postproc::ReduceOptions& base) {
  StatusLine status;
  const auto labels = postproc::unique_case_labels(dirs);
  int rc = kOk;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    postproc::ReduceOptions o = base;
    if (status.active()) {
      const long total = expected_frames(dirs[i]);
      const auto t0 = std::chrono::steady_clock::now();
      o.on_frame = [&, total, t0, i](long frames) {
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double frac = total > 0 ? static_cast<double>(frames) / static_cast<double>(total) : 0.0;
        status.show(fmt::format("reduce: case {}/{} {} frame {}/{} ETA {}", i + 1, dirs.size(), labels[i], frames, total,
                                eta(el, frac)));
      };
    }
    const int one = reduce_one(dirs[i], labels[i], o, results);
    status.clear();
    // The most serious code wins: a broken law or a bad file over a case that cannot be reduced.
    if (one != kOk && (rc == kOk || one > rc)) rc = one;
  }
  status.clear();
  return rc;
}

namespace {

struct ReduceFlags {
  std::vector<std::string> cases;
  bool json = false;
  int threads = 0;
  std::string output;
  bool force = false;
};

int reduce(const ReduceFlags& f) {
  const auto dirs = formats::expand_case_dirs(f.cases);
  postproc::ReduceOptions o;
  o.threads = f.threads;
  if (!f.output.empty()) {
    std::vector<std::string> names;
    for (const auto& label : postproc::unique_case_labels(dirs)) names.push_back(label);
    formats::prepare_output_directory(f.output, names, f.force, "granstack reduce -o");
    // --force: each case's results are written anew, none of an earlier reduce left beside them.
    for (const auto& name : names) fs::remove_all(fs::path(f.output) / name);
    o.output_dir = f.output;
  }
  std::vector<postproc::CaseReduction> results;
  const int rc = reduce_all(dirs, results, o);
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
  bool force = false;
};

int table(const TableFlags& f) {
  const std::vector<std::string> names = {"table.md", "table.csv", "fits.csv"};
  if (!f.output.empty()) formats::prepare_output_directory(f.output, names, f.force, "granstack table -o");
  std::vector<postproc::CaseReduction> results;
  postproc::ReduceOptions o;
  o.write_files = false;  // the table needs the results, not the case's reduce/ files
  const int rc = reduce_all(formats::expand_case_dirs(f.cases), results, o);
  if (results.empty()) return rc;
  const auto t = postproc::build_table(results);
  fmt::print("{}", f.json ? postproc::table_json(t).dump() + "\n" : postproc::table_markdown(t));
  if (!f.output.empty()) {
    const fs::path out(f.output);
    // All three or none (a full disk left table.md alone behind).
    formats::write_files_atomically(out, {{names[0], postproc::table_markdown(t)},
                                          {names[1], postproc::table_csv(t)},
                                          {names[2], postproc::fits_csv(t)}});
    fmt::print(stderr, "wrote {0}/table.md, {0}/table.csv and {0}/fits.csv\n", f.output);
  }
  return rc;
}

struct PlotFlags {
  std::vector<std::string> cases;
  std::string output;
  std::string format = "png";
  bool force = false;
};

int plot(const PlotFlags& f) {
  const auto dirs = formats::expand_case_dirs(f.cases);
  std::vector<postproc::CaseReduction> results;
  postproc::ReduceOptions ro;
  ro.write_files = false;
  int rc = reduce_all(dirs, results, ro);
  postproc::PlotOptions o;
  o.format = f.format;
  std::vector<std::string> names;
  for (const auto& r : results) {
    for (const auto& n : postproc::plot_files(postproc::energy_plot_name(r.case_name), o)) names.push_back(n);
    if (r.panel_frames.empty()) continue;
    for (const auto& n : postproc::plot_files(postproc::panel_plot_name(r.case_name), o)) names.push_back(n);
  }
  const auto t = postproc::build_table(results);
  const bool any_fit = std::any_of(t.groups.begin(), t.groups.end(), [](const auto& g) { return g.cases.size() > 1; });
  if (any_fit) {
    for (const auto& n : postproc::plot_files("decay", o)) names.push_back(n);
  }
  if (std::set<std::string>(names.begin(), names.end()).size() != names.size()) {
    throw std::runtime_error("two cases' figures would have the same file name; plot them into separate directories");
  }
  if (results.empty()) return rc;
  formats::prepare_output_directory(f.output, names, f.force, "granstack plot -o");
  for (const auto& r : results) {
    fmt::print("{}\n", postproc::plot_block_energy(r.case_dir, r.case_name, f.output, o));
    if (!r.panel_frames.empty()) fmt::print("{}\n", postproc::plot_panel_energy(r, r.case_name, f.output, o));
  }
  if (any_fit) {
    fmt::print("{}\n", postproc::plot_decay(t, f.output, o));
  } else {
    fmt::print(stderr, "note: no decay figure (decay.{}): no group of these cases has two values of N_B to fit; plot a "
                       "sweep over --blocks for it\n",
               o.format);
  }
  return rc;
}

}  // namespace

Command add_reduce(CLI::App& app) {
  auto f = std::make_shared<ReduceFlags>();
  auto* cmd = app.add_subcommand("reduce", "Per-block energies and output fractions of run cases");
  cmd->add_option("cases", f->cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  cmd->add_flag("--json", f->json, "One JSON object per case per line");
  cmd->add_option("--threads", f->threads, "Threads that parse and analyse the dump frames [one per core]")
      ->check(CLI::Range(1, 256));
  cmd->add_option("-o,--output", f->output,
                  "Write each case's results into DIR/CASE instead of CASE/reduce (e.g. for a read-only case)")
      ->check(output_directory());
  cmd->add_flag("--force", f->force, "With -o: replace results an earlier 'reduce -o' wrote there");
  return {cmd, [f] { return reduce(*f); }};
}

Command add_table(CLI::App& app) {
  auto f = std::make_shared<TableFlags>();
  auto* cmd = app.add_subcommand("table", "Output fraction against N_B per group of cases, with exponential fits");
  cmd->add_option("cases", f->cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", f->output, "Also write table.md, table.csv and fits.csv into this directory")
      ->check(output_directory());
  cmd->add_flag("--json", f->json, "Print the table and fits as one JSON object");
  cmd->add_flag("--force", f->force, "Replace table files an earlier 'table -o' wrote there");
  return {cmd, [f] { return table(*f); }};
}

Command add_plot(CLI::App& app) {
  auto f = std::make_shared<PlotFlags>();
  auto* cmd = app.add_subcommand("plot", "Figures with gnuplot: per-block energy of each case, output fraction against N_B");
  cmd->add_option("cases", f->cases, "Case or sweep directories")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", f->output, "Directory for the images, their data and gnuplot scripts")
      ->check(output_directory())->required();
  cmd->add_option("--format", f->format, "png or svg [png]")->check(CLI::IsMember({"png", "svg"}));
  cmd->add_flag("--force", f->force, "Replace figures an earlier 'plot -o' wrote there");
  return {cmd, [f] { return plot(*f); }};
}

}  // namespace granstack::app
