// LIGGGHTS's normal model hooke (normal_model_hooke.h): F = k_n d, damped with gamma_n.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

Normal hooke_normal(const ModelRecord& r, const ContactPoint& c, bool tangential_damping) {
  const double deltan = c.deltan, vn = c.vn;
  const double kn = r.hooke_kn, gamman = r.hooke_gamman;
  const double gammat = tangential_damping ? gamman : 0.0;
  const double fn_damping = -gamman * vn;
  const double fn_contact = kn * deltan;
  return {fn_damping + fn_contact, kn, gammat, kn};
}

}  // namespace granstack::refsim::detail
