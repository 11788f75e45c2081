#pragma once
// LIGGGHTS's contact sub-models, each a scalar kernel in a file of its own in this folder, and
// the one composition of them that both LIGGGHTS's pair style and its fix wall/gran apply
// (liggghts_composition.cpp): a normal model (hertz | hooke) gives the normal force and the
// tangential stiffness and damping; a tangential model (history | no_history) the tangential
// force; a rolling model (off | epsd2 | cdt) a torque. Each performs LIGGGHTS's floating-point
// operations in its order (refsim agrees with it to the bit). LAMMPS's rules are
// lammps_rules.cpp's, in this folder too.
#include "../contacts.hpp"

#include <granstack/model/contact.hpp>

namespace granstack::refsim::detail {

// The Hertz normal force with restitution damping, and the tangential stiffness and damping
// (normal_model_hertz.h); shared by the pair kernel and the walls.
struct Normal {
  double fn, kt, gammat;
  double kn;  // the normal stiffness (cdt's torque is mu_r R* k_n delta)
};
Normal hertz_normal(const PairConstants& k, double reff, double meff, double deltan, double vn, bool tangential_damping);
// The Hooke normal force (normal_model_hooke.h): k_n and gamma_n of the pair, k_t = k_n.
Normal hooke_normal(const ModelRecord& r, double deltan, double vn, bool tangential_damping);

// The viscous tangential force of tangential no_history (tangential_model_no_history.h): no
// spring, gamma_t capped so that |F_t| <= mu |F_n|. Outputs as tangential_force.
void tangential_no_history(const double en[3], const double vtr[3], const Normal& n, double mu, double ft[3],
                           double tor[3]);

// epsd2's rolling torque (rolling_model_epsd2.h, torsionTorque off): the relative rotation's
// tangential part `wr` drives a spring of stiffness k_t R*^2 on the history `roll`, capped at
// mu_r R* |F_n|. The torque on the first body is minus `torque`, on the second plus.
void rolling_torque(double roll[3], const double en[3], const double wr[3], const Normal& n, double reff, double mu_r,
                    bool update_history, double dt, double torque[3]);

// The tangential history spring (tangential_model_history.h): increment by the sliding velocity,
// project on the tangent plane, Coulomb-truncate (no damping while sliding). Returns the
// tangential force on the first body in `ft` and n x Ft in `tor` (the torque on each body is
// minus its lever arm times it).
void tangential_force(double shear[3], const double en[3], const double vtr[3], const Normal& n, double mu,
                      bool update_history, double dt, double ft[3], double tor[3]);

// cdt's rolling torque (rolling_model_cdt.h, torsionTorque off): mu_r R* k_n delta along the
// rotation `wr` (none while it is zero), less its part along the normal; no history. The torque
// on the first body is minus `torque`, on the second plus. LIGGGHTS forms it in two orders, a
// wall's and a pair's (`wall`).
void rolling_cdt(const double en[3], const double wr[3], const Normal& n, double deltan, double reff, double mu_r,
                 bool wall, double torque[3]);

// One touching contact as both LIGGGHTS's pair style and fix wall/gran see it: the unit normal
// towards the first body, its normal speed, the tangential speed at the contact point, the
// overlap, the normal model's R* and m*, and the rolling model's R* and the rotation it turns (the
// pair's relative rotation, a wall's contact-point rotation).
struct ContactPoint {
  double en[3];
  double vn;
  double vtr[3];
  double deltan;
  double reff, meff;
  double rolling_reff;
  double wr[3];
  bool wall;  // a sphere on a wall (cdt's order differs)
};
// What the composition gives the first body: the normal part, the tangential force and n x Ft
// (the torque on each body is minus its lever arm times it), and the rolling torque (minus it on
// the first body, plus on the second; `rolling` false and zero without a rolling model).
struct ContactForces {
  Normal n;
  double ft[3], tor[3];
  bool rolling = false;
  double rt[3] = {0.0, 0.0, 0.0};
};
// The contact's sub-models by `m`, composed in LIGGGHTS's order, with the contact's tangential
// (shear) and rolling (roll) histories, updated when `update_history`.
ContactForces liggghts_contact(const model::ContactModel& m, const PairConstants& k, const ModelRecord& mr,
                               const ContactPoint& c, double shear[3], double roll[3], bool update_history,
                               bool tangential_damping, double dt);

}  // namespace granstack::refsim::detail
