#pragma once
// A run case's dump as ParaView files (formats/vtk.hpp): per frame one .vtp of its spheres, in
// id order, with each sphere's id, type, block (1 = the top block, 0 = the striker), row,
// column and y-column (as the stack numbers them; 0 for the striker), radius,
// mass, velocity, angular velocity, force, and translational, rotational and total kinetic
// energy (SI units, as the dump); and a .pvd listing the frames with their times (step x dt).
#include <functional>
#include <string>
#include <vector>

namespace granstack::postproc {

// Which of `count` frames a --frames selection picks: "all", or comma-separated frame numbers
// (0 is the first frame, -1 the last) and Python-style slices "first:end:stride" of them
// ("::10", every tenth; "-5:", the last five). Throws std::invalid_argument naming the fault and
// the fix.
std::vector<bool> select_frames(const std::string& selection, long count);

struct ExportOptions {
  std::string output_dir;        // default CASE/paraview
  std::string frames = "all";    // select_frames
  bool force = false;            // replace files of an earlier export (only in granstack's directory)
  std::function<void(long done, long total)> on_frame;  // after each file written
  std::function<bool()> stop;    // asked between frames: true ends the export early
};

struct ExportResult {
  std::string pvd;               // the file to open in ParaView
  long frames = 0;               // written
  long spheres = 0;
  bool complete = true;          // false when stopped early or the dump ended before a selected frame
};

// Throws formats::FormatError for a missing or malformed dump, formats::OutputError when a file
// is in the way, std::invalid_argument for a bad selection.
ExportResult export_case(const std::string& case_dir, const ExportOptions& options);

}  // namespace granstack::postproc
