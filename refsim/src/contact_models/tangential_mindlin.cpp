// LAMMPS's tangential model mindlin (pair_granular.cpp of LAMMPS 29 Sep 2021), which granstack's
// LAMMPS deck sets where a pair has friction, and linear_nohistory 0 0 (no force) where it has
// none. Unlike LIGGGHTS's history spring, the spring is turned into the tangent plane keeping its
// length before the step's displacement is added, it is damped while it sticks, and the Coulomb
// cap resets it to what the capped force needs.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

namespace {
// LAMMPS's EPSILON in pair_granular.cpp: the spring is turned only when its normal part matters.
constexpr double kFrameEpsilon = 1e-10;

double length(const double a[3]) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
}  // namespace

void tangential_mindlin(double* shear, const ContactPoint& c, const Normal& n, double mu,
                        bool update_history, double dt, double ft[3]) {
  ft[0] = ft[1] = ft[2] = 0.0;
  if (mu == 0.0) return;
  const double* nv = c.en;
  const double fscrit = mu * std::fabs(n.fn);
  const double k_t = n.kt, damp_t = n.gammat;
  if (update_history) {
    const double rsht = shear[0] * nv[0] + shear[1] * nv[1] + shear[2] * nv[2];
    if (std::fabs(rsht) * k_t > kFrameEpsilon * fscrit) {
      const double shrmag = length(shear);
      for (int d = 0; d < 3; ++d) shear[d] -= rsht * nv[d];
      const double prjmag = length(shear);
      const double scalefac = prjmag > 0 ? shrmag / prjmag : 0;
      for (int d = 0; d < 3; ++d) shear[d] *= scalefac;
    }
    for (int d = 0; d < 3; ++d) shear[d] += c.vtr[d] * dt;
  }
  for (int d = 0; d < 3; ++d) ft[d] = -k_t * shear[d] - damp_t * c.vtr[d];
  const double f = length(ft);
  if (f > fscrit) {
    if (length(shear) != 0.0) {
      for (int d = 0; d < 3; ++d) shear[d] = -1.0 / k_t * (fscrit * ft[d] / f + damp_t * c.vtr[d]);
      for (int d = 0; d < 3; ++d) ft[d] *= fscrit / f;
    } else {
      ft[0] = ft[1] = ft[2] = 0.0;
    }
  }
}

}  // namespace granstack::refsim::detail
