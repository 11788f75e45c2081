#include <granstack/formats/case.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/contact.hpp>
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
  if (!mismatches.empty()) return std::numeric_limits<double>::infinity();
  double w = output_fraction.relative;
  for (const auto* list : {&dump, &series, &measures}) {
    for (const auto& d : *list) w = std::max(w, d.relative);
  }
  return w;
}

std::string RunComparison::disagreement(double tolerance) const {
  if (!mismatches.empty()) return mismatches.front();
  if (worst() <= tolerance) return "";
  const auto& w = largest();
  return fmt::format("whole runs differ by {:.3g} ({}, step {}), above the tolerance {:g}", w.relative, w.quantity, w.step,
                     tolerance);
}

const Difference& RunComparison::largest() const {
  const Difference* w = &output_fraction;
  for (const auto* list : {&dump, &series, &measures}) {
    for (const auto& d : *list) {
      if (d.relative > w->relative) w = &d;
    }
  }
  return *w;
}

namespace {

// The physical scale of each quantity, the floor of its relative differences.
struct Scales {
  double radius, mass, speed, spin, force, torque, energy, plate_mass;
  explicit Scales(const model::Stack& stack) {
    const auto& spec = stack.spec();
    const auto& top = stack.block(1);
    const auto& bottom = stack.blocks().back();
    const auto lib = spec.material_library();
    const auto& m = lib.at(top.material);
    // The largest force of the impact: the striker's peak on a top sphere (elastic, undamped).
    const auto c = model::sphere_sphere(m, top.radius, m, top.radius);
    const double d = model::max_overlap(spec.contact_model(), c, spec.striker_speed);
    radius = bottom.radius;
    mass = bottom.sphere_mass;
    speed = spec.striker_speed;
    spin = speed / radius;
    force = model::elastic_normal_force(spec.contact_model(), c, d);
    torque = force * radius;
    energy = stack.incident_energy();
    plate_mass = spec.plate_mass;
  }
  // Floor and unit of a series column: the energies by E_in, the wall's force by the impact's, the
  // plate's displacement by a radius, its velocity by the striker's, its acceleration by the
  // impact's force over its mass.
  std::pair<double, const char*> of_series(const std::string& column) const {
    const auto unit = model::series_column_unit(column);
    if (unit == "N") return {force, "N"};
    if (unit == "m") return {radius, "m"};
    if (unit == "m/s") return {speed, "m/s"};
    if (unit == "m/s^2") return {force / plate_mass, "m/s^2"};
    return {energy, "J"};
  }
  // Floor and unit of a dump column.
  std::pair<double, const char*> of(const std::string& column) const {
    const char first = column.empty() ? ' ' : column.front();
    if (column == "radius") return {radius, "m"};
    if (column == "mass") return {mass, "kg"};
    if (column == "x" || column == "y" || column == "z") return {radius, "m"};
    if (column.rfind("omega", 0) == 0) return {spin, "rad/s"};
    if (column.rfind("tq", 0) == 0) return {torque, "N m"};
    if (first == 'v') return {speed, "m/s"};
    if (first == 'f') return {force, "N"};
    return {1.0, ""};
  }
};

void add(Difference& d, double a, double b, long step, long atom) {
  const double r = std::fabs(a - b) / std::max({std::fabs(a), std::fabs(b), d.floor});
  if (d.values++ == 0 || r > d.relative) {
    d.relative = r;
    d.step = step;
    d.atom = atom;
    d.a = a;
    d.b = b;
  }
}

bool finite_frame(const formats::DumpFrame& f, const std::string& path, RunComparison& c) {
  for (std::size_t i = 0; i < f.values.size(); ++i) {
    if (!std::isfinite(f.values[i])) {
      const auto row = static_cast<long>(i / f.columns.size());
      const int id = f.column("id");
      c.mismatches.push_back(fmt::format("{}: {} in column '{}' of atom {} at step {}", path, f.values[i],
                                         f.columns[i % f.columns.size()], id >= 0 ? f.at(row, id) : 0.0, f.step));
      return false;
    }
  }
  return true;
}

// Every column both dumps carry, every sphere, every frame.
void compare_dumps(const std::string& dir_a, const formats::Manifest& ma, const std::string& dir_b,
                   const formats::Manifest& mb, const model::Stack& stack, RunComparison& c) {
  const auto path_a = formats::find_dump(dir_a, ma.files.dump), path_b = formats::find_dump(dir_b, mb.files.dump);
  const auto ra = formats::open_dump(path_a, ma.spec.dump_format == model::DumpFormat::binary, ma.files.dump_columns);
  const auto rb = formats::open_dump(path_b, mb.spec.dump_format == model::DumpFormat::binary, mb.files.dump_columns);
  const Scales scales(stack);
  formats::DumpFrame fa, fb;
  FrameView va(stack, path_a), vb(stack, path_b);
  std::vector<std::pair<int, int>> columns;  // (column in a, column in b) per Difference
  for (;;) {
    const bool more_a = ra->next(fa), more_b = rb->next(fb);
    if (!more_a || !more_b) {
      if (more_a || more_b) {
        c.mismatches.push_back(fmt::format("{} has more dump frames than {} (the first one {} lacks is at step {})",
                                           more_a ? path_a : path_b, more_a ? path_b : path_a, more_a ? path_b : path_a,
                                           (more_a ? fa : fb).step));
      }
      return;
    }
    if (fa.step != fb.step) {
      c.mismatches.push_back(fmt::format("dump frame {} is at step {} in {} and at step {} in {}", c.frames + 1, fa.step,
                                         path_a, fb.step, path_b));
      return;
    }
    if (!finite_frame(fa, path_a, c) || !finite_frame(fb, path_b, c)) return;
    va.bind(fa);
    vb.bind(fb);
    if (c.frames == 0) {
      for (const auto& name : fa.columns) {
        if (name == "id") continue;
        const int kb = fb.column(name);
        if (kb < 0) {
          c.mismatches.push_back(fmt::format("{} has the dump column '{}', {} has not", path_a, name, path_b));
          continue;
        }
        const auto [floor, unit] = scales.of(name);
        c.dump.push_back({name, unit, floor});
        columns.emplace_back(fa.column(name), kb);
      }
      for (const auto& name : fb.columns) {
        if (fa.column(name) < 0) c.mismatches.push_back(fmt::format("{} has the dump column '{}', {} has not", path_b, name, path_a));
      }
    }
    for (const auto& s : stack.spheres()) {
      const long rowa = va.row(s.id), rowb = vb.row(s.id);
      for (std::size_t k = 0; k < columns.size(); ++k) {
        add(c.dump[k], fa.at(rowa, columns[k].first), fb.at(rowb, columns[k].second), fa.step, s.id);
      }
    }
    ++c.frames;
  }
}

// Every column of the two series, step by step.
void compare_series(const std::string& dir_a, const formats::Manifest& ma, const std::string& dir_b,
                    const formats::Manifest& mb, const model::Stack& stack, RunComparison& c) {
  const auto path_a = formats::find_dump(dir_a, ma.files.series), path_b = formats::find_dump(dir_b, mb.files.series);
  const auto sa = formats::read_series(path_a), sb = formats::read_series(path_b);
  if (sa.columns != sb.columns) {
    c.mismatches.push_back(fmt::format("the series have other columns: {} in {}, {} in {}", fmt::join(sa.columns, " "),
                                       path_a, fmt::join(sb.columns, " "), path_b));
    return;
  }
  if (sa.rows.size() != sb.rows.size()) {
    c.mismatches.push_back(fmt::format("{} has {} series rows, {} has {}", path_a, sa.rows.size(), path_b, sb.rows.size()));
    return;
  }
  const Scales scales(stack);
  for (std::size_t j = 1; j < sa.columns.size(); ++j) {
    const auto [floor, unit] = scales.of_series(sa.columns[j]);
    c.series.push_back({sa.columns[j], unit, floor});
  }
  for (std::size_t i = 0; i < sa.rows.size(); ++i) {
    const auto& a = sa.rows[i];
    const auto& b = sb.rows[i];
    if (a[0] != b[0]) {
      c.mismatches.push_back(fmt::format("series row {} is at step {} in {} and at step {} in {}", i + 1, a[0], path_a,
                                         b[0], path_b));
      return;
    }
    for (std::size_t j = 1; j < a.size(); ++j) {
      if (!std::isfinite(a[j]) || !std::isfinite(b[j])) {
        c.mismatches.push_back(fmt::format("series column '{}' at step {}: {} in {}, {} in {}", sa.columns[j], a[0], a[j],
                                           path_a, b[j], path_b));
        return;
      }
      add(c.series[j - 1], a[j], b[j], static_cast<long>(a[0]), -1);
    }
    ++c.series_rows;
  }
}

// Runs `what`, turning a bad file into a mismatch.
template <typename F>
void recorded(RunComparison& c, F what) {
  try {
    what();
  } catch (const formats::FormatError& e) {
    c.mismatches.push_back(e.what());
  } catch (const PhysicsError& e) {
    c.mismatches.push_back(e.what());
  }
}

// The protection measures of two reductions of one case, and where each judged the blow ended.
void compare_measures(const CaseReduction& a, const CaseReduction& b, const Scales& scale, RunComparison& c) {
  c.measures.push_back({"crush", "m", scale.radius});
  add(c.measures.back(), a.crush, b.crush, -1, -1);
  c.measures.push_back({"penetration", "m", scale.radius});
  add(c.measures.back(), a.penetration, b.penetration, -1, -1);
  if (a.peak_wall_force && b.peak_wall_force) {
    c.measures.push_back({"peak_wall_force", "N", scale.force});
    add(c.measures.back(), *a.peak_wall_force, *b.peak_wall_force, -1, -1);
  } else if (a.peak_wall_force.has_value() != b.peak_wall_force.has_value()) {
    c.mismatches.push_back("only one run has a bottom wall's force");
  }
  if (a.yield_ratio && b.yield_ratio) {
    // Relative, with first yield (1) as the floor.
    c.measures.push_back({"yield_ratio", "of first yield", 1.0});
    add(c.measures.back(), *a.yield_ratio, *b.yield_ratio, -1, -1);
  } else if (a.yield_ratio.has_value() != b.yield_ratio.has_value()) {
    c.mismatches.push_back("only one run's contacts are judged for first yield");
  }
  if (a.blow_end_time != b.blow_end_time) {
    const auto when = [](const std::optional<double>& t) { return t ? fmt::format("at t = {:.17g} s", *t) : std::string("not"); };
    c.mismatches.push_back(fmt::format("the blow ended {} in one run and {} in the other (judged from each dump)",
                                       when(a.blow_end_time), when(b.blow_end_time)));
  }
}

}  // namespace

RunComparison compare_runs(const std::string& dir_a, const std::string& dir_b) {
  RunComparison c;
  const auto case_a = formats::Case::open(dir_a), case_b = formats::Case::open(dir_b);
  const auto &ma = case_a.manifest(), &mb = case_b.manifest();
  c.case_name = ma.case_name;
  const auto& stack = case_a.stack();
  recorded(c, [&] { compare_dumps(dir_a, ma, dir_b, mb, stack, c); });
  recorded(c, [&] { compare_series(dir_a, ma, dir_b, mb, stack, c); });
  c.output_fraction = {"output_fraction", "of E_in", kOutputFractionFloor};
  ReduceOptions quiet;
  quiet.write_files = false;
  quiet.verify_run_outputs = false;  // the copies validate has just run, compared frame by frame above
  recorded(c, [&] {
    const auto a = reduce_case(dir_a, quiet);
    const auto b = reduce_case(dir_b, quiet);
    add(c.output_fraction, a.output_fraction, b.output_fraction, -1, -1);
    compare_measures(a, b, Scales(stack), c);
  });
  return c;
}

std::string format_comparison(const RunComparison& c, const std::string& name_a, const std::string& name_b,
                              double tolerance) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, "{}: {} against {}: {} dump frames, {} series rows compared; tolerance {:g} of max(|{}|, |{}|, floor)\n",
                 c.case_name, name_a, name_b, c.frames, c.series_rows, tolerance, name_a, name_b);
  fmt::format_to(out, "{:<24} {:>10} {:<7} {:>10}  {:<4} {:>9} {:>6}  {:>24} {:>24}\n", "quantity", "floor", "", "largest",
                 "", "at step", "atom", name_a, name_b);
  auto row = [&](const Difference& d) {
    fmt::format_to(out, "{:<24} {:>10.3e} {:<7} {:>10.3e}  {:<4} {:>9} {:>6}  {:>24.17g} {:>24.17g}\n", d.quantity, d.floor,
                   d.unit, d.relative, d.relative <= tolerance ? "ok" : "OVER", d.step >= 0 ? std::to_string(d.step) : "-",
                   d.atom >= 0 ? std::to_string(d.atom) : "-", d.a, d.b);
  };
  for (const auto& d : c.dump) row(d);
  for (const auto& d : c.series) row(d);
  row(c.output_fraction);
  for (const auto& d : c.measures) row(d);
  for (const auto& m : c.mismatches) fmt::format_to(out, "MISMATCH: {}\n", m);
  const auto& w = c.largest();
  if (c.mismatches.empty()) {
    fmt::format_to(out, "{}: largest difference {:.3e} ({}{}) {} the tolerance {:g}\n",
                   c.worst() <= tolerance ? "agree" : "DISAGREE", w.relative, w.quantity,
                   w.step >= 0 ? fmt::format(", step {}", w.step) : "", c.worst() <= tolerance ? "within" : "above",
                   tolerance);
  } else {
    fmt::format_to(out, "DISAGREE: {} mismatch{}\n", c.mismatches.size(), c.mismatches.size() == 1 ? "" : "es");
  }
  return fmt::to_string(b);
}

}  // namespace granstack::postproc
