#include "curves.hpp"

#include <granstack/formats/case.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/line_reader.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/postproc/waves.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace granstack::study {

namespace fs = std::filesystem;

double Curve::max() const { return y.empty() ? 0.0 : *std::max_element(y.begin(), y.end()); }

double Curve::first_peak() const {
  const auto peaks = postproc::prominent_peaks(y, postproc::kPeakProminence * max());
  return peaks.empty() ? max() : y[peaks.front()];
}

double Curve::max_until(double t_end) const {
  double m = 0.0;
  for (std::size_t i = 0; i < t.size() && t[i] <= t_end; ++i) m = std::max(m, y[i]);
  return m;
}

namespace {
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(line);
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

std::string reduce_dir(const postproc::CaseReduction& r) { return fs::path(r.csv_path).parent_path().string(); }
}  // namespace

std::vector<Curve> reduce_columns(const postproc::CaseReduction& r, const std::string& table,
                                  const std::vector<std::string>& columns) {
  const auto path = (fs::path(reduce_dir(r)) / (table + ".csv")).string();
  std::istringstream in(formats::read_file(path));
  std::string line;
  std::getline(in, line);
  const auto header = split(line);
  auto index = [&](const std::string& name) {
    const auto at = static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
    if (at == header.size()) throw std::runtime_error(fmt::format("{}: no column '{}'", path, name));
    return at;
  };
  const auto time_col = index("time_s");
  std::vector<std::size_t> cols;
  for (const auto& c : columns) cols.push_back(index(c));
  std::vector<Curve> curves(columns.size());
  while (std::getline(in, line)) {
    const auto f = split(line);
    double t = 0.0;
    if (f.size() != header.size() || !formats::parse_double(f[time_col], t)) {
      throw std::runtime_error(fmt::format("{}: a malformed row: {}", path, line.substr(0, 80)));
    }
    for (std::size_t k = 0; k < cols.size(); ++k) {
      double y = 0.0;
      if (!formats::parse_double(f[cols[k]], y)) {
        throw std::runtime_error(fmt::format("{}: a malformed row: {}", path, line.substr(0, 80)));
      }
      curves[k].t.push_back(t);
      curves[k].y.push_back(y);
    }
  }
  return curves;
}

Curve reduce_column(const postproc::CaseReduction& r, const std::string& table, const std::string& column) {
  return reduce_columns(r, table, {column}).front();
}

std::vector<Curve> series_energies(const postproc::CaseReduction& r, const std::vector<std::string>& groups) {
  const auto c = formats::Case::open(r.case_dir);
  const double dt = c.derived().dt;
  const auto s = formats::read_series(formats::find_dump(c.dir(), c.files().series));
  const int step = s.column("step");
  std::vector<std::pair<int, int>> cols;  // translational, rotational
  for (const auto& g : groups) {
    cols.emplace_back(s.column("ke_trans_" + g), s.column("ke_rot_" + g));
    if (cols.back().first < 0 || cols.back().second < 0 || step < 0) {
      throw std::runtime_error(fmt::format("{}: the series has no '{}'", r.case_dir, g));
    }
  }
  std::vector<Curve> curves(groups.size());
  for (const auto& row : s.rows) {
    const double t = row[static_cast<std::size_t>(step)] * dt;
    for (std::size_t k = 0; k < cols.size(); ++k) {
      curves[k].t.push_back(t);
      curves[k].y.push_back(row[static_cast<std::size_t>(cols[k].first)] + row[static_cast<std::size_t>(cols[k].second)]);
    }
  }
  return curves;
}

Curve series_energy(const postproc::CaseReduction& r, const std::string& group) { return series_energies(r, {group}).front(); }

std::vector<Curve> block_energies(const postproc::CaseReduction& r) {
  std::vector<std::string> groups;
  for (int k = 1; k <= r.spec.blocks; ++k) groups.push_back(fmt::format("block{}", k));
  return series_energies(r, groups);
}

std::vector<Curve> impact_column_energies(const postproc::CaseReduction& r) {
  const auto stack = model::Stack::build(r.spec);
  std::vector<std::string> columns;
  for (int k = 1; k <= r.spec.blocks; ++k) columns.push_back(fmt::format("ke_block{}_column{}_J", k, stack.impact_column(k)));
  return reduce_columns(r, "column_ke", columns);
}

}  // namespace granstack::study
