#include <granstack/formats/case.hpp>
#include <granstack/formats/deck.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/ownership.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/formats/vtk.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/os/case_lock.hpp>
#include <granstack/postproc/energy.hpp>
#include <granstack/postproc/export.hpp>
#include <granstack/postproc/reduce.hpp>

#include <fmt/format.h>

#include <charconv>
#include <filesystem>
#include <optional>
#include <stdexcept>

namespace granstack::postproc {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void bad_selection(const std::string& selection, const std::string& why) {
  throw std::invalid_argument(fmt::format(
      "--frames '{}': {}; give 'all', frame numbers (0 the first, -1 the last) or slices such as '::10' (every tenth "
      "frame) and '-5:' (the last five), separated by commas",
      selection, why));
}

// A whole number of a selection, `fallback` for an empty text.
long whole_number(const std::string& selection, std::string_view text, long fallback) {
  if (text.empty()) return fallback;
  long v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size()) bad_selection(selection, fmt::format("'{}' is not a whole number", text));
  return v;
}

// A frame number of a selection; negative counts from the end.
long frame_number(const std::string& selection, std::string_view text, long count, long fallback) {
  const long v = whole_number(selection, text, fallback);
  return v < 0 ? v + count : v;
}

}  // namespace

std::vector<bool> select_frames(const std::string& selection, long count) {
  std::vector<bool> picked(static_cast<std::size_t>(std::max(0L, count)), selection == "all");
  if (selection == "all") return picked;
  if (selection.empty()) bad_selection(selection, "nothing selected");
  std::size_t start = 0;
  while (start <= selection.size()) {
    const std::size_t comma = std::min(selection.find(',', start), selection.size());
    const std::string_view item(selection.data() + start, comma - start);
    const std::size_t c1 = item.find(':');
    if (c1 == std::string_view::npos) {
      const long k = frame_number(selection, item, count, -1);
      if (item.empty() || k < 0 || k >= count) {
        bad_selection(selection, fmt::format("frame '{}' is not one of the dump's {} frames (0 to {})", item, count, count - 1));
      }
      picked[static_cast<std::size_t>(k)] = true;
    } else {
      const std::size_t c2 = item.find(':', c1 + 1);
      const auto stride_text = c2 == std::string_view::npos ? std::string_view{} : item.substr(c2 + 1);
      const long stride = whole_number(selection, stride_text, 1);
      if (stride < 1) bad_selection(selection, fmt::format("the stride in '{}' must be 1 or more", item));
      const long first = std::clamp(frame_number(selection, item.substr(0, c1), count, 0), 0L, count);
      const long end = std::clamp(frame_number(selection, item.substr(c1 + 1, c2 == std::string_view::npos ? std::string_view::npos : c2 - c1 - 1),
                                               count, count),
                                  0L, count);
      if (first >= end) {
        bad_selection(selection, fmt::format("the range '{}' selects no frame (of the dump's {}, 0 to {}): its start "
                                             "must come before its end",
                                             item, count, count - 1));
      }
      for (long k = first; k < end; k += stride) picked[static_cast<std::size_t>(k)] = true;
    }
    start = comma + 1;
  }
  return picked;
}

namespace {

// The arrays of one frame, spheres in id order.
formats::VtkPoints frame_points(const model::Stack& stack, const formats::DumpFrame& f, const FrameView& view) {
  const long n = f.atoms;
  formats::VtkPoints p;
  p.scalars = "kinetic_energy";
  p.vectors = "velocity";
  p.xyz.reserve(static_cast<std::size_t>(3 * n));
  const auto column = [&](const char* name) { return f.column(name); };
  const int cx = column("x"), cy = column("y"), cz = column("z");
  formats::VtkArray id{"id", 1, {}, {}}, type{"type", 1, {}, {}}, block{"block", 1, {}, {}};
  formats::VtkArray row_index{"row", 1, {}, {}}, x_column{"column", 1, {}, {}}, y_column{"column_y", 1, {}, {}};
  formats::VtkArray panel{"panel", 1, {}, {}}, chain{"matrix_chain", 1, {}, {}};
  formats::VtkArray radius{"radius", 1, {}, {}}, mass{"mass", 1, {}, {}};
  formats::VtkArray ke{"kinetic_energy", 1, {}, {}}, ke_t{"kinetic_energy_translational", 1, {}, {}},
      ke_r{"kinetic_energy_rotational", 1, {}, {}};
  // Three-component columns the dump holds.
  struct Vector {
    formats::VtkArray array;
    int c[3];
  };
  std::vector<Vector> vectors;
  for (const auto& [name, a, b, c] : {std::tuple{"velocity", "vx", "vy", "vz"}, {"angular_velocity", "omegax", "omegay", "omegaz"},
                                      {"force", "fx", "fy", "fz"}, {"torque", "tqx", "tqy", "tqz"}}) {
    if (column(a) >= 0 && column(b) >= 0 && column(c) >= 0) vectors.push_back({{name, 3, {}, {}}, {column(a), column(b), column(c)}});
  }
  const int ctype = column("type"), cradius = column("radius"), cmass = column("mass");
  for (int sid = 1; sid <= n; ++sid) {
    const long r = view.row(sid);
    for (const int c : {cx, cy, cz}) p.xyz.push_back(f.at(r, c));
    id.integers.push_back(sid);
    type.integers.push_back(ctype >= 0 ? static_cast<std::int64_t>(f.at(r, ctype)) : 0);
    const auto& sphere = stack.spheres()[static_cast<std::size_t>(sid - 1)];
    block.integers.push_back(sphere.block);
    row_index.integers.push_back(sphere.row);
    x_column.integers.push_back(sphere.column);
    y_column.integers.push_back(sphere.column_y);
    panel.integers.push_back(stack.panel_of(sphere));
    chain.integers.push_back(sphere.chain);
    radius.reals.push_back(f.at(r, cradius));
    mass.reals.push_back(f.at(r, cmass));
    // Their sum, as FrameView::kinetic_energy adds them.
    ke_t.reals.push_back(view.translational_energy(f, r));
    ke_r.reals.push_back(view.rotational_energy(f, r));
    ke.reals.push_back(ke_t.reals.back() + ke_r.reals.back());
    for (auto& v : vectors) {
      for (const int c : v.c) v.array.reals.push_back(f.at(r, c));
    }
  }
  p.arrays = {std::move(id),    std::move(type),  std::move(block), std::move(row_index), std::move(x_column),
              std::move(y_column), std::move(panel), std::move(chain), std::move(radius), std::move(mass),
              std::move(ke),    std::move(ke_t),  std::move(ke_r)};
  for (auto& v : vectors) p.arrays.push_back(std::move(v.array));
  return p;
}

}  // namespace

ExportResult export_case(const std::string& case_dir, const ExportOptions& o) {
  const auto c = formats::Case::open(case_dir);
  // Writing into the case (its paraview/), export holds the case's lock, as every command that writes a case does.
  std::optional<os::CaseLock> lock;
  if (o.output_dir.empty()) lock.emplace(c.lock("granstack export"));
  require_finished_run(c, lock.has_value());  // a run that failed or goes on has no frames to show as the case's
  formats::check_deck_matches_manifest(c);  // an edited case's frames would carry the manifest's labels
  formats::require_files_as_run(c);          // and so would another case's dump copied in
  const auto& m = c.manifest();
  const auto& stack = c.stack();
  const double dt = c.derived().dt;
  const long steps = c.derived().steps, every = c.derived().dump_every;
  const long count = formats::frames_written(c);  // frames at steps 0, every, 2 every, ..., up to the run's end
  const auto picked = select_frames(o.frames, count);
  const fs::path out = o.output_dir.empty() ? fs::path(case_dir) / "paraview" : fs::path(o.output_dir);
  // The case directory's own name, however it was written ("runs/a/", ".", "../a").
  const std::string name = fs::weakly_canonical(fs::absolute(case_dir)).filename().string();
  const int width = static_cast<int>(std::to_string(steps).size());
  const auto frame_file = [&](long step) { return fmt::format("{}_{:0{}}.vtp", name, step, width); };
  std::vector<std::string> names{name + ".pvd"};
  for (long k = 0; k < count; ++k) {
    if (picked[static_cast<std::size_t>(k)]) names.push_back(frame_file(k * every));
  }
  const auto dump_path = formats::find_dump(case_dir, m.files.dump);
  const auto reader = formats::open_dump(dump_path, m.spec.dump_format == model::DumpFormat::binary, m.files.dump_columns);
  formats::prepare_output_directory(out, names, o.force, "export");

  ExportResult result;
  result.pvd = (out / names.front()).string();
  result.spheres = static_cast<long>(stack.spheres().size());
  FrameView view(stack, dump_path);
  std::vector<formats::PvdEntry> entries;
  formats::DumpFrame f;
  const long wanted = static_cast<long>(names.size()) - 1;
  while (result.frames < wanted) {
    if (o.stop && o.stop()) {
      result.complete = false;
      break;
    }
    try {
      if (!reader->next(f)) {
        result.complete = false;
        break;
      }
    } catch (const formats::TruncatedError&) {
      result.complete = false;  // a run still going, or cut short: its complete frames
      break;
    }
    const long index = f.step / every;
    if (f.step % every != 0 || index >= count || !picked[static_cast<std::size_t>(index)]) continue;
    view.bind(f);
    const std::string file = frame_file(f.step);
    formats::write_file_atomically(out / file, formats::vtp_document(frame_points(stack, f, view)));
    entries.push_back({static_cast<double>(f.step) * dt, file});
    ++result.frames;
    if (o.on_frame) o.on_frame(result.frames, wanted);
  }
  formats::write_file_atomically(out / names.front(), formats::pvd_document(entries));
  return result;
}

}  // namespace granstack::postproc
