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

double FrameView::kinetic_energy(const formats::DumpFrame& f, long r) const {
  const double m = f.at(r, c_mass_);
  const double rad = f.at(r, c_radius_);
  const double vx = f.at(r, c_vx_), vy = f.at(r, c_vy_), vz = f.at(r, c_vz_);
  const double wx = f.at(r, c_wx_), wy = f.at(r, c_wy_), wz = f.at(r, c_wz_);
  return 0.5 * m * (vx * vx + vy * vy + vz * vz) + 0.5 * (0.4 * m * rad * rad) * (wx * wx + wy * wy + wz * wz);
}

namespace {
// Calls fn(i, j, overlap) for every overlapping pair of spheres, by id.
template <typename Fn>
void for_each_overlap(const formats::DumpFrame& f, const FrameView& v, const model::Stack& stack, int cx, int cy, int cz,
                      Fn&& fn) {
  const auto& spheres = stack.spheres();
  const std::size_t n = spheres.size();
  std::vector<double> x(n), y(n), z(n), r(n);
  for (std::size_t i = 0; i < n; ++i) {
    const long row = v.row(static_cast<int>(i) + 1);
    x[i] = f.at(row, cx);
    y[i] = f.at(row, cy);
    z[i] = f.at(row, cz);
    r[i] = spheres[i].radius;
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
      const double sum = r[i] + r[j];
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < sum * sum) fn(i, j, sum - std::sqrt(d2));
    }
  }
}
}  // namespace

FrameEnergy frame_energy(const formats::DumpFrame& f, const FrameView& v, const model::Stack& stack) {
  FrameEnergy e;
  e.step = f.step;
  e.block_ke.assign(stack.blocks().size(), 0.0);
  const int out_id = stack.output_sphere_id();
  const int bottom_first = stack.bottom_row_ids().front();
  for (const auto& s : stack.spheres()) {
    const double ke = v.kinetic_energy(f, v.row(s.id));
    e.kinetic += ke;
    if (s.block == 0) {
      e.striker_ke += ke;
    } else {
      e.block_ke[static_cast<std::size_t>(s.block - 1)] += ke;
    }
    if (s.id == out_id) e.output_sphere_ke = ke;
    if (s.id >= bottom_first) e.bottom_row_ke += ke;
  }

  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  const auto types = stack.type_materials();
  std::vector<const model::Material*> mat;
  for (const auto& t : types) mat.push_back(&lib.at(t));
  auto material_of = [&](std::size_t i) { return mat[static_cast<std::size_t>(stack.spheres()[i].atom_type - 1)]; };
  for_each_overlap(f, v, stack, v.c_x_, v.c_y_, v.c_z_, [&](std::size_t i, std::size_t j, double d) {
    const auto& si = stack.spheres()[i];
    const auto& sj = stack.spheres()[j];
    const double y_star = model::effective_youngs_modulus(*material_of(i), *material_of(j));
    e.elastic += model::hertz_elastic_energy(y_star, si.radius * sj.radius / (si.radius + sj.radius), d);
  });
  if (stack.has_walls()) {
    const auto& wall = lib.at(spec.effective_wall_material());
    for (std::size_t i = 0; i < stack.spheres().size(); ++i) {
      const auto& s = stack.spheres()[i];
      const long row = v.row(s.id);
      const double y_star = model::effective_youngs_modulus(*material_of(i), wall);
      auto add = [&](double gap) {
        if (gap < s.radius) e.elastic += model::hertz_elastic_energy(y_star, s.radius, s.radius - gap);
      };
      if (spec.bottom == model::Boundary::wall) add(std::fabs(f.at(row, v.c_z_)));
      if (spec.sides == model::Boundary::wall) {
        add(std::fabs(f.at(row, v.c_x_) + stack.half_width()));
        add(std::fabs(f.at(row, v.c_x_) - stack.half_width()));
      }
    }
  }
  return e;
}

double contact_energy(const formats::DumpFrame& f, const FrameView& v, const model::Stack& stack, int id) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  const auto types = stack.type_materials();
  auto material = [&](const model::Sphere& s) -> const model::Material& {
    return lib.at(types[static_cast<std::size_t>(s.atom_type - 1)]);
  };
  const auto& me = stack.sphere(id);
  const long row = v.row(id);
  const int cx = f.column("x"), cy = f.column("y"), cz = f.column("z");
  const double x = f.at(row, cx), y = f.at(row, cy), z = f.at(row, cz);
  double energy = 0.0;
  for (const auto& s : stack.spheres()) {
    if (s.id == id) continue;
    const long r = v.row(s.id);
    const double dx = f.at(r, cx) - x, dy = f.at(r, cy) - y, dz = f.at(r, cz) - z;
    const double sum = me.radius + s.radius;
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < sum * sum) {
      energy += model::hertz_elastic_energy(model::effective_youngs_modulus(material(me), material(s)),
                                            me.radius * s.radius / sum, sum - std::sqrt(d2));
    }
  }
  if (stack.has_walls()) {
    const double y_star = model::effective_youngs_modulus(material(me), lib.at(spec.effective_wall_material()));
    auto add = [&](double gap) {
      if (gap < me.radius) energy += model::hertz_elastic_energy(y_star, me.radius, me.radius - gap);
    };
    if (spec.bottom == model::Boundary::wall) add(std::fabs(z));
    if (spec.sides == model::Boundary::wall) {
      add(std::fabs(x + stack.half_width()));
      add(std::fabs(x - stack.half_width()));
    }
  }
  return energy;
}

bool has_separated(const formats::DumpFrame& f, const FrameView& v, const model::Stack& stack, int id) {
  const double ke = v.kinetic_energy(f, v.row(id));
  return ke > 0.0 && contact_energy(f, v, stack, id) <= kSeparatedContactEnergy * ke;
}

}  // namespace granstack::postproc
