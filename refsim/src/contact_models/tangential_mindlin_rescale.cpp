// LAMMPS's tangential model mindlin_rescale (pair_granular.cpp and fix_wall_gran.cpp of LAMMPS 29 Sep
// 2021): mindlin's spring (tangential_mindlin.cpp), whose stored displacement is first multiplied
// by a / a_last when the contact radius a = sqrt(R* d) is below its value at the last history
// update, so that an unloading contact's spring force follows its shrinking area. LAMMPS scales
// before it turns the spring into the tangent plane, at every force call, and records a after it
// adds the step's displacement, at the calls that update the history.
#include "sub_models.hpp"

namespace granstack::refsim::detail {

void tangential_mindlin_rescale(double* shear, const ContactPoint& c, const Normal& n, double mu,
                                bool update_history, double dt, double ft[3]) {
  if (n.a < shear[3]) {
    const double factor = n.a / shear[3];
    for (int d = 0; d < 3; ++d) shear[d] *= factor;
  }
  tangential_mindlin(shear, c, n, mu, update_history, dt, ft);
  if (update_history) shear[3] = n.a;
}

}  // namespace granstack::refsim::detail
