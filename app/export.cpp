// granstack export: a run case's dump as ParaView files (a .vtp per frame and a .pvd series).
#include "commands.hpp"

#include <granstack/postproc/reduce.hpp>
#include "progress.hpp"

#include <granstack/os/case_lock.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/postproc/export.hpp>

#include <fmt/format.h>

#include <memory>

namespace granstack::app {

namespace {

struct ExportFlags {
  std::string case_dir;
  std::string output;
  std::string frames = "all";
  bool force = false;
};

int export_case(const ExportFlags& f) {
  StatusLine status;
  postproc::ExportOptions o;
  o.output_dir = f.output;
  o.frames = f.frames;
  o.force = f.force;
  o.stop = [] { return os::interrupt_signal() != 0; };
  if (status.active()) {
    o.on_frame = [&](long done, long total) { status.show(fmt::format("export: frame {}/{}", done, total)); };
  }
  postproc::ExportResult r;
  try {
    r = postproc::export_case(f.case_dir, o);
  } catch (const postproc::NotRunError& e) {
    status.clear();
    fmt::print(stderr, "error: {}\n", e.what());
    return kCaseFailed;
  } catch (const os::LockFileError& e) {  // a read-only case: its paraview/ cannot be written
    throw os::LockFileError(fmt::format("{}; export it into another directory with 'granstack export -o DIR {}'",
                                        e.what(), f.case_dir));
  }
  status.clear();
  fmt::print("{}: {} frames of {} spheres; open it in ParaView (File > Open), colour by kinetic_energy\n", r.pvd, r.frames,
             r.spheres);
  if (!r.complete && os::interrupt_signal() == 0) {
    fmt::print(stderr, "note: the dump ended before the last frame asked for (a run still going, or cut short); "
                       "the series holds the frames it has\n");
  }
  return kOk;
}

}  // namespace

Command add_export(CLI::App& app) {
  auto f = std::make_shared<ExportFlags>();
  auto* cmd = app.add_subcommand("export", "Write a run case's dump as ParaView files (VTK XML: a .vtp per frame, a .pvd series)");
  cmd->add_option("case", f->case_dir, "A run case directory")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", f->output, "Output directory [CASE/paraview]")->check(output_directory());
  cmd->add_option("--frames", f->frames,
                  "Frames to write: all, frame numbers (0 the first, -1 the last) or slices such as ::10 (every tenth), "
                  "comma-separated [all]");
  cmd->add_flag("--force", f->force, "Replace the files of an earlier export");
  return {cmd, [f] { return export_case(*f); }};
}

}  // namespace granstack::app
