// The one composition of LIGGGHTS's sub-models (sub_models.hpp), for sphere-sphere contacts
// (contacts.cpp) and walls (walls.cpp) alike.
#include "sub_models.hpp"

namespace granstack::refsim::detail {

ContactForces liggghts_contact(const model::ContactModel& m, const PairConstants& k, const ModelRecord& mr,
                               const ContactPoint& c, double shear[3], double roll[3], bool update_history,
                               bool tangential_damping, double dt) {
  ContactForces out;
  out.n = m.normal == model::NormalModel::hooke ? hooke_normal(mr, c.deltan, c.vn, tangential_damping)
                                                 : hertz_normal(k, c.reff, c.meff, c.deltan, c.vn, tangential_damping);
  if (m.tangential == model::TangentialModel::no_history) {
    tangential_no_history(c.en, c.vtr, out.n, k.friction, out.ft, out.tor);
  } else {
    tangential_force(shear, c.en, c.vtr, out.n, k.friction, update_history, dt, out.ft, out.tor);
  }
  out.rolling = m.rolling != model::RollingModel::off;
  if (m.rolling == model::RollingModel::epsd2) {
    rolling_torque(roll, c.en, c.wr, out.n, c.rolling_reff, mr.rolling_friction, update_history, dt, out.rt);
  } else if (m.rolling == model::RollingModel::cdt) {
    rolling_cdt(c.en, c.wr, out.n, c.deltan, c.rolling_reff, mr.rolling_friction, c.wall, out.rt);
  }
  return out;
}

}  // namespace granstack::refsim::detail
