#pragma once
// Time curves the analyses read from a reduced case: reduce's CSV tables and the in-situ series.
#include <granstack/postproc/reduce.hpp>

#include <string>
#include <vector>

namespace granstack::study {

struct Curve {
  std::vector<double> t;  // s
  std::vector<double> y;
  double max() const;
  // The first prominent maximum (postproc::kPeakProminence), or the maximum when there is none.
  double first_peak() const;
  // The largest value at t <= t_end.
  double max_until(double t_end) const;
};

// A column of CASE/reduce/<table>.csv (block_ke, energy_parts, column_ke, row_ke) against time_s.
Curve reduce_column(const postproc::CaseReduction& r, const std::string& table, const std::string& column);
// Translational plus rotational energy of a group of the in-situ series ("block2", "output_sphere").
Curve series_energy(const postproc::CaseReduction& r, const std::string& group);

// The kicks a sphere receives: stretches of time in which its energy changes (by more than
// `tolerance`), separated by quiet stretches of at least `min_gap` s; for each, when it ends and
// the energy after it.
struct Kick {
  double end = 0.0;
  double after = 0.0;
};
std::vector<Kick> kicks(const Curve& c, double min_gap, double tolerance);

}  // namespace granstack::study
