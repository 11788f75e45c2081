// The one composition of the sub-models (sub_models.hpp), for sphere-sphere contacts
// (contacts.cpp) and walls (walls.cpp), by LIGGGHTS's rules and by LAMMPS's; and the choice of
// sub-models each engine's rules make of the spec's model.
#include "sub_models.hpp"

#include <fmt/format.h>

#include <iterator>
#include <stdexcept>
#include <string>

namespace granstack::refsim::detail {

namespace {
// The rolling models' kernels, by model::RollingModel (none for off): a new rolling model is its
// file in this folder and its line here.
constexpr RollingTorque kRolling[] = {
    nullptr,        // off
    rolling_epsd2,  // epsd2
    rolling_cdt,    // cdt
};
// Each frame's tangential kernels, by model::TangentialModel; none where that engine has no
// counterpart (its row's refusal in model/src/contact_models.cpp says why). A new tangential
// model is its file in this folder and its line in each table.
constexpr TangentialForce kLiggghtsTangential[] = {
    tangential_history,     // history
    tangential_no_history,  // no_history
    nullptr,                // mindlin_rescale: LAMMPS's
};
constexpr TangentialForce kLammpsTangential[] = {
    tangential_mindlin,          // history: LAMMPS's Hertz-Mindlin
    nullptr,                     // no_history: not mapped
    tangential_mindlin_rescale,  // mindlin_rescale
};

TangentialForce tangential_kernel(Frame f, model::TangentialModel m) {
  const auto k = static_cast<std::size_t>(m);
  const auto& table = f == Frame::lammps ? kLammpsTangential : kLiggghtsTangential;
  return k < std::size(table) ? table[k] : nullptr;
}

// The choice `s` runs: every sub-model has its kernel in the frame (a table short of one is a
// defect of this file, not of the spec).
SubModels checked(const SubModels& s) {
  if (tangential_kernel(s.frame, s.tangential) == nullptr) {
    throw std::logic_error(fmt::format("refsim has no kernel for tangential_model = '{}' by {}'s rules "
                                       "(contact_models/composition.cpp)",
                                       model::to_string(s.tangential), s.frame == Frame::lammps ? "LAMMPS" : "LIGGGHTS"));
  }
  if (static_cast<std::size_t>(s.rolling) >= std::size(kRolling)) {
    throw std::logic_error(fmt::format("refsim has no kernel for rolling_model = '{}' (contact_models/composition.cpp)",
                                       model::to_string(s.rolling)));
  }
  return s;
}
}  // namespace

SubModels liggghts_rules(const model::ContactModel& m) {
  if (const auto why = model::liggghts_refusal(m); !why.empty()) {
    throw std::invalid_argument("LIGGGHTS's contact rules (--contact-rules liggghts, the default): " + std::string(why));
  }
  SubModels s;
  s.frame = Frame::liggghts;
  s.normal = m.normal == model::NormalModel::hooke ? NormalKernel::hooke : NormalKernel::hertz;
  s.tangential = m.tangential;
  s.rolling = m.rolling;
  return checked(s);
}

SubModels lammps_rules(const model::ContactModel& m) {
  if (const auto why = model::lammps_refusal(m); !why.empty()) {
    throw std::invalid_argument("--contact-rules lammps: " + std::string(why));
  }
  return checked({Frame::lammps, NormalKernel::hertz_material_tsuji, m.tangential, model::RollingModel::off});
}

PairPoint pair_point(Frame f, const PairTable& t, const ContactStep& s, std::size_t p) {
  return f == Frame::lammps ? lammps_pair_point(t, s, p) : liggghts_pair_point(t, s, p);
}

bool wall_touches(Frame f, double wall_position, double position, double radius) {
  return f == Frame::lammps ? lammps_wall_touches(wall_position, position, radius)
                            : liggghts_wall_gap(wall_position, position, radius) <= 0.0;
}

WallPoint wall_point(Frame f, int axis, double wall_position, double position, double radius, double mass,
                     const double v[3], const double w[3]) {
  return f == Frame::lammps ? lammps_wall_point(axis, wall_position, position, radius, mass, v, w)
                            : liggghts_wall_point(axis, wall_position, position, radius, mass, v, w);
}

void wall_force(Frame f, double fn, const double en[3], const double ft[3], double force[3]) {
  if (f == Frame::lammps) {
    lammps_wall_force(fn, en, ft, force);
  } else {
    liggghts_wall_force(fn, en, ft, force);
  }
}

double kept_wall_force(Frame f, double before, double after, double force) {
  return f == Frame::lammps ? force : after - before;
}

ContactPoint pair_contact_point(const PairGeometry& g, const ContactFrame& f, const ContactStep& s) {
  const PairRecord& rec = *g.rec;
  const std::size_t i = g.i, j = g.j, y = s.stride, z = 2 * s.stride;
  ContactPoint c{};
  for (int d = 0; d < 3; ++d) c.en[d] = f.en[d];
  c.vn = f.vn;
  c.reff = rec.reff;
  c.meff = rec.meff;
  c.rolling_reff = rec.radi * rec.radj / (rec.radi + rec.radj);
  c.wr[0] = s.w[i] - s.w[j];
  c.wr[1] = s.w[y + i] - s.w[y + j];
  c.wr[2] = s.w[z + i] - s.w[z + j];
  c.wall = false;
  return c;
}

namespace {

Normal normal_force(NormalKernel m, const PairConstants& k, const ModelRecord& mr, const ContactPoint& c,
                    bool tangential_damping) {
  switch (m) {
    case NormalKernel::hooke: return hooke_normal(mr, c, tangential_damping);
    case NormalKernel::hertz_material_tsuji: return tsuji_normal(k, mr, c);
    case NormalKernel::hertz: break;
  }
  return hertz_normal(k, c, tangential_damping);
}

}  // namespace

ContactForces contact(const SubModels& m, const PairConstants& k, const ModelRecord& mr, const ContactPoint& c,
                      double shear[kShearHistory], double roll[3], bool update_history, bool tangential_damping,
                      double dt) {
  ContactForces out;
  out.n = normal_force(m.normal, k, mr, c, tangential_damping);
  tangential_kernel(m.frame, m.tangential)(shear, c, out.n, k.friction, update_history, dt, out.ft);
  const double* en = c.en;
  out.tor[0] = en[1] * out.ft[2] - en[2] * out.ft[1];
  out.tor[1] = en[2] * out.ft[0] - en[0] * out.ft[2];
  out.tor[2] = en[0] * out.ft[1] - en[1] * out.ft[0];
  if (const RollingTorque kernel = kRolling[static_cast<std::size_t>(m.rolling)]) {
    out.rolling = true;
    kernel(roll, c, out.n, mr.rolling_friction, update_history, dt, out.rt);
  }
  return out;
}

}  // namespace granstack::refsim::detail
