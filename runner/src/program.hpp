#pragma once
// A DEM program of the LAMMPS family (LIGGGHTS, LAMMPS) run as a separate process on a case's
// deck: started (through mpirun for several ranks), its output followed for progress and errors.
// liggghts_engine.cpp holds it; the LIGGGHTS and LAMMPS engines call it.
#include "engine.hpp"

#include <granstack/os/process.hpp>

#include <array>
#include <string>
#include <vector>

namespace granstack::runner {

struct Program {
  std::string name;        // in messages: "LIGGGHTS", "LAMMPS"
  std::string executable;  // the program, as given (--liggghts, --lammps)
  formats::CaseFiles files;  // the deck it reads, the log and screen files it writes
  std::string version_key;   // run.json's key for its banner's version
  std::vector<std::string> extra_arguments;  // after -in DECK -log LOG
  // The deck granstack's own template gives for the case on this program, and its name: what the
  // run's executed commands are held to (deck_check.hpp).
  std::string reference;
  std::string reference_source;
  // The MPI processor grid for several ranks (LiggghtsOptions::grid); zeros: chosen for the case.
  std::array<int, 3> grid{0, 0, 0};
};

// Why the program cannot be started at all (not found; mpirun missing for ranks > 1; no
// temporary directory for Open MPI), or "": `flag` and `package` name the fixes.
std::string program_unavailable(const std::string& name, const std::string& executable, const std::string& flag,
                                const std::string& package, const RunOptions& o);

// The CPUs a case takes on a program run through MPI: its ranks (--np).
EngineRow::Cpus mpi_cpus(const RunOptions& o);

EngineResult run_program(const formats::Case& c, const RunOptions& o, const Program& program,
                         const std::function<void(long)>& on_step, const std::function<void()>& on_started);

}  // namespace granstack::runner
