#pragma once
// Runs a generated case directory with the reference integrator, writing the dump and the
// in-situ series in exactly the formats the generated deck makes LIGGGHTS write, so
// `granstack reduce` treats both engines the same.
#include <granstack/refsim/system.hpp>

#include <functional>
#include <string>

namespace granstack::model {
class Stack;
struct Material;
}
namespace granstack::formats {
struct DataFile;
}

namespace granstack::refsim {

struct RunOptions {
  int threads = 1;
  std::string kernel = "auto";  // Parameters::kernel
  std::function<void(long step, long total)> on_progress;  // called every few hundred steps
  // Format and write the dumps and the series on a thread of their own, beside the steps (the
  // same files): for a core the steps leave free.
  bool write_behind = false;
  bool lammps_rules = false;  // Parameters::lammps_rules: LAMMPS's contact rules, for a cross-check with LAMMPS
};

struct RunStats {
  long steps = 0;                          // run (a case that stops at the blow's end: up to that frame)
  long atoms = 0;
  double loop_seconds = 0.0;               // wall time of the step loop, as LIGGGHTS's "Loop time"
  double particle_steps_per_second = 0.0;
  long neighbor_builds = 0;
  std::string kernel;                      // the kernels that ran: "reference" or a vector instruction set
  bool write_behind = false;               // the outputs were written on a thread of their own
  // Where the time outside the loop went: reading the case and its data file; building the
  // system (its first neighbour list, pair table and sum plan); the setup force call and the
  // step-0 output; closing the files after the loop.
  double read_seconds = 0.0, build_seconds = 0.0, first_output_seconds = 0.0, close_seconds = 0.0;
};

// The parameters a case's deck gives LIGGGHTS: time step, skin, property tables per atom
// type, walls and gravity.
Parameters case_parameters(const model::Stack& stack);
// Property tables for types 1..N made of `materials` (type k = materials[k - 1]), with one
// restitution and one friction coefficient for every pair.
Parameters uniform_parameters(const std::vector<model::Material>& materials, double restitution, double friction,
                              double dt, double skin);

// The particles of a data file, with LIGGGHTS's masses (4/3 pi r^3 rho, r = diameter / 2).
std::vector<Particle> particles_from(const formats::DataFile& data);

// The z force of Parameters::stored_wall (the bottom wall) on all particles in the last force
// call, summed in atom order as the deck's compute reduce sums it: the series' last column
// with a bottom wall (model::kBottomWallForceColumn).
double bottom_wall_force(const System& s);

// Throws formats::FormatError or std::runtime_error for an unreadable case.
RunStats run_case(const std::string& case_dir, const RunOptions& options = {});

}  // namespace granstack::refsim
