#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/postproc/energy.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

namespace granstack::postproc {

namespace fs = std::filesystem;

double RunComparison::worst() const {
  double w = output_fraction_difference;
  for (const double d : block_series_difference) w = std::max(w, d);
  if (position_scale > 0) w = std::max(w, max_position_difference / position_scale);
  if (velocity_scale > 0) w = std::max(w, max_velocity_difference / velocity_scale);
  return w;
}

namespace {
// Per-block KE (translational + rotational) by step, from the in-situ series.
std::map<long, std::vector<double>> block_series(const std::string& dir, int blocks) {
  const auto m = formats::read_manifest(dir);
  const auto s = formats::read_series((fs::path(dir) / m.files.series).string());
  std::vector<std::pair<int, int>> cols;
  for (int k = 1; k <= blocks; ++k) {
    cols.emplace_back(s.column(fmt::format("ke_trans_block{}", k)), s.column(fmt::format("ke_rot_block{}", k)));
  }
  std::map<long, std::vector<double>> out;
  for (const auto& row : s.rows) {
    std::vector<double> ke;
    for (const auto& [t, r] : cols) {
      ke.push_back(t >= 0 && r >= 0 ? row[static_cast<std::size_t>(t)] + row[static_cast<std::size_t>(r)] : 0.0);
    }
    out[static_cast<long>(row[0])] = std::move(ke);
  }
  return out;
}
}  // namespace

RunComparison compare_runs(const std::string& dir_a, const std::string& dir_b) {
  RunComparison c;
  c.a = reduce_case(dir_a);
  c.b = reduce_case(dir_b);
  const auto& spec = c.a.spec;
  const int nb = spec.blocks;
  c.output_fraction_difference =
      c.a.output_fraction != 0.0 ? std::fabs(c.a.output_fraction - c.b.output_fraction) / std::fabs(c.a.output_fraction)
                                 : std::fabs(c.b.output_fraction);

  const auto sa = block_series(dir_a, nb);
  const auto sb = block_series(dir_b, nb);
  c.block_series_difference.assign(static_cast<std::size_t>(nb), 0.0);
  for (const auto& [step, ka] : sa) {
    const auto it = sb.find(step);
    if (it == sb.end()) continue;
    ++c.series_rows_compared;
    for (std::size_t k = 0; k < ka.size(); ++k) {
      const double peak = c.a.blocks[k].peak_ke;
      if (peak > 0) c.block_series_difference[k] = std::max(c.block_series_difference[k], std::fabs(ka[k] - it->second[k]) / peak);
    }
  }

  const auto stack = model::Stack::build(spec);
  c.position_scale = stack.blocks().back().radius;
  c.velocity_scale = spec.striker_speed;
  const auto ma = formats::read_manifest(dir_a);
  const auto mb = formats::read_manifest(dir_b);
  const auto ra = formats::open_dump(formats::find_dump(dir_a, ma.files.dump),
                                     ma.spec.dump_format == model::DumpFormat::binary, ma.files.dump_columns);
  const auto rb = formats::open_dump(formats::find_dump(dir_b, mb.files.dump),
                                     mb.spec.dump_format == model::DumpFormat::binary, mb.files.dump_columns);
  formats::DumpFrame fa, fb;
  FrameView va(stack, ra->path()), vb(stack, rb->path());
  while (ra->next(fa)) {
    if (!rb->next(fb)) break;
    if (fa.step != fb.step) {
      throw formats::FormatError(rb->path(), 0, fmt::format("dump frame at step {} where {} has step {}: the runs do not "
                                                            "dump the same steps",
                                                            fb.step, ra->path(), fa.step));
    }
    va.bind(fa);
    vb.bind(fb);
    const int xa[3] = {fa.column("x"), fa.column("y"), fa.column("z")};
    const int xb[3] = {fb.column("x"), fb.column("y"), fb.column("z")};
    const int ua[3] = {fa.column("vx"), fa.column("vy"), fa.column("vz")};
    const int ub[3] = {fb.column("vx"), fb.column("vy"), fb.column("vz")};
    for (const auto& s : stack.spheres()) {
      const long rowa = va.row(s.id), rowb = vb.row(s.id);
      for (int d = 0; d < 3; ++d) {
        c.max_position_difference = std::max(c.max_position_difference, std::fabs(fa.at(rowa, xa[d]) - fb.at(rowb, xb[d])));
        c.max_velocity_difference = std::max(c.max_velocity_difference, std::fabs(fa.at(rowa, ua[d]) - fb.at(rowb, ub[d])));
      }
    }
    ++c.frames_compared;
  }
  return c;
}

std::string format_comparison(const RunComparison& c, const std::string& name_a, const std::string& name_b,
                              double tolerance) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  auto mark = [&](double rel) { return rel <= tolerance ? "ok" : "OVER"; };
  fmt::format_to(out, "{}: {} against {} ({} dump frames, {} series samples compared; tolerance {:g})\n",
                 c.a.case_name, name_a, name_b, c.frames_compared, c.series_rows_compared, tolerance);
  fmt::format_to(out, "{:>5}  {:>16}  {:>16}  {:>22}\n", "block", fmt::format("peak KE {} (J)", name_a),
                 fmt::format("peak KE {} (J)", name_b), "max |dKE(t)| / peak");
  for (std::size_t k = 0; k < c.block_series_difference.size(); ++k) {
    fmt::format_to(out, "{:>5}  {:>16.10e}  {:>16.10e}  {:>18.3e} {}\n", k + 1, c.a.blocks[k].peak_ke, c.b.blocks[k].peak_ke,
                   c.block_series_difference[k], mark(c.block_series_difference[k]));
  }
  fmt::format_to(out, "output fraction: {:.15g} against {:.15g}, relative difference {:.3e} {}\n", c.a.output_fraction,
                 c.b.output_fraction, c.output_fraction_difference, mark(c.output_fraction_difference));
  const double px = c.position_scale > 0 ? c.max_position_difference / c.position_scale : 0.0;
  const double pv = c.velocity_scale > 0 ? c.max_velocity_difference / c.velocity_scale : 0.0;
  fmt::format_to(out, "largest position difference: {:.3e} m ({:.3e} of the smallest radius) {}\n",
                 c.max_position_difference, px, mark(px));
  fmt::format_to(out, "largest velocity difference: {:.3e} m/s ({:.3e} of the striker speed) {}\n",
                 c.max_velocity_difference, pv, mark(pv));
  return fmt::to_string(b);
}

}  // namespace granstack::postproc
