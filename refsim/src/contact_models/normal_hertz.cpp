// LIGGGHTS's normal model hertz (normal_model_hertz.h): F = 4/3 Y* sqrt(R* d) d, damped with beta(e).
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

// With beta = 0 (e = 1) the damping coefficients are the factor itself (-0.0) whatever the
// square root, so it is not taken.
Normal hertz_normal(const PairConstants& k, const ModelRecord&, const ContactPoint& c, bool tangential_damping,
                    double*) {
  const double reff = c.reff, meff = c.meff, deltan = c.deltan, vn = c.vn;
  const double sqrtval = std::sqrt(reff * deltan);
  const double kt = k.st_factor * sqrtval;
  const double kn = k.kn_factor * sqrtval;
  const bool damped = k.damped();
  const double gamman = damped ? k.damping_factor * std::sqrt(k.sn_factor * sqrtval * meff) : k.damping_factor;
  const double gammat = !tangential_damping ? 0.0 : damped ? k.damping_factor * std::sqrt(kt * meff) : k.damping_factor;
  return {-gamman * vn + kn * deltan, kt, gammat, kn};
}

}  // namespace granstack::refsim::detail
