#include <granstack/formats/data_file.hpp>
#include <granstack/formats/case.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/model/yield.hpp>
#include <granstack/refsim/case_run.hpp>

#include <fmt/compile.h>
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <vector>

#include "frame_judge.hpp"
#include "write_behind.hpp"

namespace granstack::refsim {

namespace fs = std::filesystem;

namespace {
// The property tables of types made of `materials`, with restitution and friction per type pair.
template <typename Restitution, typename Friction>
Parameters tables(const std::vector<model::Material>& materials, Restitution&& restitution, Friction&& friction) {
  Parameters p;
  p.types = static_cast<int>(materials.size());
  for (const auto& a : materials) {
    for (const auto& b : materials) {
      p.y_star.push_back(model::effective_youngs_modulus(a, b));
      p.g_star.push_back(model::effective_shear_modulus(a, b));
      p.beta.push_back(model::restitution_beta(restitution(a, b)));
      p.friction.push_back(friction(a, b));
      p.restitution.push_back(restitution(a, b));
      p.rolling_friction.push_back(0.0);
    }
  }
  return p;
}
}  // namespace

Parameters uniform_parameters(const std::vector<model::Material>& materials, double restitution, double friction,
                              double dt, double skin) {
  auto p = tables(materials, [&](const auto&, const auto&) { return restitution; },
                  [&](const auto&, const auto&) { return friction; });
  p.dt = dt;
  p.skin = skin;
  return p;
}

Parameters case_parameters(const model::Stack& stack) {
  const auto& spec = stack.spec();
  const auto res = model::resolve(stack);
  const auto lib = spec.material_library();
  std::vector<model::Material> materials;
  for (const auto& name : stack.type_materials()) materials.push_back(lib.at(name));
  auto p = tables(
      materials, [&](const model::Material& a, const model::Material& b) { return spec.restitution.get(a.name, b.name); },
      [&](const model::Material& a, const model::Material& b) { return spec.friction.get(a.name, b.name); });
  p.dt = res.dt;
  p.skin = res.skin;
  p.contact = spec.contact_model();
  p.rolling_friction.clear();
  for (const auto& a : materials) {
    for (const auto& b : materials) {
      p.rolling_friction.push_back(spec.rolling_friction.get(a.name, b.name));
      p.yield_pressure.push_back(model::yield_pressure(a, b, spec.yield_pressure_factor).value_or(0.0));
    }
  }
  if (spec.normal_model == model::NormalModel::thornton_ning) {
    const auto plan = model::thornton_ning_plan(stack);
    if (!plan.refusal.empty()) throw std::invalid_argument("normal_model = 'thornton_ning': " + plan.refusal);
    p.yield_ratio = plan.ratio;
  }
  // The deck's walls, in its order.
  for (const auto& w : stack.walls()) {
    if (w.name == model::kBottomWallName) p.stored_wall = static_cast<int>(p.walls.size());
    p.walls.push_back({w.axis, w.position, stack.wall_type()});
  }
  if (spec.has_plate()) {
    p.plate = {p.stored_wall, spec.plate_mass, spec.mount_stiffness, spec.mount_damping, model::plate_body(stack).start[2]};
  }
  // fix gravity ... vector 0 0 -1: acceleration = magnitude * unit vector.
  if (spec.gravity > 0.0) p.gravity = {spec.gravity * 0.0, spec.gravity * 0.0, spec.gravity * -1.0};
  return p;
}

std::vector<Particle> particles_from(const formats::DataFile& data) {
  std::vector<Particle> out;
  std::vector<long> ids;
  out.reserve(data.atoms.size());
  ids.reserve(data.atoms.size());
  for (const auto& a : data.atoms) {
    Particle p;
    p.type = a.type;
    p.radius = 0.5 * a.diameter;
    p.mass = model::sphere_mass(p.radius, a.density);
    p.x = {a.x, a.y, a.z};
    p.v = {a.vx, a.vy, a.vz};
    p.omega = {a.wx, a.wy, a.wz};
    out.push_back(p);
    ids.push_back(a.id);
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] != static_cast<long>(i) + 1) {
      throw std::runtime_error("refsim: the data file's atom ids must be 1..N in order (as granstack writes them)");
    }
  }
  return out;
}

double bottom_wall_force(const System& s) { return s.stored_wall_total(); }

namespace {

// The in-situ series of the generated deck: `fix print` of per-group ke and erotate/sphere
// (compute_ke.cpp and compute_erotate_sphere.cpp), each group's sums taken over its runs of
// consecutive atoms in System::kinetic_energy's order (LIGGGHTS sums in its own atom order:
// the sums agree to round-off); where the law keeps its contacts' energy, the contacts' elastic
// energy and dissipated work (model::series_contact_columns, System::contact_energies, summed in
// id order); the bottom wall's force. Each value is written in its shortest form that reads back
// to the same double (LIGGGHTS writes %.20g).
class SeriesWriter {
 public:
  SeriesWriter(const std::string& path, const model::Stack& stack, const std::vector<std::string>& columns)
      : path_(path), file_(std::fopen(path.c_str(), "w"), &std::fclose) {
    if (!file_) throw std::runtime_error(fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
    std::fprintf(file_.get(), "# %s\n", fmt::format("{}", fmt::join(columns, " ")).c_str());
    for (const auto& g : model::series_groups(stack)) {
      std::vector<Run> group;  // its ids as runs of consecutive particles
      for (const int id : g.ids) {
        if (!group.empty() && group.back().second == static_cast<std::size_t>(id - 1)) {
          ++group.back().second;
        } else {
          group.emplace_back(static_cast<std::size_t>(id - 1), static_cast<std::size_t>(id));
        }
      }
      if (g.atom_type != 0) dissipated_groups_.push_back(groups_.size());
      groups_.push_back(std::move(group));
    }
    contact_energy_ = !model::series_contact_columns(stack).empty();
    if (!contact_energy_) dissipated_groups_.clear();
    wall_force_ = std::find(columns.begin(), columns.end(), model::kBottomWallForceColumn) != columns.end();
    plate_ = stack.spec().has_plate();
    per_line_ = 1 + 2 * groups_.size() + (contact_energy_ ? 2 + dissipated_groups_.size() : 0) + (wall_force_ ? 1 : 0) +
                (plate_ ? model::kPlateColumns.size() : 0);
    if (columns.size() != per_line_) {
      throw std::runtime_error("refsim: the manifest's series columns are not this granstack's: generate the case again");
    }
  }

  // The series line of the system's state now: its step, then each group's two sums
  // (kinetic_energy, on the thread that steps it), the contacts' energies, the wall's force,
  // appended to `batch`.
  void sample(const System& s, std::vector<double>& batch) const {
    batch.push_back(static_cast<double>(s.step_count()));  // exact: steps stay far below 2^53
    for (const auto& g : groups_) {
      double ke = 0.0, rot = 0.0;
      for (const auto& [begin, end] : g) {
        const auto e = s.kinetic_energy(begin, end);
        ke += e[0];
        rot += e[1];
      }
      batch.push_back(ke);
      batch.push_back(rot);
    }
    if (contact_energy_) contact_energy(s, batch);
    if (wall_force_) batch.push_back(bottom_wall_force(s));
    if (plate_) {  // kPlateColumns' order
      batch.push_back(s.plate_displacement());
      batch.push_back(s.plate_velocity());
      batch.push_back(s.plate_acceleration());
    }
  }

  // The lines of samples taken by sample().
  void write(const std::vector<double>& batch) {
    // Formatted straight into a buffer long enough for any line (a number takes at most 24
    // characters and its space).
    line_.resize(25 * per_line_ + 1);
    for (std::size_t at = 0; at + per_line_ <= batch.size(); at += per_line_) {
      char* out = fmt::format_to(line_.data(), FMT_COMPILE("{}"), static_cast<long>(batch[at]));
      for (std::size_t k = at + 1; k < at + per_line_; ++k) out = fmt::format_to(out, FMT_COMPILE(" {}"), batch[k]);
      *out++ = '\n';
      const auto length = static_cast<std::size_t>(out - line_.data());
      if (std::fwrite(line_.data(), 1, length, file_.get()) != length) fail();
    }
  }

  // Writes out what is buffered and closes the file; throws if not all of it was written.
  void close() { formats::close_written(file_.release(), path_); }

 private:
  using Run = std::pair<std::size_t, std::size_t>;  // particles [first, second)
  [[noreturn]] void fail() const { throw std::runtime_error(fmt::format("{}: cannot write: {}", path_, std::strerror(errno))); }
  // The contacts' elastic energy and dissipated work, then each dissipating group's share.
  void contact_energy(const System& s, std::vector<double>& batch) const {
    const auto e = s.contact_energies();
    double elastic = 0.0, dissipated = 0.0;
    for (std::size_t i = 0; i < e.elastic.size(); ++i) {
      elastic += e.elastic[i];
      dissipated += e.dissipated[i];
    }
    batch.push_back(elastic);
    batch.push_back(dissipated);
    for (const std::size_t g : dissipated_groups_) {
      double sum = 0.0;
      for (const auto& [begin, end] : groups_[g]) {
        for (std::size_t i = begin; i < end; ++i) sum += e.dissipated[i];
      }
      batch.push_back(sum);
    }
  }
  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::vector<std::vector<Run>> groups_;  // each group's runs of consecutive particles
  std::vector<std::size_t> dissipated_groups_;  // the groups whose dissipated work is a column: blocks, strikers
  bool contact_energy_ = false;           // the contacts' energy columns follow the groups'
  bool wall_force_ = false;               // a column is the bottom wall's force
  bool plate_ = false;                    // the plate's columns end the line (model::kPlateColumns)
  std::size_t per_line_ = 0;
  std::string line_;
};

// The quantities a dump column can hold, each column's resolved once per run (comparing column
// names for every value took a fifth of a run's instructions).
enum class Column { id, type, radius, mass, x, y, z, vx, vy, vz, omegax, omegay, omegaz, fx, fy, fz, tqx, tqy, tqz };

std::vector<Column> resolve_columns(const std::vector<std::string>& columns) {
  static const std::vector<std::pair<const char*, Column>> known{
      {"id", Column::id},         {"type", Column::type},     {"radius", Column::radius}, {"mass", Column::mass},
      {"x", Column::x},           {"y", Column::y},           {"z", Column::z},           {"vx", Column::vx},
      {"vy", Column::vy},         {"vz", Column::vz},         {"omegax", Column::omegax}, {"omegay", Column::omegay},
      {"omegaz", Column::omegaz}, {"fx", Column::fx},         {"fy", Column::fy},         {"fz", Column::fz},
      {"tqx", Column::tqx},       {"tqy", Column::tqy},       {"tqz", Column::tqz}};
  std::vector<Column> out;
  for (const auto& c : columns) {
    const auto it = std::find_if(known.begin(), known.end(), [&](const auto& k) { return c == k.first; });
    if (it == known.end()) throw std::runtime_error(fmt::format("refsim cannot write the dump column '{}'", c));
    out.push_back(it->second);
  }
  return out;
}

double column_value(const System& s, std::size_t i, Column c) {
  switch (c) {
    case Column::id: return static_cast<double>(i + 1);
    case Column::type: return s.type(i);
    case Column::radius: return s.radius(i);
    case Column::mass: return s.mass(i);
    case Column::x: return s.x(i)[0];
    case Column::y: return s.x(i)[1];
    case Column::z: return s.x(i)[2];
    case Column::vx: return s.v(i)[0];
    case Column::vy: return s.v(i)[1];
    case Column::vz: return s.v(i)[2];
    case Column::omegax: return s.omega(i)[0];
    case Column::omegay: return s.omega(i)[1];
    case Column::omegaz: return s.omega(i)[2];
    case Column::fx: return s.force(i)[0];
    case Column::fy: return s.force(i)[1];
    case Column::fz: return s.force(i)[2];
    case Column::tqx: return s.torque(i)[0];
    case Column::tqy: return s.torque(i)[1];
    case Column::tqz: return s.torque(i)[2];
  }
  return 0.0;
}

// The frame's rows filled in `shares`' shares of the spheres (empty: in one).
void fill_frame(const System& s, const std::vector<std::string>& columns, const std::vector<Column>& resolved,
                const std::array<double, 6>& box0, formats::DumpFrame& f, const formats::ForShares& shares) {
  const std::size_t n = s.size();
  f.step = s.step_count();
  f.atoms = static_cast<long>(n);
  f.box_flags = "mm mm mm";
  if (f.columns != columns) f.columns = columns;
  f.values.resize(n * columns.size());
  // Shrink-wrapped with a minimum: the data file's box, grown to hold every sphere.
  f.box = box0;
  std::mutex m;
  const auto fill = [&](std::size_t begin, std::size_t end) {
    auto box = box0;
    double* out = f.values.data() + begin * columns.size();
    for (std::size_t i = begin; i < end; ++i) {
      const auto x = s.x(i);
      for (std::size_t d = 0; d < 3; ++d) {
        box[2 * d] = std::min(box[2 * d], x[d]);
        box[2 * d + 1] = std::max(box[2 * d + 1], x[d]);
      }
      for (const auto c : resolved) *out++ = column_value(s, i, c);
    }
    const std::lock_guard<std::mutex> lock(m);
    for (std::size_t d = 0; d < 3; ++d) {
      f.box[2 * d] = std::min(f.box[2 * d], box[2 * d]);
      f.box[2 * d + 1] = std::max(f.box[2 * d + 1], box[2 * d + 1]);
    }
  };
  if (shares) {
    shares(n, fill);
  } else {
    fill(0, n);
  }
}

// The dump frames of a run, at most two at a time (at a million spheres a frame holds 150 MB):
// one filled by the steps' thread while the other is written. A frame comes back when the last
// copy of its pointer goes (written, or dropped with the writing's jobs after an error).
class FramePool {
 public:
  std::shared_ptr<formats::DumpFrame> take() {
    std::unique_lock<std::mutex> lock(m_);
    returned_.wait(lock, [&] { return !free_.empty() || made_ < kFrames; });
    std::unique_ptr<formats::DumpFrame> f;
    if (free_.empty()) {
      f = std::make_unique<formats::DumpFrame>();
      ++made_;
    } else {
      f = std::move(free_.back());
      free_.pop_back();
    }
    return {f.release(), [this](formats::DumpFrame* back) { give(back); }};
  }

 private:
  static constexpr int kFrames = 2;
  void give(formats::DumpFrame* f) {
    {
      const std::lock_guard<std::mutex> lock(m_);
      free_.emplace_back(f);
    }
    returned_.notify_one();
  }
  std::mutex m_;
  std::condition_variable returned_;
  std::vector<std::unique_ptr<formats::DumpFrame>> free_;
  int made_ = 0;
};

}  // namespace

RunStats run_case(const std::string& case_dir, const RunOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  const auto started = Clock::now();
  auto read = started;
  const fs::path dir(case_dir);
  const auto c = formats::Case::open(case_dir);
  const auto& manifest = c.manifest();
  const auto& stack = c.stack();
  const auto res = c.resolution();
  auto params = case_parameters(stack);
  params.threads = options.threads;
  params.kernel = options.kernel;
  params.lammps_rules = options.lammps_rules;
  std::array<double, 6> box{};
  // The data file's atoms only while the system is built (a million spheres' take 110 MB).
  System system = [&] {
    const auto data = formats::parse_data_file((dir / manifest.files.data).string(), options.threads);
    box = data.box;
    auto particles = particles_from(data);
    read = Clock::now();
    return System(std::move(particles), params);
  }();
  const auto built = Clock::now();

  fs::create_directories((dir / manifest.files.dump).parent_path());
  // refsim's binary dumps are zstd streams of LIGGGHTS's bytes: a stack at rest or a constant
  // column costs next to nothing on disk, and every reader here takes them.
  formats::DumpWriter dump((dir / manifest.files.dump).string(), manifest.spec.dump_format == model::DumpFormat::binary, true);
  SeriesWriter series((dir / manifest.files.series).string(), stack, manifest.files.series_columns);
  const auto columns = resolve_columns(manifest.files.dump_columns);
  FramePool frames;
  std::vector<double> samples;
  // Declared last, so that it ends (its jobs done) before what they write to.
  detail::WriteBehind out(options.write_behind);
  // A frame is filled on the system's threads, which would wait; written in line, its text is
  // formatted on them too.
  formats::ForShares on_threads;
  if (options.threads > 1) {
    on_threads = [&system](std::size_t count, const std::function<void(std::size_t, std::size_t)>& job) {
      system.run_in_shares(count, job);
    };
  }
  const auto write_frame = [&] {
    auto frame = frames.take();
    fill_frame(system, manifest.files.dump_columns, columns, box, *frame, on_threads);
    const auto shares = options.write_behind ? formats::ForShares() : on_threads;
    out.submit([&dump, frame = std::move(frame), shares] { dump.write(*frame, shares); });
  };
  const auto write_samples = [&] {
    if (samples.empty()) return;
    out.submit([&series, batch = std::move(samples)] { series.write(batch); });
    samples.clear();
  };

  // A case that stops at the blow's end judges it at every dump frame (as the deck does in
  // LIGGGHTS) and stops where the deck stops (model::BlowEnd::stop_at); res.steps is then the cap.
  model::BlowEnd blow(stack, res);
  const auto frame = [&] {
    write_frame();
    if (!res.stops_at_blow_end) return false;
    detail::judge_blow_end(blow, stack, system);
    return blow.stop_at().has_value();
  };
  system.setup();
  bool ended = frame();
  // As LIGGGHTS's "Loop time" (run.cpp): the setup force call and the step-0 output are not in
  // it; the writing of the outputs of its steps is.
  const auto t0 = Clock::now();
  long last = 0;
  for (long step = 1; step <= res.steps && !ended; ++step) {
    // Up to the next step with output, a progress report or the end, in one go.
    const long next = std::min({res.steps, (step + res.series_every - 1) / res.series_every * res.series_every,
                                (step + res.dump_every - 1) / res.dump_every * res.dump_every, (step + 255) / 256 * 256});
    system.advance(next - step + 1);
    step = last = next;
    if (step % res.series_every == 0) series.sample(system, samples);
    if (step % res.dump_every == 0) ended = frame();
    if (step % 256 == 0 || step == res.steps || ended) {
      write_samples();  // in batches: a line each would cost the thread a wake-up each
      if (options.on_progress) options.on_progress(step, res.steps);
    }
  }
  out.finish();
  const auto looped = Clock::now();
  dump.close();
  series.close();
  RunStats stats;
  stats.loop_seconds = seconds(t0, looped);
  stats.read_seconds = seconds(started, read);
  stats.build_seconds = seconds(read, built);
  stats.first_output_seconds = seconds(built, t0);
  stats.close_seconds = seconds(looped, Clock::now());
  stats.steps = last;
  stats.atoms = static_cast<long>(system.size());
  stats.particle_steps_per_second =
      stats.loop_seconds > 0 ? static_cast<double>(stats.steps) * static_cast<double>(stats.atoms) / stats.loop_seconds : 0.0;
  stats.neighbor_builds = system.neighbor_builds();
  stats.kernel = system.kernel();
  stats.write_behind = options.write_behind;
  return stats;
}

}  // namespace granstack::refsim
