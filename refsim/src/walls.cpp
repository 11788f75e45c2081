// refsim's walls and gravity: each particle against the planar walls near it, by LIGGGHTS's
// fix wall/gran (or LAMMPS's rules), then gravity: the post_force fixes that follow the pair style.
#include <granstack/refsim/system.hpp>

#include "contacts.hpp"
#include "contact_models/sub_models.hpp"

#include <granstack/model/contact.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace granstack::refsim {

namespace {
// A sphere's gap to a plane wall, negative where they overlap (primitive_wall_definitions.h).
double wall_gap(const Wall& wall, double pos, double radius) {
  return pos > wall.position ? pos - wall.position - radius : wall.position - pos - radius;
}
}  // namespace

void System::wall_force(std::size_t i, std::size_t wi, bool update_history) {
  const Wall& wall = p_.walls[wi];
  const int a = wall.axis;
  const double radi = radius_[i];
  const double pos = x_[static_cast<std::size_t>(a) * stride_ + i];
  double* shear = &wall_history_[3 * (wi * n_ + i)];
  double* roll = &wall_roll_[3 * (wi * n_ + i)];
  // Vector from the centre to the plane, and the gap (primitive_wall_definitions.h).
  double delta[3] = {0., 0., 0.};
  delta[a] = wall.position - pos;
  const double gap = wall_gap(wall, pos, radi);
  wall_touched_[wi * n_ + i] = gap <= 0.0;
  const bool stored = static_cast<int>(wi) == p_.stored_wall;
  if (stored) wall_store_[3 * i] = wall_store_[3 * i + 1] = wall_store_[3 * i + 2] = 0.0;
  if (p_.lammps_rules) {
    wall_force_lammps_rules(i, wi, update_history);
    return;
  }
  if (!(gap <= 0.0)) {  // not touching: a wall's history never survives a separation
    shear[0] = shear[1] = shear[2] = 0.0;
    roll[0] = roll[1] = roll[2] = 0.0;
    return;
  }
  const double overlap_in = -gap;
  const double dx = -delta[0], dy = -delta[1], dz = -delta[2];  // from the wall to the centre
  const double r = radi - overlap_in;
  const double rinv = 1.0 / r;
  const double enx = dx * rinv, eny = dy * rinv, enz = dz * rinv;
  const double meff = mass_[i];

  const Vec3 v = this->v(i), w = omega(i);
  const double vr1 = v[0] - 0.0, vr2 = v[1] - 0.0, vr3 = v[2] - 0.0;
  const double vn = vr1 * enx + vr2 * eny + vr3 * enz;
  const double vt1 = vr1 - vn * enx, vt2 = vr2 - vn * eny, vt3 = vr3 - vn * enz;
  const double deltan = radi - r;
  const double cr = radi - 0.5 * overlap_in;
  const double wr1 = cr * w[0] * rinv, wr2 = cr * w[1] * rinv, wr3 = cr * w[2] * rinv;
  const std::size_t type_pair = static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                static_cast<std::size_t>(wall.type - 1);
  // A wall has R* = R_i and m* = m_i; a rolling model on a wall turns the contact point's rotation speed,
  // wr = cr omega / r, not omega.
  const detail::ContactPoint c{{enx, eny, enz},
                               vn,
                               {vt1 - (dz * wr2 - dy * wr3), vt2 - (dx * wr3 - dz * wr1), vt3 - (dy * wr1 - dx * wr2)},
                               deltan,
                               radi,
                               meff,
                               radi,
                               {wr1, wr2, wr3},
                               true};
  const auto model = detail::model_record(p_.contact, model_constants_[type_pair], radi, meff);
  const detail::ContactForces out = detail::liggghts_contact(p_.contact, type_constants_[type_pair], model, c, shear, roll,
                                                             update_history, p_.tangential_damping, p_.dt);
  const double fn = out.n.fn;
  double df[3] = {0.0 + fn * 1. * enx, 0.0 + fn * 1. * eny, 0.0 + fn * 1. * enz};  // * area_ratio (1)
  for (std::size_t d = 0; d < 3; ++d) df[d] += out.ft[d] * 1.;
  for (std::size_t d = 0; d < 3; ++d) {
    const double before = f_[d * stride_ + i];
    f_[d * stride_ + i] += df[d];
    if (stored) wall_store_[3 * i + d] = f_[d * stride_ + i] - before;
    double dt = 0.0 + -cr * out.tor[d] * 1.;
    if (out.rolling) dt -= out.rt[d];
    t_[d * stride_ + i] += dt;
  }
}

void System::wall_force_lammps_rules(std::size_t i, std::size_t wi, bool update_history) {
  const Wall& wall = p_.walls[wi];
  const std::size_t type_pair = static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                static_cast<std::size_t>(wall.type - 1);
  const double pos = x_[static_cast<std::size_t>(wall.axis) * stride_ + i];
  const Vec3 v = this->v(i), w = omega(i);
  const auto record = detail::model_record(p_.contact, model_constants_[type_pair], radius_[i], mass_[i]);
  double force[3], torque[3];
  if (!detail::wall_force_lammps(wall.axis, pos - wall.position, radius_[i], mass_[i], v.data(), w.data(),
                                 type_constants_[type_pair], record, &wall_history_[3 * (wi * n_ + i)], update_history,
                                 p_.dt, force, torque)) {
    return;
  }
  const bool stored = static_cast<int>(wi) == p_.stored_wall;
  for (std::size_t d = 0; d < 3; ++d) {
    f_[d * stride_ + i] += force[d];
    if (stored) wall_store_[3 * i + d] = force[d];
    t_[d * stride_ + i] += torque[d];
  }
}

// The particles that may touch each wall before the next build (wall_near_): those touching it
// at their last force call, and those within a skin of it now.
void System::find_wall_candidates() {
  wall_near_.assign(p_.walls.size(), {});
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    const double* pos = x_.data() + static_cast<std::size_t>(p_.walls[w].axis) * stride_;
    for (std::size_t i = 0; i < n_; ++i) {
      // Within a skin: twice the half skin a particle may move, for a margin far above rounding.
      if (wall_touched_[w * n_ + i] != 0 || wall_gap(p_.walls[w], pos[i], radius_[i]) <= p_.skin) {
        wall_near_[w].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
}

// Each particle of [begin, end) in turn meets the walls, then gravity (each particle's sums in the
// deck's order: walls by number, then gravity). Of the particles that may touch a wall, those
// neither touching it now nor at their last call have nothing to compute or clear there.
void System::external_forces(std::size_t begin, std::size_t end, bool update_history) {
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    if (p_.lammps_rules) {  // LAMMPS's rules: every particle, as wall_force_lammps_rules decides
      for (std::size_t i = begin; i < end; ++i) wall_force(i, w, update_history);
      continue;
    }
    const Wall wall = p_.walls[w];
    const double* pos = x_.data() + static_cast<std::size_t>(wall.axis) * stride_;
    const auto& near = wall_near_[w];
    auto k = std::lower_bound(near.begin(), near.end(), static_cast<std::uint32_t>(begin));
    for (; k != near.end() && *k < end; ++k) {
      if (wall_touched_[w * n_ + *k] != 0 || wall_gap(wall, pos[*k], radius_[*k]) <= 0.0) wall_force(*k, w, update_history);
    }
  }
  if (p_.gravity[0] != 0.0 || p_.gravity[1] != 0.0 || p_.gravity[2] != 0.0) {
    for (std::size_t i = begin; i < end; ++i) {
      const double m = mass_[i] * 1.;
      for (std::size_t d = 0; d < 3; ++d) f_[d * stride_ + i] += m * p_.gravity[d];
    }
  }
}

}  // namespace granstack::refsim
