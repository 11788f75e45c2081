// LIGGGHTS's contact frame (pair_gran.cpp, fix_wall_gran.cpp, primitive_wall_definitions.h): the
// contact point's sliding velocity and the torque's lever arms take the radii shortened by half
// the overlap; a pair forgets its history within the neighbour list's contact distance
// (surfacesClose), a wall as soon as it separates; the stored wall force is the sphere's force
// after the wall minus before it (fix_wall_gran_base.h).
#include "sub_models.hpp"

namespace granstack::refsim::detail {

PairPoint liggghts_pair_point(const PairTable& t, const ContactStep& s, std::size_t p) {
  const auto g = pair_geometry(t, s, p);
  if (!spheres_touch(g)) {
    const double radsum = g.rec->radi + g.rec->radj, cdf = s.contact_distance_factor;
    return {false, g.rsq < cdf * cdf * radsum * radsum, {}};
  }
  const std::size_t i = g.i, j = g.j, y = s.stride, z = 2 * s.stride;
  const auto f = contact_frame(g, s);
  PairPoint out{true, false, pair_contact_point(g, f, s)};
  ContactPoint& c = out.c;
  // Relative velocity at the contact point; lever arms shortened by half the overlap.
  c.deltan = g.rec->radi + g.rec->radj - f.r;
  c.arm_i = g.rec->radi - 0.5 * c.deltan;
  c.arm_j = g.rec->radj - 0.5 * c.deltan;
  const double cri = c.arm_i, crj = c.arm_j;
  const double wr1 = (cri * s.w[i] + crj * s.w[j]) * f.rinv;
  const double wr2 = (cri * s.w[y + i] + crj * s.w[y + j]) * f.rinv;
  const double wr3 = (cri * s.w[z + i] + crj * s.w[z + j]) * f.rinv;
  const double delx = g.delx, dely = g.dely, delz = g.delz;
  c.vtr[0] = f.vt[0] - (delz * wr2 - dely * wr3);
  c.vtr[1] = f.vt[1] - (delx * wr3 - delz * wr1);
  c.vtr[2] = f.vt[2] - (dely * wr1 - delx * wr2);
  return out;
}

// A sphere's gap to a plane wall, negative where they overlap (primitive_wall_definitions.h).
double liggghts_wall_gap(double wall_position, double position, double radius) {
  return position > wall_position ? position - wall_position - radius : wall_position - position - radius;
}

WallPoint liggghts_wall_point(int axis, double wall_position, double pos, double radi, double mass, const double v[3],
                              const double w[3]) {
  const double gap = liggghts_wall_gap(wall_position, pos, radi);
  if (!(gap <= 0.0)) return {false, {}};
  // Vector from the centre to the plane.
  double delta[3] = {0., 0., 0.};
  delta[axis] = wall_position - pos;
  const double overlap_in = -gap;
  const double dx = -delta[0], dy = -delta[1], dz = -delta[2];  // from the wall to the centre
  const double r = radi - overlap_in;
  const double rinv = 1.0 / r;
  const double enx = dx * rinv, eny = dy * rinv, enz = dz * rinv;
  const double vr1 = v[0] - 0.0, vr2 = v[1] - 0.0, vr3 = v[2] - 0.0;
  const double vn = vr1 * enx + vr2 * eny + vr3 * enz;
  const double vt1 = vr1 - vn * enx, vt2 = vr2 - vn * eny, vt3 = vr3 - vn * enz;
  const double cr = radi - 0.5 * overlap_in;
  const double wr1 = cr * w[0] * rinv, wr2 = cr * w[1] * rinv, wr3 = cr * w[2] * rinv;
  // A wall has R* = R_i and m* = m_i; a rolling model on a wall turns the contact point's
  // rotation speed, wr = cr omega / r, not omega.
  return {true,
          {{enx, eny, enz},
           vn,
           {vt1 - (dz * wr2 - dy * wr3), vt2 - (dx * wr3 - dz * wr1), vt3 - (dy * wr1 - dx * wr2)},
           radi - r,
           radi,
           mass,
           radi,
           {wr1, wr2, wr3},
           true,
           cr,
           0.0}};
}

void liggghts_wall_force(double fn, const double en[3], const double ft[3], double force[3]) {
  for (std::size_t d = 0; d < 3; ++d) force[d] = 0.0 + fn * 1. * en[d];  // * area_ratio (1)
  for (std::size_t d = 0; d < 3; ++d) force[d] += ft[d] * 1.;
}

}  // namespace granstack::refsim::detail
