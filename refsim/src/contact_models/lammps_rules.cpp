// refsim's contacts by LAMMPS's rules (Parameters::lammps_rules): LAMMPS 29 Sep 2021's
// pair_style granular (hertz/material, tsuji or no damping, linear_nohistory 0 0 without
// friction, mindlin with it) and fix wall/gran granular, in their operation order, so that
// refsim agrees with LAMMPS on LAMMPS's model as it agrees with LIGGGHTS on LIGGGHTS's
// (docs/explanation/lammps.md). What differs from LIGGGHTS's rules (contacts.cpp):
//   - no tangential force at all without friction (LIGGGHTS applies gamma_t v_t on a step whose
//     spring is still zero, e.g. the first step of a contact);
//   - the damping coefficient alpha(e') sqrt(m* 4/3 Y* a), a = sqrt(R* d) (the same function);
//   - mindlin: the spring is turned into the tangent plane keeping its length before the step's
//     displacement is added, the contact's sliding speed takes the full radii, and the Coulomb
//     cap resets the spring to what the capped force needs;
//   - walls: E* as fix wall/gran forms it (model/lammps.hpp gives the E' for it), the elastic force
//     as (E a) delta, and the torque's lever arm the full radius.
#include "../contacts.hpp"

#include <cmath>

namespace granstack::refsim::detail {

namespace {

// LAMMPS's EPSILON in pair_granular.cpp: the spring is turned only when its normal part matters.
constexpr double kFrameEpsilon = 1e-10;

struct LammpsNormal {
  double fntot;       // elastic plus damping
  double prefactor;   // the damping coefficient eta_n (0 undamped)
  double a;           // sqrt(R* d)
};

// pair_granular forms the elastic force as (E delta) a, fix wall/gran as (E a) delta (`wall`).
LammpsNormal lammps_normal(const PairConstants& k, const ModelRecord& mr, double reff, double meff, double delta,
                           double vnnr, bool wall) {
  const double dr = delta * reff;
  double knfac = k.kn_factor;
  double fne = knfac * delta;
  const double a = std::sqrt(dr);
  fne *= a;
  knfac *= a;
  if (wall) fne = knfac * delta;
  // tsuji: alpha sqrt(m* knfac); undamped is viscoelastic with coefficient 0.
  const double damp_normal = mr.lammps_alpha != 0.0 ? std::sqrt(meff * knfac) : a * meff;
  const double prefactor = mr.lammps_alpha * damp_normal;
  const double fdamp = -prefactor * vnnr;
  return {fne + fdamp, prefactor, a};
}

// pair_granular's mindlin (friction > 0) or linear_nohistory 0 0 (friction 0: zero force).
void lammps_tangential(const PairConstants& k, const ModelRecord& mr, const LammpsNormal& n, const double nv[3],
                       const double vtr[3], double history[3], bool update_history, double dt, double fs[3]) {
  fs[0] = fs[1] = fs[2] = 0.0;
  if (k.friction == 0.0) return;
  const double fscrit = k.friction * std::fabs(n.fntot);
  const double k_t = k.st_factor * n.a;
  const double damp_t = mr.lammps_tangential_ratio * n.prefactor;
  if (update_history) {
    const double rsht = history[0] * nv[0] + history[1] * nv[1] + history[2] * nv[2];
    if (std::fabs(rsht) * k_t > kFrameEpsilon * fscrit) {
      const double shrmag = std::sqrt(history[0] * history[0] + history[1] * history[1] + history[2] * history[2]);
      for (int d = 0; d < 3; ++d) history[d] -= rsht * nv[d];
      const double prjmag = std::sqrt(history[0] * history[0] + history[1] * history[1] + history[2] * history[2]);
      const double scalefac = prjmag > 0 ? shrmag / prjmag : 0;
      for (int d = 0; d < 3; ++d) history[d] *= scalefac;
    }
    for (int d = 0; d < 3; ++d) history[d] += vtr[d] * dt;
  }
  for (int d = 0; d < 3; ++d) fs[d] = -k_t * history[d] - damp_t * vtr[d];
  const double f = std::sqrt(fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2]);
  if (f > fscrit) {
    const double shrmag = std::sqrt(history[0] * history[0] + history[1] * history[1] + history[2] * history[2]);
    if (shrmag != 0.0) {
      for (int d = 0; d < 3; ++d) history[d] = -1.0 / k_t * (fscrit * fs[d] / f + damp_t * vtr[d]);
      for (int d = 0; d < 3; ++d) fs[d] *= fscrit / f;
    } else {
      fs[0] = fs[1] = fs[2] = 0.0;
    }
  }
}

}  // namespace

void pair_force_lammps(PairTable& t, const ContactStep& s, std::size_t p) {
  const auto g = pair_geometry(t, s, p);
  const PairRecord& rec = *g.rec;
  const std::size_t i = g.i, j = g.j, y = s.stride, z = 2 * s.stride;
  const double radi = rec.radi, radj = rec.radj;
  const double radsum = radi + radj;
  if (!(g.rsq < radsum * radsum)) {  // LAMMPS forgets a pair's history as soon as it does not touch
    t.touching[p] = 0;
    t.shear_x[p] = t.shear_y[p] = t.shear_z[p] = 0.0;
    zero_contribution(t, p);
    return;
  }
  t.touching[p] = 1;
  const auto f = contact_frame(g, s);
  const double* nv = f.en;
  const double delta = radsum - f.r;
  const ModelRecord& mr = t.model_records[static_cast<std::size_t>(t.record[p])];
  const LammpsNormal n = lammps_normal(rec.constants(), mr, rec.reff, rec.meff, delta, f.vn, false);

  const double vt1 = f.vt[0], vt2 = f.vt[1], vt3 = f.vt[2];
  const double wr1 = radi * s.w[i] + radj * s.w[j];
  const double wr2 = radi * s.w[y + i] + radj * s.w[y + j];
  const double wr3 = radi * s.w[z + i] + radj * s.w[z + j];
  const double vtr[3] = {vt1 - (nv[2] * wr2 - nv[1] * wr3), vt2 - (nv[0] * wr3 - nv[2] * wr1),
                         vt3 - (nv[1] * wr1 - nv[0] * wr2)};
  double history[3] = {t.shear_x[p], t.shear_y[p], t.shear_z[p]};
  double fs[3];
  lammps_tangential(rec.constants(), mr, n, nv, vtr, history, s.update_history, s.dt, fs);
  t.shear_x[p] = history[0];
  t.shear_y[p] = history[1];
  t.shear_z[p] = history[2];

  t.fx[p] = nv[0] * n.fntot + fs[0];
  t.fy[p] = nv[1] * n.fntot + fs[1];
  t.fz[p] = nv[2] * n.fntot + fs[2];
  const double tor1 = nv[1] * fs[2] - nv[2] * fs[1];
  const double tor2 = nv[2] * fs[0] - nv[0] * fs[2];
  const double tor3 = nv[0] * fs[1] - nv[1] * fs[0];
  const double arm_i = radi - 0.5 * delta, arm_j = radj - 0.5 * delta;
  const std::size_t q = t.padded() + p;
  t.tx[p] = -arm_i * tor1;
  t.ty[p] = -arm_i * tor2;
  t.tz[p] = -arm_i * tor3;
  t.tx[q] = -arm_j * tor1;
  t.ty[q] = -arm_j * tor2;
  t.tz[q] = -arm_j * tor3;
}

bool wall_force_lammps(int axis, double gap_axis, double radius, double mass, const double v[3], const double w[3],
                       const PairConstants& k, const ModelRecord& mr, double history[3], bool update_history, double dt,
                       double force[3], double torque[3]) {
  force[0] = force[1] = force[2] = torque[0] = torque[1] = torque[2] = 0.0;
  const double rsq = gap_axis * gap_axis;
  if (rsq > radius * radius) {
    history[0] = history[1] = history[2] = 0.0;
    return false;
  }
  const double r = std::sqrt(rsq);
  const double rinv = 1.0 / r;
  double nv[3] = {0.0, 0.0, 0.0};
  nv[axis] = gap_axis * rinv;
  const double vnnr = v[0] * nv[0] + v[1] * nv[1] + v[2] * nv[2];
  const double delta = radius - r;
  const LammpsNormal n = lammps_normal(k, mr, radius, mass, delta, vnnr, true);
  const double vt1 = v[0] - nv[0] * vnnr, vt2 = v[1] - nv[1] * vnnr, vt3 = v[2] - nv[2] * vnnr;
  const double wr1 = radius * w[0], wr2 = radius * w[1], wr3 = radius * w[2];
  const double vtr[3] = {vt1 - (nv[2] * wr2 - nv[1] * wr3), vt2 - (nv[0] * wr3 - nv[2] * wr1),
                         vt3 - (nv[1] * wr1 - nv[0] * wr2)};
  double fs[3];
  lammps_tangential(k, mr, n, nv, vtr, history, update_history, dt, fs);
  for (int d = 0; d < 3; ++d) force[d] = nv[d] * n.fntot + fs[d];
  const double tor[3] = {nv[1] * fs[2] - nv[2] * fs[1], nv[2] * fs[0] - nv[0] * fs[2], nv[0] * fs[1] - nv[1] * fs[0]};
  // fix wall/gran's lever arm is the radius itself (pair_granular's is shortened by half the
  // overlap): measured, a frictional wall case agrees with LAMMPS to round-off only so.
  for (int d = 0; d < 3; ++d) torque[d] = -radius * tor[d];
  return true;
}

}  // namespace granstack::refsim::detail
