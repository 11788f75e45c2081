// LAMMPS's normal model hertz/material with tsuji damping (pair_granular.cpp, fix_wall_gran.cpp of
// LAMMPS 29 Sep 2021, as granstack's LAMMPS deck sets them: model/lammps.hpp): the elastic force
// E* sqrt(R* d) d with E* = 4/3 Y* (a wall's E* as fix wall/gran forms it: model/lammps.hpp gives
// the E' for it), the damping alpha(e') sqrt(m* E* sqrt(R* d)) (tsuji's alpha of the mapped e', 0
// undamped), and mindlin's stiffness 8 G* sqrt(R* d) and damping eta_t / eta_n times eta_n.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

// pair_granular forms the elastic force as (E delta) a, fix wall/gran as (E a) delta.
Normal tsuji_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool, double*) {
  const double delta = c.deltan;
  const double dr = delta * c.reff;
  double knfac = k.kn_factor;
  double fne = knfac * delta;
  const double a = std::sqrt(dr);
  fne *= a;
  knfac *= a;
  if (c.wall) fne = knfac * delta;
  // tsuji: alpha sqrt(m* knfac); undamped is viscoelastic with coefficient 0.
  const double damp_normal = r.law[0] != 0.0 ? std::sqrt(c.meff * knfac) : a * c.meff;
  const double prefactor = r.law[0] * damp_normal;
  const double fdamp = -prefactor * c.vn;
  return {fne + fdamp, k.st_factor * a, r.law[1] * prefactor, knfac, a};
}

}  // namespace granstack::refsim::detail

namespace granstack::refsim::detail {

// The coefficients granstack's LAMMPS deck gives (model/lammps.hpp): tsuji's alpha of the e' that
// matches LIGGGHTS's damping of e (0 undamped), and eta_t / eta_n = sqrt(4 G* / Y*).
void tsuji_record(const ModelConstants& k, double, double, double, ModelRecord& r) {
  r.law[0] = k.lammps_alpha;
  r.law[1] = k.lammps_tangential_ratio;
}

void tsuji_constants(double restitution, double g_star, double y_star, ModelConstants& k) {
  k.lammps_alpha = restitution < 1.0 ? model::tsuji_alpha(model::lammps_tsuji_restitution(restitution)) : 0.0;
  k.lammps_tangential_ratio = std::sqrt(4.0 * g_star / y_star);
}

}  // namespace granstack::refsim::detail
