#pragma once
// Two runs of the same case (LIGGGHTS and refsim) compared the way `granstack validate`
// reports them: per-block energies over time, the output fraction, and every sphere's state.
#include <granstack/postproc/reduce.hpp>

#include <string>
#include <vector>

namespace granstack::postproc {

struct RunComparison {
  CaseReduction a, b;
  std::vector<double> block_series_difference;  // per block: max over common steps |KE_a - KE_b| / peak_a
  double output_fraction_difference = 0.0;     // |f_a - f_b| / f_a
  double max_position_difference = 0.0;        // m, any sphere, any common dump frame
  double max_velocity_difference = 0.0;        // m/s
  double position_scale = 0.0;                 // m: the smallest radius
  double velocity_scale = 0.0;                 // m/s: the striker speed
  long frames_compared = 0;
  long series_rows_compared = 0;
  // The largest of the relative measures: series / peak, output fraction, |dx| / R_min, |dv| / v.
  double worst() const;
};

// Reduces both run directories (same case) and compares them. Throws like reduce_case, and
// formats::FormatError when the runs do not share their dump steps.
RunComparison compare_runs(const std::string& dir_a, const std::string& dir_b);

std::string format_comparison(const RunComparison& c, const std::string& name_a, const std::string& name_b,
                              double tolerance);

}  // namespace granstack::postproc
