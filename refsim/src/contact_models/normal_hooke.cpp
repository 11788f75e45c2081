// LIGGGHTS's normal model hooke (normal_model_hooke.h): F = k_n d, damped with gamma_n.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

Normal hooke_normal(const PairConstants&, const ModelRecord& r, const ContactPoint& c, bool tangential_damping,
                    double*) {
  const double deltan = c.deltan, vn = c.vn;
  const double kn = r.law[0], gamman = r.law[1];  // hooke_record's
  const double gammat = tangential_damping ? gamman : 0.0;
  const double fn_damping = -gamman * vn;
  const double fn_contact = kn * deltan;
  return {fn_damping + fn_contact, kn, gammat, kn};
}

}  // namespace granstack::refsim::detail

namespace granstack::refsim::detail {

// The pair's spring and damping, as LIGGGHTS forms them in every contact: k_n calibrated at the
// characteristic velocity (model::hooke_stiffness), gamma_n = sqrt(4 m* k_n ln(e)^2 / (ln(e)^2 + pi^2)).
void hooke_record(const ModelConstants& k, double, double reff, double meff, ModelRecord& r) {
  r.law[0] = model::hooke_stiffness({k.y_star, 0.0, reff, meff}, k.characteristic_velocity);
  const double log_sq = k.restitution_log * k.restitution_log;
  r.law[1] = std::sqrt(4. * meff * r.law[0] * log_sq / (log_sq + M_PI * M_PI));
}

}  // namespace granstack::refsim::detail
