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

// Columns of CASE/reduce/<table>.csv (block_ke, energy_parts, column_ke, row_ke) against time_s,
// the file read once.
std::vector<Curve> reduce_columns(const postproc::CaseReduction& r, const std::string& table,
                                  const std::vector<std::string>& columns);
Curve reduce_column(const postproc::CaseReduction& r, const std::string& table, const std::string& column);
// Translational plus rotational energy of groups of the in-situ series ("block2", "output_sphere"),
// the file read once.
std::vector<Curve> series_energies(const postproc::CaseReduction& r, const std::vector<std::string>& groups);
Curve series_energy(const postproc::CaseReduction& r, const std::string& group);
// Every block's energy (the series), and every block's impact column's (reduce/column_ke.csv),
// top block first.
std::vector<Curve> block_energies(const postproc::CaseReduction& r);
std::vector<Curve> impact_column_energies(const postproc::CaseReduction& r);

}  // namespace granstack::study
