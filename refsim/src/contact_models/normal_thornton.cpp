// Thornton (1997)'s elastic-perfectly-plastic normal contact (model::thornton_force): the force a
// function of the overlap and the largest overlap so far, evaluated exactly at every step (no
// incremental update, so no error of the time step in the law itself); no viscous damping. The
// tangential stiffness is Mindlin's of the Hertz radius, 8 G* sqrt(R* d), as LIGGGHTS's laws take
// it, and the tangential damping is off (restitution 1: the law dissipates by yielding).
#include "sub_models.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace granstack::refsim::detail {

void thornton_record(const ModelConstants& k, double, double reff, double meff, ModelRecord& r) {
  const auto l = model::thornton_law({k.y_star, 0.0, reff, meff}, k.yield_pressure);
  const double values[] = {l.y_star, l.r_star, l.yield_pressure, l.yield_overlap, l.yield_force, l.slope};
  static_assert(std::size(values) <= kLawValues);
  std::copy(std::begin(values), std::end(values), r.law);
}

namespace {
model::ThorntonLaw law_of(const ModelRecord& r) { return {r.law[0], r.law[1], r.law[2], r.law[3], r.law[4], r.law[5]}; }
}  // namespace

ContactEnergy thornton_energy(const ModelRecord& r, double overlap, const double* history) {
  const auto state = model::thornton_state(law_of(r), overlap, history[0]);
  return {state.elastic, state.dissipated};
}

Normal thornton_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool, double* history) {
  const double d = c.deltan;
  if (d > history[0]) history[0] = d;
  const model::ThorntonLaw law = law_of(r);
  const double fn = model::thornton_force(law, d, history[0]);
  const double sqrtval = std::sqrt(c.reff * d);
  // The local stiffness of the loading branch (cdt's k_n delta): Hertz's 2 E* a, or pi p_y R*.
  const double kn = history[0] > law.yield_overlap ? law.slope : 2.0 * law.y_star * sqrtval;
  return {fn, k.st_factor * sqrtval, 0.0, kn};
}

}  // namespace granstack::refsim::detail
