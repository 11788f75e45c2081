#pragma once
// The protected plate on its mount (StackSpec::plate_mass, docs/physics.md section 7), what every
// engine integrates alike; its energy and measures are in protection.hpp. No dependency beyond the
// language, so refsim's kernels (also cross-compiled alone) include it.

namespace granstack::model {

// The force on the plate along +z, N, from the spheres' push (`wall_load`: the wall's force on the
// spheres along +z, summed; the plate takes minus it) and its mount of stiffness k (N/m) and
// damping c (N s/m) at displacement z (m, from where it stood at the start) and velocity vz (m/s):
// -wall_load - k z - c vz, in that order.
inline double plate_force(double wall_load, double z, double vz, double k, double c) {
  return -wall_load - k * z - c * vz;
}

}  // namespace granstack::model
