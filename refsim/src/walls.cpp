// refsim's walls and gravity: each particle against the planar walls near it, by the engine's
// fix wall/gran (the contact composed of the sub-models its rules choose: contact_models/), then
// gravity: the post_force fixes that follow the pair style.
#include <granstack/refsim/system.hpp>

#include "contacts.hpp"
#include "contact_models/sub_models.hpp"

#include <granstack/model/contact.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace granstack::refsim {

// Sphere i against wall wi, the contact composed of the table's sub-models: the force and
// torque added to i's sums, and the stored wall's force on i kept.
void System::wall_force(std::size_t i, std::size_t wi, bool update_history) {
  const Wall& wall = p_.walls[wi];
  const detail::SubModels& rules = pairs_->sub_models;
  Vec3 v = this->v(i);
  const Vec3 w = omega(i);
  // Against the plate, the sphere's velocity relative to it (the mesh's node velocity, which
  // LIGGGHTS subtracts from the sphere's).
  if (static_cast<int>(wi) == p_.plate.wall) v[2] = v[2] - plate_v_;
  const detail::WallPoint point = detail::wall_point(rules.frame, wall.axis, wall_position(wi),
                                                     x_[static_cast<std::size_t>(wall.axis) * stride_ + i], radius_[i],
                                                     mass_[i], v.data(), w.data());
  const std::size_t slots = detail::history_layout(rules).size;
  double* history = wall_history_.data() + slots * (wi * n_ + i);
  const bool touched = wall_touched_[wi * n_ + i] != 0;
  wall_touched_[wi * n_ + i] = point.touching;
  const bool stored = static_cast<int>(wi) == p_.stored_wall;
  if (stored) wall_store_[3 * i] = wall_store_[3 * i + 1] = wall_store_[3 * i + 2] = 0.0;
  if (!point.touching) {  // a wall's history never survives a separation
    if (touched && !banked_.empty()) detail::bank_work(banked_.data(), i, wall_contact_energy(i, wi, 0.0).dissipated);
    std::fill(history, history + slots, 0.0);
    return;
  }
  const detail::ContactPoint& c = point.c;
  const std::size_t type_pair = wall_type_pair(i, wi);
  const auto model = detail::model_record(rules, model_constants_[type_pair], radius_[i], c.reff, c.meff);
  const detail::ContactForces out = detail::contact(rules, type_constants_[type_pair], model, c, history,
                                                    update_history, p_.tangential_damping, p_.dt);
  double df[3];
  detail::wall_force(rules.frame, out.n.fn, c.en, out.ft, df);
  for (std::size_t d = 0; d < 3; ++d) {
    const double before = f_[d * stride_ + i];
    f_[d * stride_ + i] += df[d];
    if (stored) wall_store_[3 * i + d] = detail::kept_wall_force(rules.frame, before, f_[d * stride_ + i], df[d]);
    double dt = 0.0 + -c.arm_i * out.tor[d] * 1.;
    if (out.rolling) dt -= out.rt[d];
    t_[d * stride_ + i] += dt;
  }
}

std::size_t System::wall_type_pair(std::size_t i, std::size_t wi) const {
  return static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
         static_cast<std::size_t>(p_.walls[wi].type - 1);
}

// A wall contact's R* is the sphere's radius and its m* the sphere's mass (fix wall/gran).
detail::ContactEnergy System::wall_contact_energy(std::size_t i, std::size_t wi, double overlap) const {
  const detail::SubModels& rules = pairs_->sub_models;
  const auto model = detail::model_record(rules, model_constants_[wall_type_pair(i, wi)], radius_[i], radius_[i], mass_[i]);
  const std::size_t slots = detail::history_layout(rules).size;
  return detail::contact_energy(rules, model, overlap, wall_history_.data() + slots * (wi * n_ + i));
}

// The particles that may touch each wall before the next build (wall_near_): those touching it
// at their last force call, and those within a skin of it now.
void System::find_wall_candidates() {
  wall_near_.assign(p_.walls.size(), {});
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    const double* pos = x_.data() + static_cast<std::size_t>(p_.walls[w].axis) * stride_;
    for (std::size_t i = 0; i < n_; ++i) {
      // Within a skin: twice the half skin a particle may move, for a margin far above rounding.
      if (wall_touched_[w * n_ + i] != 0 || detail::liggghts_wall_gap(wall_position(w), pos[i], radius_[i]) <= p_.skin) {
        wall_near_[w].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
}

// Each particle of [begin, end) in turn meets the walls, then gravity (each particle's sums in the
// deck's order: walls by number, then gravity). Of the particles that may touch a wall, those
// neither touching it now nor at their last call have nothing to compute or clear there.
void System::external_forces(std::size_t begin, std::size_t end, bool update_history) {
  const detail::Frame frame = pairs_->sub_models.frame;
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    const Wall wall = p_.walls[w];
    const double* pos = x_.data() + static_cast<std::size_t>(wall.axis) * stride_;
    const auto& near = wall_near_[w];
    auto k = std::lower_bound(near.begin(), near.end(), static_cast<std::uint32_t>(begin));
    for (; k != near.end() && *k < end; ++k) {
      if (wall_touched_[w * n_ + *k] != 0 || detail::wall_touches(frame, wall_position(w), pos[*k], radius_[*k])) {
        wall_force(*k, w, update_history);
      }
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
