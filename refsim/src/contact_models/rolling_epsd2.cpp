// LIGGGHTS's rolling friction epsd2 (rolling_model_epsd2.h): an elastic-plastic torque spring.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

void rolling_epsd2(double* roll, const ContactPoint& c, const Normal& n, double mu_r, bool update_history, double dt,
                   double torque[3]) {
  const double* en = c.en;
  const double* wr = c.wr;
  const double reff = c.rolling_reff;
  const double wr_dot_delta = wr[0] * en[0] + wr[1] * en[1] + wr[2] * en[2];
  const double kr = n.kt * reff * reff;
  const double scale = dt * kr;
  for (int d = 0; d < 3; ++d) {
    const double wr_tot = wr[d] - en[d] * wr_dot_delta;
    torque[d] = roll[d] + scale * wr_tot;
  }
  const double magnitude = std::sqrt(torque[0] * torque[0] + torque[1] * torque[1] + torque[2] * torque[2]);
  const double most = std::fabs(n.fn) * reff * mu_r;
  if (magnitude > most) {
    const double factor = most / magnitude;
    for (int d = 0; d < 3; ++d) torque[d] *= factor;
  }
  if (update_history) {
    for (int d = 0; d < 3; ++d) roll[d] = torque[d];
  }
}

}  // namespace granstack::refsim::detail
