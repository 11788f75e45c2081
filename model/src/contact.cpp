#include <granstack/model/contact.hpp>

#include <cmath>

namespace granstack::model {

double sphere_mass(double radius, double density) { return 4.0 * kPi / 3.0 * radius * radius * radius * density; }

// The mixing rules are written in LIGGGHTS's operation order (global_properties.cpp:432, 463,
// 516-539), so the reference integrator gets the same doubles.
double effective_youngs_modulus(const Material& a, const Material& b) {
  return 1. / ((1. - std::pow(a.poisson_ratio, 2.)) / a.youngs_modulus +
               (1. - std::pow(b.poisson_ratio, 2.)) / b.youngs_modulus);
}

double effective_shear_modulus(const Material& a, const Material& b) {
  return 1. / (2. * (2. - a.poisson_ratio) * (1. + a.poisson_ratio) / a.youngs_modulus +
               2. * (2. - b.poisson_ratio) * (1. + b.poisson_ratio) / b.youngs_modulus);
}

ContactPair sphere_sphere(const Material& a, double radius_a, const Material& b, double radius_b) {
  const double ma = sphere_mass(radius_a, a.density);
  const double mb = sphere_mass(radius_b, b.density);
  return {effective_youngs_modulus(a, b), effective_shear_modulus(a, b), radius_a * radius_b / (radius_a + radius_b),
          ma * mb / (ma + mb)};
}

ContactPair sphere_wall(const Material& sphere, double radius, const Material& wall) {
  return {effective_youngs_modulus(sphere, wall), effective_shear_modulus(sphere, wall), radius,
          sphere_mass(radius, sphere.density)};
}

double hertz_max_overlap(const ContactPair& c, double v) {
  return std::pow(15.0 * c.m_star * v * v / (16.0 * c.y_star * std::sqrt(c.r_star)), 0.4);
}

double hertz_time_coefficient() {
  static const double coefficient = 0.8 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  return coefficient;
}

double hertz_contact_time(const ContactPair& c, double v) { return hertz_time_coefficient() * hertz_max_overlap(c, v) / v; }

double rayleigh_time(const Material& m, double radius) {
  const double shear = m.youngs_modulus / (2.0 * (1.0 + m.poisson_ratio));
  return kPi * radius * std::sqrt(m.density / shear) / (0.1631 * m.poisson_ratio + 0.8766);
}

double restitution_beta(double e) {
  const double l = std::log(e);
  return l / std::sqrt(std::pow(l, 2.) + std::pow(kPi, 2.));
}

}  // namespace granstack::model
