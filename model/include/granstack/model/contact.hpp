#pragma once
// Hertz contact parameters and the analytic formulas of physics.md sections 2 and 5.
#include <granstack/model/material.hpp>

#include <cmath>

namespace granstack::model {

inline constexpr double kPi = 3.14159265358979323846;

// Effective quantities of one contact, as LIGGGHTS 3.8.0 forms them (docs/liggghts.md section 1).
struct ContactPair {
  double y_star = 0.0;  // Pa: 1/Y* = (1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j
  double g_star = 0.0;  // Pa: 1/G* = 2(2-nu_i)(1+nu_i)/Y_i + 2(2-nu_j)(1+nu_j)/Y_j
  double r_star = 0.0;  // m: R_i R_j / (R_i + R_j); a wall contributes R* = R_i
  double m_star = 0.0;  // kg: m_i m_j / (m_i + m_j); a wall contributes m* = m_i
};

// Sphere mass, in LIGGGHTS's operation order (4/3 pi r^3 rho).
double sphere_mass(double radius, double density);

double effective_youngs_modulus(const Material& a, const Material& b);
double effective_shear_modulus(const Material& a, const Material& b);

ContactPair sphere_sphere(const Material& a, double radius_a, const Material& b, double radius_b);
ContactPair sphere_wall(const Material& sphere, double radius, const Material& wall);

// Two-body Hertz impact at relative normal speed v (physics.md section 5):
// d_max = (15 m* v^2 / (16 Y* sqrt(R*)))^(2/5).
double hertz_max_overlap(const ContactPair& c, double relative_speed);
// The Hertz collision integral's coefficient: t_c = kHertzTimeCoefficient d_max / v, with
// kHertzTimeCoefficient = 2 int_0^1 (1 - x^(5/2))^(-1/2) dx = (4/5) B(2/5, 1/2)
// = (4/5) Gamma(2/5) Gamma(1/2) / Gamma(9/10) = 2.9432752...
double hertz_time_coefficient();
// Contact time t_c = hertz_time_coefficient() d_max / v.
double hertz_contact_time(const ContactPair& c, double relative_speed);
// Elastic energy stored in an overlap d: 8/15 Y* sqrt(R*) d^(5/2).
inline double hertz_elastic_energy(double y_star, double r_star, double overlap) {
  return 8.0 / 15.0 * y_star * std::sqrt(r_star) * overlap * overlap * std::sqrt(overlap);
}
// Rayleigh time pi R sqrt(rho/G) / (0.1631 nu + 0.8766), G = Y / (2 (1 + nu)).
double rayleigh_time(const Material& m, double radius);

// Restitution damping coefficient beta = ln(e) / sqrt(ln(e)^2 + pi^2) (docs/liggghts.md section 1).
double restitution_beta(double e);

}  // namespace granstack::model
