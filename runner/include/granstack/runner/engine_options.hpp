#pragma once
// Each built-in engine's own options, a struct per engine, set through
// RunOptions::own<T>() (runner.hpp) and read only by that engine's file; its row
// (engines.cpp) adds them to `granstack run` as its option group. What every engine shares
// (jobs, ranks, programs) is RunOptions' own.
#include <array>
#include <string>

namespace granstack::runner {

// LIGGGHTS (liggghts_engine.cpp).
struct LiggghtsOptions {
  // The MPI processor grid, ranks along x, y, z; all zero: chosen for each case's stack
  // (choose_decomposition in decomposition.hpp).
  std::array<int, 3> grid{0, 0, 0};
  std::string grid_text;  // --grid as given (run's check parses it against --np)
};

// refsim (refsim_engine.cpp).
struct RefsimOptions {
  int threads = 1;              // threads per case
  std::string kernel = "auto";  // auto, reference or a vector instruction set (refsim::vector_kernels())
  // LAMMPS's contact rules instead of LIGGGHTS's (refsim::Parameters::lammps_rules): the model a
  // case has on LAMMPS, for a cross-check with it.
  bool lammps_rules = false;
};

// LAMMPS (lammps_engine.cpp).
struct LammpsOptions {
  std::string deck_template;  // a template of the user's for the deck; "": templates/in.lammps.tmpl
};

}  // namespace granstack::runner
