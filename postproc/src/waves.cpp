#include <granstack/formats/case.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/energy.hpp>
#include <granstack/postproc/least_squares.hpp>
#include <granstack/postproc/waves.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

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


WaveTracker::WaveTracker(const model::Stack& stack, double dt) : stack_(stack), dt_(dt) {
  for (const auto& b : stack.blocks()) {
    Column c;
    for (int i = 1; i <= b.rows; ++i) c.ids.push_back(stack.impact_path_id(b.index, i));
    for (std::size_t r = 0; r + 1 < c.ids.size(); ++r) {
      c.radius_sum.push_back(stack.sphere(c.ids[r]).radius + stack.sphere(c.ids[r + 1]).radius);
    }
    c.offset = samples_per_frame_;
    samples_per_frame_ += c.ids.size() + c.radius_sum.size();
    c.rows.resize(c.ids.size());
    columns_.push_back(std::move(c));
  }
}

void WaveTracker::sample(const formats::DumpFrame& f, const FrameView& view, std::vector<double>& out) const {
  out.resize(samples_per_frame_);
  const int cx = f.column("x"), cy = f.column("y"), cz = f.column("z");
  const int cvx = f.column("vx"), cvy = f.column("vy"), cvz = f.column("vz");
  for (const auto& c : columns_) {
    double* speed = out.data() + c.offset;
    double* overlap = speed + c.ids.size();
    for (std::size_t r = 0; r < c.ids.size(); ++r) {
      const long row = view.row(c.ids[r]);
      speed[r] = std::hypot(f.at(row, cvx), f.at(row, cvy), f.at(row, cvz));
      if (r + 1 < c.ids.size()) {
        const long below = view.row(c.ids[r + 1]);
        const double d = std::hypot(f.at(row, cx) - f.at(below, cx), f.at(row, cy) - f.at(below, cy),
                                    f.at(row, cz) - f.at(below, cz));
        overlap[r] = std::max(0.0, c.radius_sum[r] - d);
      }
    }
  }
}

void WaveTracker::add(const formats::DumpFrame& f, const FrameView& view) {
  sample(f, view, scratch_);
  add(f.step, scratch_);
}

void WaveTracker::add(long step, const std::vector<double>& samples) {
  times_[0] = times_[1];
  times_[1] = times_[2];
  times_[2] = static_cast<double>(step) * dt_;
  frame_times_.push_back(times_[2]);
  if (frames_ == 1) first_interval_ = times_[2] - times_[1];
  for (auto& c : columns_) {
    const double* speed = samples.data() + c.offset;
    const double* overlap = speed + c.ids.size();
    std::swap(c.overlaps_before, c.overlaps);
    c.overlaps.assign(overlap, overlap + c.radius_sum.size());
    for (const double o : c.overlaps) c.max_overlap = std::max(c.max_overlap, o);
    c.middle_energy.push_back(speed[c.rows.size() / 2] * speed[c.rows.size() / 2]);
    for (std::size_t r = 0; r < c.rows.size(); ++r) {
      auto& row = c.rows[r];
      const double s = speed[r];
      // Is the previous frame a local maximum (higher than the one before it, not lower than this)?
      if (frames_ >= 2 && row.last > row.before && row.last >= s &&
          (row.records.empty() || row.last > row.records.back().speed)) {
        Maximum m;
        m.speed = row.last;
        // Its time refined by the parabola through it and its neighbours.
        m.time = times_[1];
        const double denom = row.before - 2 * row.last + s;
        if (denom != 0.0) m.time += 0.5 * (row.before - s) / denom * (times_[2] - times_[0]) / 2.0;
        if (r == c.rows.size() / 2) m.overlaps = c.overlaps_before;
        row.records.push_back(std::move(m));
      }
      row.top = frames_ == 0 ? s : std::max(row.top, s);
      row.before = row.last;
      row.last = s;
    }
  }
  ++frames_;
}

std::vector<BlockWaves> analyse_waves(const std::string& case_dir) {
  const auto c = formats::Case::open(case_dir);
  formats::require_files_as_run(c);
  const auto& m = c.manifest();
  const auto& stack = c.stack();
  WaveTracker tracker(stack, c.derived().dt);
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
  return tracker.finish(formats::read_series(formats::find_dump(case_dir, m.files.series)));
}

// The energy of block k's middle_path_id sphere from the in-situ series (every series_every
// steps), when the series records it; the dump frames would sample a passing wave's peak only a
// few times.
void WaveTracker::middle_sphere(BlockWaves& w, const formats::Series& series, int k) const {
  const int step = series.column("step");
  const int ct = series.column(fmt::format("ke_trans_middle{}", k)), cr = series.column(fmt::format("ke_rot_middle{}", k));
  if (step < 0 || ct < 0 || cr < 0) return;
  for (const auto& row : series.rows) {
    w.middle_time.push_back(row[static_cast<std::size_t>(step)] * dt_);
    w.middle_ke.push_back(row[static_cast<std::size_t>(ct)] + row[static_cast<std::size_t>(cr)]);
  }
}

std::string leading_pulse_rule() {
  return fmt::format("the leading pulse: each interior row's first speed maximum reaching {:g} of the row's largest "
                     "speed, the rows below the entrance (the rows above the deepest one reached no later than a "
                     "shallower row), least squares",
                     kLeadingPulseFraction);
}

// The leading pulse's arrival at each interior row of column `c` (the first and last rows are the
// interfaces): the row's first speed maximum reaching kLeadingPulseFraction of its largest speed.
// The rows above the deepest one whose pulse arrives no later than a shallower row's are
// entrance rows (the block above sets them moving together, out of depth order): left out.
WaveTracker::Arrivals WaveTracker::leading_pulse_arrivals(const Column& c, double diameter, long frames) {
  Arrivals out;
  std::vector<std::pair<std::size_t, const Maximum*>> timed;  // (row, its leading pulse)
  for (std::size_t r = 1; r + 1 < c.ids.size() && frames >= 3; ++r) {
    const auto& row = c.rows[r];
    if (row.top <= 0.0) continue;
    const auto first = std::find_if(row.records.begin(), row.records.end(),
                                    [&](const Maximum& m) { return m.speed >= kLeadingPulseFraction * row.top; });
    if (first != row.records.end()) timed.emplace_back(r, &*first);
  }
  // The first row in depth order: it and every deeper row arrive after every shallower row.
  std::size_t start = 0;
  double latest = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < timed.size(); ++i) {
    if (timed[i].second->time <= latest) start = i + 1;
    latest = std::max(latest, timed[i].second->time);
  }
  out.entrance = start > 0 ? static_cast<int>(timed[start - 1].first) : 0;
  for (std::size_t i = start; i < timed.size(); ++i) {
    const auto& [r, pulse] = timed[i];
    out.depth.push_back(diameter * static_cast<double>(r));
    out.arrival.push_back(pulse->time);
    if (r == c.ids.size() / 2) out.middle_overlaps = &pulse->overlaps;
  }
  return out;
}

std::vector<BlockWaves> WaveTracker::finish(const formats::Series& series) const {
  const auto& stack = stack_;
  const double dt = dt_;
  const auto& columns = columns_;
  const auto lib = stack.spec().material_library();
  const int nb = stack.spec().blocks;
  std::vector<BlockWaves> out(static_cast<std::size_t>(nb));
  for (int k = 1; k <= nb; ++k) {
    auto& w = out[static_cast<std::size_t>(k - 1)];
    w.block = k;
    w.column = stack.impact_column(k);
    const int ct = series.column(fmt::format("ke_trans_block{}", k)), cr = series.column(fmt::format("ke_rot_block{}", k));
    if (ct < 0 || cr < 0) continue;
    std::vector<double> ke;
    for (const auto& row : series.rows) ke.push_back(row[static_cast<std::size_t>(ct)] + row[static_cast<std::size_t>(cr)]);
    const double top = ke.empty() ? 0.0 : *std::max_element(ke.begin(), ke.end());
    w.peaks = static_cast<int>(prominent_peaks(ke, kPeakProminence * top).size());
    middle_sphere(w, series, k);
    if (w.middle_ke.empty()) {  // a case without the series group: the dump frames
      const double half_mass = 0.5 * stack.block(k).sphere_mass;
      w.middle_time = frame_times_;
      for (const double v2 : columns[static_cast<std::size_t>(k - 1)].middle_energy) w.middle_ke.push_back(half_mass * v2);
    }
    if (!w.middle_ke.empty()) {
      const double highest = *std::max_element(w.middle_ke.begin(), w.middle_ke.end());
      const auto pulses = prominent_peaks(w.middle_ke, kPeakProminence * highest);
      w.pulses = static_cast<int>(pulses.size());
      w.middle_peak_ke = highest;
      w.middle_leading_ke = pulses.empty() ? highest : w.middle_ke[pulses.front()];
    }
  }
  for (const auto& b : stack.blocks()) {
    auto& w = out[static_cast<std::size_t>(b.index - 1)];
    const auto& c = columns[static_cast<std::size_t>(b.index - 1)];
    const auto& mat = lib.at(b.material);
    const double diameter = 2.0 * b.radius;
    const auto timed = leading_pulse_arrivals(c, diameter, frames_);
    const auto& depth = timed.depth;
    const auto& arrival = timed.arrival;
    w.rows_entrance = timed.entrance;
    const std::vector<double>* middle_overlaps = timed.middle_overlaps;
    w.rows_used = static_cast<int>(depth.size());
    if (depth.size() >= 3) {
      // depth = speed t + offset, by least squares.
      Eigen::MatrixXd x(static_cast<Eigen::Index>(depth.size()), 2);
      Eigen::VectorXd z(static_cast<Eigen::Index>(depth.size()));
      for (std::size_t k = 0; k < depth.size(); ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        x(i, 0) = arrival[k];
        x(i, 1) = 1.0;
        z(i) = depth[k];
      }
      try {
        const double speed = least_squares(x, z).coefficients(0);
        if (speed > 0) w.speed = speed;
      } catch (const std::invalid_argument&) {  // every row timed at the same instant
      }
    }
    if (!w.speed && timed.entrance > 0 && depth.size() < 3) {
      w.note = fmt::format("the whole block is entrance: the leading pulse reaches its rows out of depth order (the block "
                           "above sets it moving as a whole), {} row(s) in order below them (3 needed)",
                           depth.size());
    } else if (!w.speed) {
      w.note = fmt::format("the leading pulse was timed at {} rows (3 needed, and a wave moving down): dump more "
                           "often (--dump-every) or use more rows",
                           depth.size());
    }
    // Peak force between vertical neighbours of the column, the contact model's elastic part.
    const auto pair = model::sphere_sphere(mat, b.radius, mat, b.radius);
    const auto law = stack.spec().contact_model();
    w.peak_force = model::elastic_normal_force(law, pair, c.max_overlap);
    // Nesterenko's solitary wave is a Hertz chain's: a linear (Hooke) chain has none.
    if (w.peak_force > 0.0 && model::normal_law(law.normal).hertzian) {
      w.nesterenko_speed = 0.6802 *
                           std::cbrt(2.0 * mat.youngs_modulus /
                                     (diameter * std::pow(mat.density, 1.5) * (1.0 - std::pow(mat.poisson_ratio, 2)))) *
                           std::pow(w.peak_force, 1.0 / 6.0);
    }
    // The arrival times are only as good as the sampling: at least two frames per row crossing
    // (estimated at Nesterenko's speed, so the check does not depend on the result).
    if (w.speed && w.nesterenko_speed && frames_ > 1) {
      const double frame_interval = first_interval_;
      const double crossing = diameter / *w.nesterenko_speed;
      if (frame_interval > 0.5 * crossing) {
        w.speed.reset();
        w.note = fmt::format("dump frames every {:.3g} µs, but the wave crosses a row of block {} in about {:.3g} µs: "
                             "dump at least twice per crossing (--dump-every {} or less) to time it",
                             frame_interval * 1e6, b.index, crossing * 1e6,
                             std::max(1L, std::lround(std::floor(0.5 * crossing / dt))));
      }
    }
    w.maximum_speed = w.speed;
    // A leading pulse far from Nesterenko's speed is no solitary wave: no speed is given for it.
    if (w.speed && w.nesterenko_speed) {
      const double ratio = *w.speed / *w.nesterenko_speed;
      if (ratio < kSolitaryWaveBand[0] || ratio > kSolitaryWaveBand[1]) {
        w.note = fmt::format("no solitary wave forms: the leading pulse moves down at {:.4g} m/s, {:.2f} of "
                             "Nesterenko's speed for its peak force (a solitary wave keeps within {:g} to {:g})",
                             *w.speed, ratio, kSolitaryWaveBand[0], kSolitaryWaveBand[1]);
        w.speed.reset();
        w.no_solitary_wave = true;
      }
    }
    // Width when the leading pulse is at the middle row: RMS width of the column's overlaps,
    // as the support of the cos^4 profile with the same RMS width (sigma = 0.1414482 L).
    if (middle_overlaps != nullptr && !middle_overlaps->empty()) {
      double w0 = 0, w1 = 0, w2 = 0;
      for (std::size_t r = 0; r < middle_overlaps->size(); ++r) {
        const double o = (*middle_overlaps)[r];
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
