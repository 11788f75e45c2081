#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/energy.hpp>
#include <granstack/postproc/waves.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace granstack::postproc {

namespace fs = std::filesystem;

std::vector<std::size_t> prominent_peaks(const std::vector<double>& y, double min_prominence) {
  std::vector<std::size_t> out;
  const std::size_t n = y.size();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    if (!(y[i] > y[i - 1] && y[i] >= y[i + 1])) continue;
    // The lowest point on each side before a higher one (or the end).
    double left_min = y[i], right_min = y[i];
    for (std::size_t k = i; k-- > 0 && y[k] <= y[i];) left_min = std::min(left_min, y[k]);
    for (std::size_t k = i + 1; k < n && y[k] <= y[i]; ++k) right_min = std::min(right_min, y[k]);
    if (y[i] - std::max(left_min, right_min) >= min_prominence) out.push_back(i);
  }
  return out;
}

namespace {
// The time of a sampled maximum, refined by the parabola through it and its neighbours.
double refined_peak_time(const std::vector<double>& t, const std::vector<double>& y, std::size_t i) {
  if (i == 0 || i + 1 >= y.size()) return t[i];
  const double a = y[i - 1], b = y[i], c = y[i + 1];
  const double denom = a - 2 * b + c;
  if (denom == 0.0) return t[i];
  const double shift = 0.5 * (a - c) / denom;  // in samples, within (-1/2, 1/2) for a true maximum
  return t[i] + shift * (t[i + 1] - t[i - 1]) / 2.0;
}
}  // namespace

WaveTracker::WaveTracker(const model::Stack& stack, double dt) : stack_(stack), dt_(dt) {
  for (const auto& b : stack.blocks()) {
    Column c;
    for (int i = 1; i <= b.rows; ++i) c.ids.push_back(stack.id_of(b.index, i, b.columns / 2 + 1));
    c.speed.resize(c.ids.size());
    c.overlap.resize(c.ids.size() > 0 ? c.ids.size() - 1 : 0);
    columns_.push_back(std::move(c));
  }
}

void WaveTracker::add(const formats::DumpFrame& f, const FrameView& view) {
  times_.push_back(static_cast<double>(f.step) * dt_);
  const int cx = f.column("x"), cy = f.column("y"), cz = f.column("z");
  const int cvx = f.column("vx"), cvy = f.column("vy"), cvz = f.column("vz");
  for (auto& c : columns_) {
    for (std::size_t r = 0; r < c.ids.size(); ++r) {
      const long row = view.row(c.ids[r]);
      c.speed[r].push_back(std::hypot(f.at(row, cvx), f.at(row, cvy), f.at(row, cvz)));
      if (r + 1 < c.ids.size()) {
        const long below = view.row(c.ids[r + 1]);
        const double d = std::hypot(f.at(row, cx) - f.at(below, cx), f.at(row, cy) - f.at(below, cy),
                                    f.at(row, cz) - f.at(below, cz));
        const double sum = stack_.sphere(c.ids[r]).radius + stack_.sphere(c.ids[r + 1]).radius;
        c.overlap[r].push_back(std::max(0.0, sum - d));
      }
    }
  }
}

std::vector<BlockWaves> analyse_waves(const std::string& case_dir) {
  const auto m = formats::read_manifest(case_dir);
  const auto stack = model::Stack::build(m.spec);
  WaveTracker tracker(stack, model::resolve(stack).dt);
  const auto dump_path = formats::find_dump(case_dir, m.files.dump);
  const auto reader = formats::open_dump(dump_path, m.spec.dump_format == model::DumpFormat::binary, m.files.dump_columns);
  FrameView view(stack, dump_path);
  formats::DumpFrame f;
  for (;;) {
    try {
      if (!reader->next(f)) break;
    } catch (const formats::TruncatedError& truncated) {
      (void)truncated;
      break;  // reduce reports it; the complete frames serve here too
    }
    view.bind(f);
    tracker.add(f, view);
  }
  return tracker.finish(formats::read_series((fs::path(case_dir) / m.files.series).string()));
}

std::vector<BlockWaves> WaveTracker::finish(const formats::Series& series) const {
  const auto& stack = stack_;
  const double dt = dt_;
  const auto& times = times_;
  const auto& columns = columns_;
  const auto lib = stack.spec().material_library();
  const int nb = stack.spec().blocks;
  std::vector<BlockWaves> out(static_cast<std::size_t>(nb));
  for (int k = 1; k <= nb; ++k) {
    auto& w = out[static_cast<std::size_t>(k - 1)];
    w.block = k;
    w.column = stack.block(k).columns / 2 + 1;
    const int ct = series.column(fmt::format("ke_trans_block{}", k)), cr = series.column(fmt::format("ke_rot_block{}", k));
    if (ct < 0 || cr < 0) continue;
    std::vector<double> ke;
    for (const auto& row : series.rows) ke.push_back(row[static_cast<std::size_t>(ct)] + row[static_cast<std::size_t>(cr)]);
    const double top = ke.empty() ? 0.0 : *std::max_element(ke.begin(), ke.end());
    w.peaks = static_cast<int>(prominent_peaks(ke, kPeakProminence * top).size());
  }
  for (const auto& b : stack.blocks()) {
    auto& w = out[static_cast<std::size_t>(b.index - 1)];
    const auto& c = columns[static_cast<std::size_t>(b.index - 1)];
    const auto& mat = lib.at(b.material);
    const double diameter = 2.0 * b.radius;
    // Arrival of the leading maximum at each row: the first local maximum of the sphere's
    // speed reaching half its largest speed. The first and last rows (the interfaces) are left out.
    std::vector<double> depth, arrival;
    std::size_t middle_frame = 0;
    for (std::size_t r = 1; r + 1 < c.ids.size(); ++r) {
      const auto& s = c.speed[r];
      if (s.size() < 3) break;
      const double top = *std::max_element(s.begin(), s.end());
      if (top <= 0.0) continue;
      for (std::size_t i = 1; i + 1 < s.size(); ++i) {
        if (s[i] >= 0.5 * top && s[i] > s[i - 1] && s[i] >= s[i + 1]) {
          depth.push_back(diameter * static_cast<double>(r));
          arrival.push_back(refined_peak_time(times, s, i));
          if (r == c.ids.size() / 2) middle_frame = i;
          break;
        }
      }
    }
    w.rows_used = static_cast<int>(depth.size());
    if (depth.size() >= 3) {
      double mt = 0, mz = 0;
      for (std::size_t k = 0; k < depth.size(); ++k) {
        mt += arrival[k];
        mz += depth[k];
      }
      mt /= static_cast<double>(depth.size());
      mz /= static_cast<double>(depth.size());
      double stt = 0, stz = 0;
      for (std::size_t k = 0; k < depth.size(); ++k) {
        stt += (arrival[k] - mt) * (arrival[k] - mt);
        stz += (arrival[k] - mt) * (depth[k] - mz);
      }
      if (stt > 0 && stz > 0) w.speed = stz / stt;
    }
    if (!w.speed) {
      w.note = fmt::format("the leading maximum was timed at {} rows (3 needed, and a wave moving down): dump more "
                           "often (--dump-every) or use more rows",
                           depth.size());
    }
    // Peak force between vertical neighbours of the column, Hertz's elastic part.
    const auto pair = model::sphere_sphere(mat, b.radius, mat, b.radius);
    double max_overlap = 0.0;
    for (const auto& o : c.overlap) {
      for (const double d : o) max_overlap = std::max(max_overlap, d);
    }
    w.peak_force = 4.0 / 3.0 * pair.y_star * std::sqrt(pair.r_star) * std::pow(max_overlap, 1.5);
    if (w.peak_force > 0.0) {
      w.nesterenko_speed = 0.6802 *
                           std::cbrt(2.0 * mat.youngs_modulus /
                                     (diameter * std::pow(mat.density, 1.5) * (1.0 - std::pow(mat.poisson_ratio, 2)))) *
                           std::pow(w.peak_force, 1.0 / 6.0);
    }
    // The arrival times are only as good as the sampling: at least two frames per row crossing
    // (estimated at Nesterenko's speed, so the check does not depend on the result).
    if (w.speed && w.nesterenko_speed && times.size() > 1) {
      const double frame_interval = times[1] - times[0];
      const double crossing = diameter / *w.nesterenko_speed;
      if (frame_interval > 0.5 * crossing) {
        w.speed.reset();
        w.note = fmt::format("dump frames every {:.3g} us, but the wave crosses a row of block {} in about {:.3g} us: "
                             "dump at least twice per crossing (--dump-every {} or less) to time it",
                             frame_interval * 1e6, b.index, crossing * 1e6,
                             std::max(1L, std::lround(std::floor(0.5 * crossing / dt))));
      }
    }
    // Width when the leading maximum is at the middle row: RMS width of the column's overlaps,
    // as the support of the cos^4 profile with the same RMS width (sigma = 0.1414482 L).
    if (middle_frame > 0 && !c.overlap.empty()) {
      double w0 = 0, w1 = 0, w2 = 0;
      for (std::size_t r = 0; r < c.overlap.size(); ++r) {
        const double o = c.overlap[r][middle_frame];
        w0 += o;
        w1 += o * static_cast<double>(r);
        w2 += o * static_cast<double>(r) * static_cast<double>(r);
      }
      if (w0 > 0) w.width = std::sqrt(std::max(0.0, w2 / w0 - (w1 / w0) * (w1 / w0))) / 0.1414482;
    }
  }
  return out;
}

}  // namespace granstack::postproc
