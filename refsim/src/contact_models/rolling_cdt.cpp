// LIGGGHTS's rolling friction cdt (rolling_model_cdt.h): a constant directional torque.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

// rolling_model_cdt.h's two branches, each in its own order: a wall takes (mu_r F_n) w / |w| R*
// with F_n = delta k_n; a pair scales w by mu_r k_n delta R* / |w|.
void rolling_cdt(double* /*roll: cdt has no history*/, const ContactPoint& c, const Normal& n, double mu_r,
                 bool /*update_history*/, double /*dt*/, double torque[3]) {
  const double* en = c.en;
  const double* wr = c.wr;
  const double deltan = c.deltan, reff = c.rolling_reff;
  const bool wall = c.wall;
  torque[0] = torque[1] = torque[2] = 0.0;
  const double magnitude = std::sqrt(wr[0] * wr[0] + wr[1] * wr[1] + wr[2] * wr[2]);
  if (!(magnitude > 0.)) return;
  if (wall) {
    const double fn = deltan * n.kn;
    for (int d = 0; d < 3; ++d) torque[d] = mu_r * fn * wr[d] / magnitude * reff;
  } else {
    const double scale = mu_r * n.kn * deltan * reff / magnitude;
    for (int d = 0; d < 3; ++d) torque[d] = scale * wr[d];
  }
  // torsionTorque off: the part along the normal goes.
  const double along = torque[0] * en[0] + torque[1] * en[1] + torque[2] * en[2];
  double normal_part[3];
  for (int d = 0; d < 3; ++d) normal_part[d] = en[d] * along;
  for (int d = 0; d < 3; ++d) torque[d] = torque[d] - normal_part[d];
}

}  // namespace granstack::refsim::detail
