#include <granstack/formats/error.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/postproc/energy.hpp>

#include <fmt/format.h>

#include <cmath>

namespace granstack::postproc {

namespace {
const std::vector<std::string> kNeededColumns{"id", "mass", "radius", "x", "y", "z", "vx", "vy", "vz",
                                              "omegax", "omegay", "omegaz"};
}  // namespace

FrameView::FrameView(const model::Stack& stack, const std::string& path)
    : stack_(stack), path_(path), rows_(stack.spheres().size(), -1) {}

void FrameView::bind(const formats::DumpFrame& f) {
  formats::require_columns(f, kNeededColumns, path_);
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

double FrameView::rotational_energy(const formats::DumpFrame& f, long r) const {
  const double m = f.at(r, c_mass_);
  const double rad = f.at(r, c_radius_);
  const double wx = f.at(r, c_wx_), wy = f.at(r, c_wy_), wz = f.at(r, c_wz_);
  return 0.5 * (0.4 * m * rad * rad) * (wx * wx + wy * wy + wz * wz);
}

double FrameView::kinetic_energy(const formats::DumpFrame& f, long r) const {
  const double m = f.at(r, c_mass_);
  const double vx = f.at(r, c_vx_), vy = f.at(r, c_vy_), vz = f.at(r, c_vz_);
  return 0.5 * m * (vx * vx + vy * vy + vz * vz) + rotational_energy(f, r);
}

namespace {

// Hertz parameters of every atom-type pair and of every type against the walls, computed once.
class ContactEnergy {
 public:
  explicit ContactEnergy(const model::Stack& stack) : stack_(stack) {
    const auto& spec = stack.spec();
    const auto lib = spec.material_library();
    const auto types = stack.type_materials();
    ntypes_ = types.size();
    y_star_.resize(ntypes_ * ntypes_);
    for (std::size_t a = 0; a < ntypes_; ++a) {
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

  double pair(const model::Sphere& a, const model::Sphere& b, double overlap) const {
    const double y = y_star_[static_cast<std::size_t>(a.atom_type - 1) * ntypes_ + static_cast<std::size_t>(b.atom_type - 1)];
    return model::hertz_elastic_energy(y, a.radius * b.radius / (a.radius + b.radius), overlap);
  }

  // Against every wall the spec has (planes z = 0 and x = -+half_width; a wall has R* = R_i).
  double walls(const model::Sphere& s, double x, double z) const {
    if (wall_y_star_.empty()) return 0.0;
    const auto& spec = stack_.spec();
    const double y = wall_y_star_[static_cast<std::size_t>(s.atom_type - 1)];
    double energy = 0.0;
    auto add = [&](double distance) {
      if (distance < s.radius) energy += model::hertz_elastic_energy(y, s.radius, s.radius - distance);
    };
    if (spec.bottom == model::Boundary::wall) add(std::fabs(z));
    if (spec.sides == model::Boundary::wall) {
      add(std::fabs(x + stack_.half_width()));
      add(std::fabs(x - stack_.half_width()));
    }
    return energy;
  }

 private:
  const model::Stack& stack_;
  std::size_t ntypes_ = 0;
  std::vector<double> y_star_;
  std::vector<double> wall_y_star_;
};

}  // namespace

FrameEnergy frame_energy(const formats::DumpFrame& f, const FrameView& v, const model::Stack& stack) {
  FrameEnergy e;
  e.step = f.step;
  const std::size_t nb = stack.blocks().size();
  e.block_ke.assign(nb, 0.0);
  e.block_ke_sideways.assign(nb, 0.0);
  e.block_ke_downward.assign(nb, 0.0);
  e.block_ke_rotational.assign(nb, 0.0);
  e.row_ke.resize(nb);
  e.column_ke.resize(nb);
  for (std::size_t k = 0; k < nb; ++k) {
    e.row_ke[k].assign(static_cast<std::size_t>(stack.blocks()[k].rows), 0.0);
    e.column_ke[k].assign(static_cast<std::size_t>(stack.blocks()[k].columns), 0.0);
  }
  const int out_id = stack.output_sphere_id();
  const int bottom_first = stack.bottom_row_ids().front();
  const auto& spheres = stack.spheres();
  const std::size_t n = spheres.size();
  std::vector<double> x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& s = spheres[i];
    const long row = v.row(s.id);
    x[i] = f.at(row, v.c_x_);
    y[i] = f.at(row, v.c_y_);
    z[i] = f.at(row, v.c_z_);
    const double ke = v.kinetic_energy(f, row);
    e.kinetic += ke;
    if (s.block == 0) {
      e.striker_ke += ke;
    } else {
      const auto k = static_cast<std::size_t>(s.block - 1);
      const double m = f.at(row, v.c_mass_);
      const double vx = f.at(row, v.c_vx_), vy = f.at(row, v.c_vy_), vz = f.at(row, v.c_vz_);
      const double sideways = 0.5 * m * (vx * vx + vy * vy), downward = 0.5 * m * vz * vz;
      e.block_ke[k] += ke;
      e.block_ke_sideways[k] += sideways;
      e.block_ke_downward[k] += downward;
      e.block_ke_rotational[k] += v.rotational_energy(f, row);
      e.row_ke[k][static_cast<std::size_t>(s.row - 1)] += ke;
      e.column_ke[k][static_cast<std::size_t>(s.column - 1)] += ke;
      if (s.block == 1 && s.row == 1) {
        e.top_row_sideways += sideways;
        e.top_row_downward += downward;
      }
    }
    if (s.id == out_id) e.output_sphere_ke = ke;
    if (s.id >= bottom_first) e.bottom_row_ke += ke;
  }
  const ContactEnergy contacts(stack);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
      const double sum = spheres[i].radius + spheres[j].radius;
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < sum * sum) e.elastic += contacts.pair(spheres[i], spheres[j], sum - std::sqrt(d2));
    }
    e.elastic += contacts.walls(spheres[i], x[i], z[i]);
  }
  return e;
}

double contact_energy(const formats::DumpFrame& f, const FrameView& v, const model::Stack& stack, int id) {
  const ContactEnergy contacts(stack);
  const auto& me = stack.sphere(id);
  const long row = v.row(id);
  const double x = f.at(row, v.c_x_), y = f.at(row, v.c_y_), z = f.at(row, v.c_z_);
  double energy = contacts.walls(me, x, z);
  for (const auto& s : stack.spheres()) {
    if (s.id == id) continue;
    const long r = v.row(s.id);
    const double dx = f.at(r, v.c_x_) - x, dy = f.at(r, v.c_y_) - y, dz = f.at(r, v.c_z_) - z;
    const double sum = me.radius + s.radius;
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < sum * sum) energy += contacts.pair(me, s, sum - std::sqrt(d2));
  }
  return energy;
}

bool has_separated(const formats::DumpFrame& f, const FrameView& v, const model::Stack& stack, int id) {
  const double ke = v.kinetic_energy(f, v.row(id));
  return ke > 0.0 && contact_energy(f, v, stack, id) <= kSeparatedContactEnergy * ke;
}

}  // namespace granstack::postproc
