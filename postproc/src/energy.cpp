#include <granstack/formats/error.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/postproc/energy.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace granstack::postproc {

namespace {
const std::vector<std::string> kNeededColumns{"id", "mass", "radius", "x", "y", "z", "vx", "vy", "vz",
                                              "omegax", "omegay", "omegaz"};
}  // namespace

const std::vector<std::string>& FrameView::needed_columns() { return kNeededColumns; }

void FrameView::require_finite(const formats::DumpFrame& f) const {
  if (f.finite) return;  // its reader checked every value
  const std::size_t n = f.values.size();
  // A double is finite unless its exponent's bits are all ones, and then only does adding one to
  // its exponent carry into the top bit: tested in blocks with adds and ors alone (vectorised),
  // the first non-finite value then looked for in its block.
  constexpr std::uint64_t kExponent = 0x7ff0000000000000, kExponentOne = 0x0010000000000000;
  constexpr std::size_t kBlock = 256;
  std::size_t bad = n;
  for (std::size_t start = 0; start < n && bad == n; start += kBlock) {
    const std::size_t stop = std::min(n, start + kBlock);
    std::uint64_t carries = 0;
    for (std::size_t i = start; i < stop; ++i) {
      carries |= (std::bit_cast<std::uint64_t>(f.values[i]) & kExponent) + kExponentOne;
    }
    if ((carries >> 63) == 0) continue;
    const auto first = f.values.begin() + static_cast<std::ptrdiff_t>(start);
    bad = static_cast<std::size_t>(std::find_if(first, f.values.end(), [](double v) { return !std::isfinite(v); }) -
                                   f.values.begin());
  }
  if (bad == n) return;
  const std::size_t ncol = f.columns.size();
  const long row = static_cast<long>(bad / ncol);
  const int c_id = f.column("id");
  const double id = c_id >= 0 ? f.at(row, c_id) : 0.0;
  // A text frame's atom lines follow its nine header lines; a binary one has no lines.
  const long line = f.first_line > 0 && f.deferred.empty() ? f.first_line + 9 + row : 0;
  throw formats::FormatError(path_, line,
                             fmt::format("{} in column '{}' of atom {} (row {}) in the frame at step {}: the run "
                                         "blew up or the file is damaged; a result cannot be taken from it",
                                         f.values[bad], f.columns[bad % ncol],
                                         std::isfinite(id) ? fmt::format("id {}", static_cast<long>(id)) : "?", row + 1,
                                         f.step));
}

FrameView::FrameView(const model::Stack& stack, const std::string& path)
    : stack_(stack), path_(path), rows_(stack.spheres().size(), -1) {}

void FrameView::bind(const formats::DumpFrame& f) {
  formats::require_columns(f, kNeededColumns, path_);
  require_finite(f);
  c_id_ = f.column("id");
  c_mass_ = f.column("mass");
  c_radius_ = f.column("radius");
  c_x_ = f.column("x");
  c_y_ = f.column("y");
  c_z_ = f.column("z");
  c_vx_ = f.column("vx");
  c_vy_ = f.column("vy");
  c_vz_ = f.column("vz");
  c_wx_ = f.column("omegax");
  c_wy_ = f.column("omegay");
  c_wz_ = f.column("omegaz");
  const long n = static_cast<long>(stack_.spheres().size());
  if (f.atoms != n) {
    throw formats::FormatError(path_, f.first_line,
                               fmt::format("the frame at step {} has {} atoms, the case has {} spheres (atoms lost, or "
                                           "a dump of another case?)",
                                           f.step, f.atoms, n));
  }
  std::fill(rows_.begin(), rows_.end(), -1);
  for (long r = 0; r < f.atoms; ++r) {
    const double idv = f.at(r, c_id_);
    const long id = static_cast<long>(idv);
    if (static_cast<double>(id) != idv || id < 1 || id > n || rows_[static_cast<std::size_t>(id - 1)] >= 0) {
      throw formats::FormatError(path_, f.first_line,
                                 fmt::format("the frame at step {} has atom id {}: ids must be 1..{}, each once", f.step,
                                             idv, n));
    }
    rows_[static_cast<std::size_t>(id - 1)] = r;
  }
}

// 1/2 (2/5 m R^2) w^2 and 1/2 m v^2: one expression each (model/contact.hpp), so every sum of
// them rounds alike.

double FrameView::rotational_energy(const formats::DumpFrame& f, long r) const {
  return model::rotational_energy(f.at(r, c_mass_), f.at(r, c_radius_), f.at(r, c_wx_), f.at(r, c_wy_), f.at(r, c_wz_));
}

double FrameView::translational_energy(const formats::DumpFrame& f, long r) const {
  return model::translational_energy(f.at(r, c_mass_), f.at(r, c_vx_), f.at(r, c_vy_), f.at(r, c_vz_));
}

double FrameView::kinetic_energy(const formats::DumpFrame& f, long r) const {
  return translational_energy(f, r) + rotational_energy(f, r);
}

// The elastic energy of the normal contacts under the case's contact model (model/contact.hpp),
// with Y* of every atom-type pair and of every type against the walls computed once. Named, not
// anonymous: FrameAnalyser::Constants holds one.
namespace detail {

class ContactEnergy {
 public:
  explicit ContactEnergy(const model::Stack& stack) : stack_(stack), model_(stack.spec().contact_model()) {
    const auto& spec = stack.spec();
    const auto lib = spec.material_library();
    const auto types = stack.type_materials();
    ntypes_ = types.size();
    y_star_.resize(ntypes_ * ntypes_);
    for (std::size_t a = 0; a < ntypes_; ++a) {
      density_.push_back(lib.at(types[a]).density);
      for (std::size_t b = 0; b < ntypes_; ++b) {
        y_star_[a * ntypes_ + b] = model::effective_youngs_modulus(lib.at(types[a]), lib.at(types[b]));
      }
    }
    if (stack.has_walls()) {
      wall_y_star_.resize(ntypes_);
      const auto& wall = lib.at(spec.effective_wall_material());
      for (std::size_t a = 0; a < ntypes_; ++a) wall_y_star_[a] = model::effective_youngs_modulus(lib.at(types[a]), wall);
    }
  }

  // An elastic-plastic law's energy depends on each contact's largest overlap, which no dump
  // holds: it counts as 0 here (the balance then bounds the kinetic energy alone).
  double pair(const model::Sphere& a, const model::Sphere& b, double overlap) const {
    if (!overlap_energy_) return 0.0;
    model::ContactPair c{y_star_[type(a) * ntypes_ + type(b)], 0.0, a.radius * b.radius / (a.radius + b.radius), 0.0};
    if (model::normal_law(model_.normal).needs_mass) c.m_star = mass(a) * mass(b) / (mass(a) + mass(b));
    return model::elastic_energy(model_, c, overlap);
  }

  // Against every wall of the stack (a wall has R* = R_i), the sphere's centre at (x, y, z).
  // Over a protected plate, the bottom wall displaced by `plate_z`.
  double walls(const model::Sphere& s, const std::array<double, 3>& centre, double plate_z) const {
    if (wall_y_star_.empty() || !overlap_energy_) return 0.0;
    const model::ContactPair c{wall_y_star_[type(s)], 0.0, s.radius, mass(s)};  // a wall: R* = R_i, m* = m_i
    double energy = 0.0;
    for (const auto& w : walls_) {
      const double overlap = w.overlap(centre, s.radius, plate_z);
      if (overlap > 0.0) energy += model::elastic_energy(model_, c, overlap);
    }
    return energy;
  }

 private:
  std::size_t type(const model::Sphere& s) const { return static_cast<std::size_t>(s.atom_type - 1); }
  double mass(const model::Sphere& s) const { return model::sphere_mass(s.radius, density_[type(s)]); }

  const model::Stack& stack_;
  model::ContactModel model_;
  bool overlap_energy_ = model::has_overlap_energy(model_);
  std::vector<double> density_;  // per atom type
  std::size_t ntypes_ = 0;
  std::vector<double> y_star_;
  std::vector<double> wall_y_star_;
  std::vector<model::Wall> walls_ = stack_.walls();
};

}  // namespace detail

struct FrameAnalyser::Constants {
  explicit Constants(const model::Stack& stack) : contacts(stack), crush(stack), yield(stack) {}
  detail::ContactEnergy contacts;
  model::CrushMeter crush;  // its `at` alone: the frames' largest is taken in frame order
  model::YieldMeter yield;  // the same
  // Per sphere, in the stack's order: its block (index 0 = block 1; kStriker, kMatrix), its
  // row and column (index 0 = 1), and whether it is in the top row of block 1 and in the bottom
  // row of Stack::bottom_row_ids.
  static constexpr int kStriker = -1, kMatrix = -2;
  std::vector<int> block, row, column, column_y;
  std::vector<char> top_row, bottom_row;
  std::vector<double> radius;
};

FrameAnalyser::FrameAnalyser(const model::Stack& stack, const std::string& path)
    : stack_(stack), view_(stack, path), candidates_(stack), constants_(std::make_unique<Constants>(stack)) {
  auto& c = *constants_;
  for (const auto& s : stack.spheres()) {
    c.block.push_back(stack.is_matrix(s) ? Constants::kMatrix : s.block - 1);
    c.row.push_back(s.row - 1);
    c.column.push_back(s.column - 1);
    c.column_y.push_back(s.column_y - 1);
    c.top_row.push_back(s.block == 1 && s.row == 1 ? 1 : 0);
    c.radius.push_back(s.radius);
  }
  c.bottom_row.assign(stack.spheres().size(), 0);
  for (const int id : stack.bottom_row_ids()) c.bottom_row[static_cast<std::size_t>(id - 1)] = 1;
}

FrameAnalyser::~FrameAnalyser() = default;

void FrameAnalyser::analyse(const formats::DumpFrame& f, FrameEnergy& e, double plate_z, double plate_vz) {
  view_.bind(f);
  plate_z_ = plate_z;
  const auto& v = view_;
  const auto& c = *constants_;
  const auto& stack = stack_;
  e.step = f.step;
  const std::size_t nb = stack.blocks().size();
  for (auto* parts : {&e.block_ke, &e.block_ke_sideways, &e.block_ke_downward, &e.block_ke_rotational}) {
    parts->assign(nb, 0.0);
  }
  e.row_ke.resize(nb);
  e.column_ke.resize(nb);
  e.column_y_ke.resize(nb);
  for (std::size_t k = 0; k < nb; ++k) {
    e.row_ke[k].assign(static_cast<std::size_t>(stack.blocks()[k].rows), 0.0);
    e.column_ke[k].assign(static_cast<std::size_t>(stack.blocks()[k].columns), 0.0);
    e.column_y_ke[k].assign(static_cast<std::size_t>(stack.blocks()[k].depth), 0.0);
  }
  e.top_row_sideways = e.top_row_downward = e.striker_ke = e.output_sphere_ke = e.bottom_row_ke = e.bottom_row_max_ke = 0.0;
  e.momentum_z = 0.0;
  e.kinetic = e.elastic = e.striker_vz = e.matrix_ke = 0.0;
  const auto out_index = static_cast<std::size_t>(stack.output_sphere_id() - 1);
  const auto& spheres = stack.spheres();
  const std::size_t n = spheres.size();
  for (auto* column : {&x_, &y_, &z_, &vx_, &vy_, &vz_, &m_, &r_}) column->resize(n);
  const std::size_t stride = f.columns.size();
  const double* values = f.values.data();
  const auto col = [](int index) { return static_cast<std::size_t>(index); };
  const std::size_t cx = col(v.c_x_), cy = col(v.c_y_), cz = col(v.c_z_), cm = col(v.c_mass_), cr = col(v.c_radius_);
  const std::size_t cvx = col(v.c_vx_), cvy = col(v.c_vy_), cvz = col(v.c_vz_);
  const std::size_t cwx = col(v.c_wx_), cwy = col(v.c_wy_), cwz = col(v.c_wz_);
  // Sphere by sphere in the stack's order (ids 1..n), so every sum keeps one order whatever the
  // order of the dump's lines.
  for (std::size_t i = 0; i < n; ++i) {
    const double* a = values + static_cast<std::size_t>(v.rows_[i]) * stride;
    x_[i] = a[cx];
    y_[i] = a[cy];
    z_[i] = a[cz];
    const double m = a[cm], rad = a[cr];
    const double vx = a[cvx], vy = a[cvy], vz = a[cvz];
    vx_[i] = vx;
    vy_[i] = vy;
    vz_[i] = vz;
    m_[i] = m;
    r_[i] = rad;
    const double wx = a[cwx], wy = a[cwy], wz = a[cwz];
    const double rot = model::rotational_energy(m, rad, wx, wy, wz);
    const double ke = model::translational_energy(m, vx, vy, vz) + rot;
    e.kinetic += ke;
    e.momentum_z += m * vz;
    const int b = c.block[i];
    if (b == Constants::kStriker) {
      e.striker_ke += ke;
      e.striker_vz = vz;
    } else if (b == Constants::kMatrix) {
      e.matrix_ke += ke;
    } else {
      const auto k = static_cast<std::size_t>(b);
      const double sideways = 0.5 * m * (vx * vx + vy * vy), downward = 0.5 * m * vz * vz;
      e.block_ke[k] += ke;
      e.block_ke_sideways[k] += sideways;
      e.block_ke_downward[k] += downward;
      e.block_ke_rotational[k] += rot;
      e.row_ke[k][static_cast<std::size_t>(c.row[i])] += ke;
      e.column_ke[k][static_cast<std::size_t>(c.column[i])] += ke;
      e.column_y_ke[k][static_cast<std::size_t>(c.column_y[i])] += ke;
      if (c.top_row[i] != 0) {
        e.top_row_sideways += sideways;
        e.top_row_downward += downward;
      }
    }
    if (i == out_index) e.output_sphere_ke = ke;
    if (c.bottom_row[i] != 0) {
      e.bottom_row_ke += ke;
      e.bottom_row_max_ke = std::max(e.bottom_row_max_ke, ke);
    }
  }
  e.output_free = true;
  // The contact pressures over first yield from the same overlaps (model::YieldMeter::at's parts).
  model::YieldFrame yield;
  const bool judged = c.yield.judged();
  for (const auto& [i, j] : candidates_.pairs(x_, y_, z_)) {
    const double dx = x_[i] - x_[j], dy = y_[i] - y_[j], dz = z_[i] - z_[j];
    const double sum = c.radius[i] + c.radius[j];
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < sum * sum) {
      const double overlap = sum - std::sqrt(d2);
      e.elastic += c.contacts.pair(spheres[i], spheres[j], overlap);
      if (judged) c.yield.pair(yield, i, j, overlap);
    }
    if ((i == out_index || j == out_index) && model::spheres_touch(dx, dy, dz, c.radius[i], c.radius[j])) e.output_free = false;
  }
  // Another sphere on course to hit the output sphere (model::BlowEnd), in id order as refsim.
  // Judged with a free bottom only (model::BlowEnd reads it there), as refsim's in-situ run does.
  const auto state = [&](std::size_t i) {
    return std::array<double, 7>{x_[i], y_[i], z_[i], vx_[i], vy_[i], vz_[i], c.radius[i]};
  };
  e.output_threatened = stack.spec().bottom != model::Boundary::wall && model::threatened(n, out_index, state);
  e.striker = model::striker_course(stack, n, state);
  e.crush = c.crush.at(state, plate_z);
  if (judged) c.yield.walls(yield, x_, y_, z_, plate_z);
  e.yield = c.yield.peak(f.step, yield);
  e.over_footprint = {};
  if (stack.spec().bottom == model::Boundary::wall) {
    e.over_footprint = model::over_footprint(
        stack, n, [&](std::size_t i) { return std::array<double, 6>{x_[i], y_[i], z_[i], r_[i], m_[i], vz_[i]}; },
        plate_vz);
  }
  if (stack.has_walls()) {
    for (std::size_t i = 0; i < n; ++i) e.elastic += c.contacts.walls(spheres[i], {x_[i], y_[i], z_[i]}, plate_z);
  }
}

bool FrameAnalyser::has_separated(const formats::DumpFrame& f, int id) const {
  const auto& v = view_;
  const double ke = v.kinetic_energy(f, v.row(id));
  if (!(ke > 0.0)) return false;
  // The elastic energy in its contacts, with the walls and with every other sphere.
  const auto& contacts = constants_->contacts;
  const auto& me = stack_.sphere(id);
  const long row = v.row(id);
  const double x = f.at(row, v.c_x_), y = f.at(row, v.c_y_), z = f.at(row, v.c_z_);
  double energy = contacts.walls(me, {x, y, z}, plate_z_);
  for (const auto& s : stack_.spheres()) {
    if (s.id == id) continue;
    const long r = v.row(s.id);
    const double dx = f.at(r, v.c_x_) - x, dy = f.at(r, v.c_y_) - y, dz = f.at(r, v.c_z_) - z;
    const double sum = me.radius + s.radius;
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < sum * sum) energy += contacts.pair(me, s, sum - std::sqrt(d2));
  }
  return energy <= kSeparatedContactEnergy * ke;
}

}  // namespace granstack::postproc
