#include "curves.hpp"

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

Curve reduce_column(const postproc::CaseReduction& r, const std::string& table, const std::string& column) {
  const auto path = (fs::path(reduce_dir(r)) / (table + ".csv")).string();
  std::istringstream in(formats::read_file(path));
  std::string line;
  std::getline(in, line);
  const auto header = split(line);
  const auto time_col = std::find(header.begin(), header.end(), "time_s") - header.begin();
  const auto col = std::find(header.begin(), header.end(), column) - header.begin();
  if (col == static_cast<long>(header.size()) || time_col == static_cast<long>(header.size())) {
    throw std::runtime_error(fmt::format("{}: no column '{}'", path, column));
  }
  Curve c;
  while (std::getline(in, line)) {
    const auto f = split(line);
    double t = 0.0, y = 0.0;
    if (f.size() != header.size() || !formats::parse_double(f[static_cast<std::size_t>(time_col)], t) ||
        !formats::parse_double(f[static_cast<std::size_t>(col)], y)) {
      throw std::runtime_error(fmt::format("{}: a malformed row: {}", path, line.substr(0, 80)));
    }
    c.t.push_back(t);
    c.y.push_back(y);
  }
  return c;
}

Curve series_energy(const postproc::CaseReduction& r, const std::string& group) {
  const auto m = formats::read_manifest(r.case_dir);
  const double dt = model::resolve(model::Stack::build(m.spec)).dt;
  const auto s = formats::read_series((fs::path(r.case_dir) / m.files.series).string());
  const int trans = s.column("ke_trans_" + group), rot = s.column("ke_rot_" + group), step = s.column("step");
  if (trans < 0 || rot < 0 || step < 0) throw std::runtime_error(fmt::format("{}: the series has no '{}'", r.case_dir, group));
  Curve c;
  for (const auto& row : s.rows) {
    c.t.push_back(row[static_cast<std::size_t>(step)] * dt);
    c.y.push_back(row[static_cast<std::size_t>(trans)] + row[static_cast<std::size_t>(rot)]);
  }
  return c;
}

std::vector<Kick> kicks(const Curve& c, double min_gap, double tolerance) {
  std::vector<Kick> out;
  double last_change = -1.0;
  for (std::size_t i = 1; i < c.y.size(); ++i) {
    if (std::fabs(c.y[i] - c.y[i - 1]) <= tolerance) continue;
    if (out.empty() || c.t[i] - last_change >= min_gap) out.push_back({});
    last_change = c.t[i];
    out.back() = {c.t[i], c.y[i]};
  }
  return out;
}

}  // namespace granstack::study
