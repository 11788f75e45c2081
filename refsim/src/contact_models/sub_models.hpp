#pragma once
// The contact sub-models (choice.hpp), each a scalar kernel in a file of its own in this folder,
// and the one composition of them (composition.cpp) that every contact takes: sphere-sphere
// (contacts.cpp) and sphere-wall (walls.cpp), by LIGGGHTS's rules or by LAMMPS's. A frame forms
// the contact's geometry; a normal model gives the normal force and the tangential stiffness and
// damping; a tangential model the tangential force; a rolling model a torque. Each kernel
// performs its engine's floating-point operations in its order (refsim agrees with LIGGGHTS to
// the bit, with LAMMPS to round-off).
#include "../contacts.hpp"
#include "choice.hpp"

namespace granstack::refsim::detail {

// One touching contact as the frame forms it: the unit normal towards the first body, its normal
// speed, the tangential speed at the contact point, the overlap, the normal model's R* and m*,
// the rolling model's R* and the rotation it turns (the pair's relative rotation, a wall's
// contact-point rotation), whether the second body is a wall, and the lever arms that turn the
// tangential force into each body's torque (arm_j unused on a wall).
struct ContactPoint {
  double en[3];
  double vn;
  double vtr[3];
  double deltan;
  double reff, meff;
  double rolling_reff;
  double wr[3];
  bool wall;
  double arm_i, arm_j;
};

// The frame of pair p of the table, touching or not; `forget`: not touching, and near enough
// that the engine forgets the pair's history.
struct PairPoint {
  bool touching, forget;
  ContactPoint c;
};
// A sphere (radius, mass, velocity, angular velocity) at `position` along the axis of a plane
// wall at `wall_position`: whether they touch by the frame's test, and if so their frame.
struct WallPoint {
  bool touching;
  ContactPoint c;
};
// Each frame's (frame_liggghts.cpp, frame_lammps.cpp), and the frame's by `f` (composition.cpp):
PairPoint pair_point(Frame f, const PairTable& t, const ContactStep& s, std::size_t p);
bool wall_touches(Frame f, double wall_position, double position, double radius);
WallPoint wall_point(Frame f, int axis, double wall_position, double position, double radius, double mass,
                     const double v[3], const double w[3]);
// The force the wall gives the sphere, as the frame's fix forms it from the normal force along
// the normal and the tangential force.
void wall_force(Frame f, double fn, const double en[3], const double ft[3], double force[3]);
// The force kept for the stored wall, from the sphere's force before and after the wall's.
double kept_wall_force(Frame f, double before, double after, double force);

// What both frames take alike of a pair whose spheres touch (radii sum above their distance):
// the normal, the normal speed, R*, m*, the rolling model's R* and the relative rotation omega_i -
// omega_j; the frame adds the sliding velocity, the overlap and the lever arms.
ContactPoint pair_contact_point(const PairGeometry& g, const ContactFrame& f, const ContactStep& s);
inline bool spheres_touch(const PairGeometry& g) {
  const double radsum = g.rec->radi + g.rec->radj;
  return g.rsq < radsum * radsum;
}
PairPoint liggghts_pair_point(const PairTable& t, const ContactStep& s, std::size_t p);
double liggghts_wall_gap(double wall_position, double position, double radius);  // negative: overlapping
WallPoint liggghts_wall_point(int axis, double wall_position, double position, double radius, double mass,
                              const double v[3], const double w[3]);
void liggghts_wall_force(double fn, const double en[3], const double ft[3], double force[3]);
PairPoint lammps_pair_point(const PairTable& t, const ContactStep& s, std::size_t p);
bool lammps_wall_touches(double wall_position, double position, double radius);
WallPoint lammps_wall_point(int axis, double wall_position, double position, double radius, double mass,
                            const double v[3], const double w[3]);
void lammps_wall_force(double fn, const double en[3], const double ft[3], double force[3]);

// What a normal model gives: the normal force (elastic and damping), the tangential stiffness
// and damping for the tangential model, and the normal stiffness (cdt's torque is mu_r R* k_n delta).
struct Normal {
  double fn, kt, gammat;
  double kn;
  double a = 0.0;  // the contact radius sqrt(R* d), where the model forms it (LAMMPS's hertz/material)
};
// A normal model's kernel: the normal force and what it sets for the tangential model, from the
// type pair's constants, the pair's record, the contact and its own history (the values it
// declares, kept from the contact's last evaluation; it updates them at every evaluation, as
// LIGGGHTS's normal models write theirs whatever shearupdate says). Every normal kernel has this
// form; its per-pair record (NormalRecord) is computed once per distinct pair.
using NormalForce = Normal (*)(const PairConstants& k, const ModelRecord& r, const ContactPoint& c,
                               bool tangential_damping, double* history);
using NormalRecord = void (*)(const ModelConstants& k, double radi, double reff, double meff, ModelRecord& r);
// The normal models' kernels and records are declared beside their table (composition.cpp);
// thornton_ning keeps LIGGGHTS's ten history values:
inline constexpr std::size_t kThorntonNingHistory = 10;
// LAMMPS's tsuji coefficients of the type pair's restitution, and mindlin's eta_t / eta_n:
void tsuji_constants(double restitution, double g_star, double y_star, ModelConstants& k);

// The tangential force on the first body, `ft`, from the contact, the normal model's output and
// the friction coefficient, with the contact's tangential history `shear` (updated when
// `update_history`; a model without history leaves it alone). Every tangential model's kernel
// has this form.
using TangentialForce = void (*)(double* shear, const ContactPoint& c, const Normal& n, double mu,
                                 bool update_history, double dt, double ft[3]);
// LIGGGHTS's history spring (tangential_model_history.h): increment by the sliding velocity,
// project on the tangent plane, Coulomb-truncate (no damping while sliding).
void tangential_history(double* shear, const ContactPoint& c, const Normal& n, double mu,
                        bool update_history, double dt, double ft[3]);
// LIGGGHTS's no_history (tangential_model_no_history.h): viscous, no spring, gamma_t capped so
// that |F_t| <= mu |F_n|.
void tangential_no_history(double* shear, const ContactPoint& c, const Normal& n, double mu,
                           bool update_history, double dt, double ft[3]);
// LAMMPS's mindlin, or its linear_nohistory 0 0 (no force) where mu = 0.
void tangential_mindlin(double* shear, const ContactPoint& c, const Normal& n, double mu,
                        bool update_history, double dt, double ft[3]);
// LAMMPS's mindlin_rescale: mindlin, its displacement first scaled by a / a_last where the
// contact radius a has shrunk since the last update; shear[3] holds a_last (0 at first touch).
void tangential_mindlin_rescale(double* shear, const ContactPoint& c, const Normal& n, double mu,
                                bool update_history, double dt, double ft[3]);
// How many history values each tangential kernel keeps.
inline constexpr std::size_t kTangentialHistory = 3;       // history and mindlin: the displacement
inline constexpr std::size_t kMindlinRescaleHistory = 4;   // ... and the contact radius at the last update

// The rolling torque: minus `torque` on the first body, plus on the second, from the contact, the
// normal model's output, mu_r and the rolling history `roll` (updated when `update_history`; a
// model without history leaves it alone). Every rolling model's kernel has this form.
using RollingTorque = void (*)(double* roll, const ContactPoint& c, const Normal& n, double mu_r, bool update_history,
                               double dt, double torque[3]);
// epsd2 (rolling_model_epsd2.h, torsionTorque off): the rotation's tangential part drives a
// spring of stiffness k_t R*^2 on the history `roll`, capped at mu_r R* |F_n|.
void rolling_epsd2(double* roll, const ContactPoint& c, const Normal& n, double mu_r, bool update_history, double dt,
                   double torque[3]);
// cdt (rolling_model_cdt.h, torsionTorque off): mu_r R* k_n delta along the rotation (none while
// it is zero), less its part along the normal; no history. LIGGGHTS forms it in two orders, a
// wall's and a pair's.
void rolling_cdt(double* roll, const ContactPoint& c, const Normal& n, double mu_r, bool update_history, double dt,
                 double torque[3]);

// What the composition gives the first body: the normal part, the tangential force and n x Ft
// (the torque on each body is minus its lever arm times it), and the rolling torque (minus it on
// the first body, plus on the second; `rolling` false and zero without a rolling model).
struct ContactForces {
  Normal n;
  double ft[3], tor[3];
  bool rolling = false;
  double rt[3] = {0.0, 0.0, 0.0};
};
// The contact's sub-models by `m`, composed in the engines' order, with the contact's history
// (history_layout(m): each sub-model's slice), the tangential and rolling parts updated when
// `update_history`, the normal model's at every call.
ContactForces contact(const SubModels& m, const PairConstants& k, const ModelRecord& mr, const ContactPoint& c,
                      double* history, bool update_history, bool tangential_damping, double dt);
// A contact's energy where its normal law keeps one with its history (a NormalRow's `energy`,
// composition.cpp: thornton's, model::thornton_state): the elastic energy it would return from
// `overlap`, and the work it has dissipated. A pair contact's energy is its spheres' together.
struct ContactEnergy {
  double elastic = 0.0, dissipated = 0.0;
};
using NormalEnergy = ContactEnergy (*)(const ModelRecord& r, double overlap, const double* history);
ContactEnergy thornton_energy(const ModelRecord& r, double overlap, const double* history);
// ... by the choice `m`, from the contact's whole history (history_layout(m)); {0, 0} where its
// normal law keeps none (has_contact_energy false).
bool has_contact_energy(const SubModels& m);
// Whether the choice's normal law, undamped and frictionless, gives a force and a history that are
// functions of the positions alone (VectorKernels::still_reference may keep a still block's).
bool positional_force(const SubModels& m);
ContactEnergy contact_energy(const SubModels& m, const ModelRecord& mr, double overlap, const double* history);
// ... of pair p of the table at `overlap` (its work banked when it opens: bank_opened, contacts.hpp).
ContactEnergy pair_contact_energy(const PairTable& t, std::size_t p, double overlap);
// The pair's record, by its sub-models (each computes its own): a sphere of radius radi (the
// first body) and the pair's R* and m*.
ModelRecord model_record(const SubModels& m, const ModelConstants& k, double radi, double reff, double meff);

}  // namespace granstack::refsim::detail
