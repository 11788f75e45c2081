#pragma once
// Two runs of the same case (LIGGGHTS and refsim) compared the way `granstack validate`
// reports them: every column both engines dump, at every frame, for every sphere; every column
// of the in-situ series at every step; and the output fraction. Nothing is skipped: frames,
// steps, columns or spheres that one run has and the other lacks, and NaN or inf anywhere, make
// the runs disagree.
#include <granstack/postproc/reduce.hpp>

#include <limits>
#include <string>
#include <vector>

namespace granstack::postproc {

// The largest difference of one quantity over the whole comparison, relative to
// max(|a|, |b|, floor): the floor is a physical scale of the quantity (the smallest radius for
// positions, the striker speed for velocities, ...), so a value that should be zero is compared
// too, and never divides by zero.
struct Difference {
  std::string quantity;  // a dump column ("vx"), a series column ("ke_trans_block2"), "output_fraction"
  std::string unit;
  double floor = 0.0;
  double relative = 0.0;  // the largest |a - b| / max(|a|, |b|, floor)
  long step = -1;         // where it is largest
  long atom = -1;         // atom id (dump columns)
  double a = 0.0, b = 0.0;
  long values = 0;        // how many pairs of values were compared
};

// The floor of the output fraction's relative difference (a fraction of E_in; the energies it is
// made of carry round-off near 1e-16 of E_in).
inline constexpr double kOutputFractionFloor = 1e-12;

// validate's default tolerance. Round-off alone, measured on the study's stacks (N_B = 1..4,
// e = 1 and 0.9, mu = 0 and 0.25; and e = 0.9, mu = 0.25 with walls and gravity), every column,
// every frame (bench/results/validate-roundoff-2026-11-23.md): N_B = 1 and 2 differ by at most 3.4e-16,
// frictionless stacks by 4.4e-16; frictional N_B = 3 and 4 by up to 2.6e-10, and 1.6e-9 with
// walls and gravity (spins, N_B = 4), because Coulomb sliding amplifies the round-off of a
// different summation order, by amounts that change by orders of magnitude with dt. The default
// sits 60 times above the largest, and four orders below any modelling difference.
inline constexpr double kDefaultTolerance = 1e-7;

struct RunComparison {
  std::string case_name;
  std::vector<Difference> dump;    // one per dump column both runs write (id and type must be equal)
  std::vector<Difference> series;  // one per series column (the step is the key)
  Difference output_fraction;
  // The protection measures reduce gives each run (docs/physics.md section 7): the crush, the
  // penetration and the yield ratio, and with a bottom wall its peak force. The blow's end must be the same frame: a mismatch if not.
  std::vector<Difference> measures;
  long frames = 0;        // dump frames compared
  long series_rows = 0;   // series rows compared
  // Why the runs cannot be compared value by value (frames, steps, columns, spheres missing on
  // one side, NaN or inf, a run that cannot be reduced): each makes them disagree.
  std::vector<std::string> mismatches;
  // The largest relative difference of all, or infinity when there is a mismatch.
  double worst() const;
  // The quantity with the largest relative difference.
  const Difference& largest() const;
  // validate's verdict against `tolerance`: "" when the runs agree, else why not (the first
  // mismatch: a different stopping frame, frames or columns on one side only; or the largest
  // difference). design confirm gives the same verdict.
  std::string disagreement(double tolerance) const;
};

// Compares two run directories of the same case. Throws formats::FormatError only when a run
// directory is not a case at all; everything about its outputs is reported in the comparison.
RunComparison compare_runs(const std::string& dir_a, const std::string& dir_b);

// The report `validate` prints: per quantity, the largest relative difference, where, and the
// verdict against `tolerance`; then the mismatches.
std::string format_comparison(const RunComparison& c, const std::string& name_a, const std::string& name_b,
                              double tolerance);

}  // namespace granstack::postproc
