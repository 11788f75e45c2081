// LIGGGHTS's tangential model no_history (tangential_model_no_history.h): viscous, capped by Coulomb.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

void tangential_no_history(double*, const ContactPoint& c, const Normal& n, double mu, bool, double,
                           double ft[3]) {
  const double* vtr = c.vtr;
  const double vrel = std::sqrt(vtr[0] * vtr[0] + vtr[1] * vtr[1] + vtr[2] * vtr[2]);
  const double ft_friction = mu * std::fabs(n.fn);
  const double gamma = ft_friction < n.gammat * vrel ? ft_friction / vrel : n.gammat;
  for (int d = 0; d < 3; ++d) ft[d] = -gamma * vtr[d];
}

}  // namespace granstack::refsim::detail
