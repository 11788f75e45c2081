// LIGGGHTS's tangential model history (tangential_model_history.h): a spring capped by Coulomb.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

void tangential_history(double* shear, const ContactPoint& c, const Normal& n, double mu,
                        bool update_history, double dt, double ft[3]) {
  const double* en = c.en;
  const double* vtr = c.vtr;
  if (update_history) {
    shear[0] += vtr[0] * dt;
    shear[1] += vtr[1] * dt;
    shear[2] += vtr[2] * dt;
    const double rsht = shear[0] * en[0] + shear[1] * en[1] + shear[2] * en[2];
    shear[0] -= rsht * en[0];
    shear[1] -= rsht * en[1];
    shear[2] -= rsht * en[2];
  }
  const double kt = n.kt;
  const double shear_sq = shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2];
  ft[0] = -(kt * shear[0]);
  ft[1] = -(kt * shear[1]);
  ft[2] = -(kt * shear[2]);
  if (mu == 0.0 && kt > 0.0 && shear_sq > 0.0) {
    // Frictionless: LIGGGHTS slides with ratio 0 / (kt |xi|), leaving a zero force and a zero
    // history; the same without the square root and the four divisions (only signs of zero differ).
    ft[0] = ft[1] = ft[2] = 0.0;
    if (update_history) shear[0] = shear[1] = shear[2] = 0.0;
  } else {
    const double shrmag = std::sqrt(shear_sq);
    const double ft_shear = kt * shrmag;
    const double ft_friction = mu * std::fabs(n.fn);
    if (ft_shear > ft_friction) {
      if (shrmag != 0.0) {
        const double ratio = ft_friction / ft_shear;
        for (int d = 0; d < 3; ++d) ft[d] *= ratio;
        if (update_history) {
          for (int d = 0; d < 3; ++d) shear[d] = -ft[d] / kt;
        }
      } else {
        ft[0] = ft[1] = ft[2] = 0.0;
      }
    } else {
      for (int d = 0; d < 3; ++d) ft[d] -= n.gammat * vtr[d];
    }
  }
}

}  // namespace granstack::refsim::detail
