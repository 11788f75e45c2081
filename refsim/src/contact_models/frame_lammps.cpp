// LAMMPS's contact frame (pair_granular.cpp, fix_wall_gran.cpp of LAMMPS 29 Sep 2021): the
// contact point's sliding velocity takes the full radii; a pair's torque arm is shortened by
// half the overlap, a wall's is the radius itself; a pair or a wall forgets its history as soon
// as it separates; the stored wall force is the wall's force on the sphere.
#include "sub_models.hpp"

#include <cmath>

namespace granstack::refsim::detail {

PairPoint lammps_pair_point(const PairTable& t, const ContactStep& s, std::size_t p) {
  const auto g = pair_geometry(t, s, p);
  if (!spheres_touch(g)) return {false, true, {}};
  const std::size_t i = g.i, j = g.j, y = s.stride, z = 2 * s.stride;
  const double radi = g.rec->radi, radj = g.rec->radj;
  const auto f = contact_frame(g, s);
  PairPoint out{true, false, pair_contact_point(g, f, s)};
  ContactPoint& c = out.c;
  const double* nv = f.en;
  c.deltan = radi + radj - f.r;
  c.arm_i = radi - 0.5 * c.deltan;
  c.arm_j = radj - 0.5 * c.deltan;
  // The sliding velocity from the full radii.
  const double wr1 = radi * s.w[i] + radj * s.w[j];
  const double wr2 = radi * s.w[y + i] + radj * s.w[y + j];
  const double wr3 = radi * s.w[z + i] + radj * s.w[z + j];
  c.vtr[0] = f.vt[0] - (nv[2] * wr2 - nv[1] * wr3);
  c.vtr[1] = f.vt[1] - (nv[0] * wr3 - nv[2] * wr1);
  c.vtr[2] = f.vt[2] - (nv[1] * wr1 - nv[0] * wr2);
  return out;
}

bool lammps_wall_touches(double wall_position, double pos, double radius) {
  const double gap_axis = pos - wall_position;
  return !(gap_axis * gap_axis > radius * radius);
}

WallPoint lammps_wall_point(int axis, double wall_position, double pos, double radius, double mass, const double v[3],
                            const double w[3]) {
  if (!lammps_wall_touches(wall_position, pos, radius)) return {false, {}};
  const double gap_axis = pos - wall_position;
  const double r = std::sqrt(gap_axis * gap_axis);
  const double rinv = 1.0 / r;
  double nv[3] = {0.0, 0.0, 0.0};
  nv[axis] = gap_axis * rinv;
  const double vnnr = v[0] * nv[0] + v[1] * nv[1] + v[2] * nv[2];
  const double vt1 = v[0] - nv[0] * vnnr, vt2 = v[1] - nv[1] * vnnr, vt3 = v[2] - nv[2] * vnnr;
  const double wr1 = radius * w[0], wr2 = radius * w[1], wr3 = radius * w[2];
  // fix wall/gran's lever arm is the radius itself (pair_granular's is shortened by half the
  // overlap): measured, a frictional wall case agrees with LAMMPS to round-off only so.
  return {true,
          {{nv[0], nv[1], nv[2]},
           vnnr,
           {vt1 - (nv[2] * wr2 - nv[1] * wr3), vt2 - (nv[0] * wr3 - nv[2] * wr1), vt3 - (nv[1] * wr1 - nv[0] * wr2)},
           radius - r,
           radius,
           mass,
           radius,
           {wr1, wr2, wr3},
           true,
           radius,
           0.0}};
}

void lammps_wall_force(double fn, const double en[3], const double ft[3], double force[3]) {
  for (int d = 0; d < 3; ++d) force[d] = en[d] * fn + ft[d];
}

}  // namespace granstack::refsim::detail
