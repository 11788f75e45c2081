#include <granstack/model/contact.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>

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

std::string liggghts_model_words(const ContactModel& m) {
  std::string words = "model ";
  words += to_string(m.normal);
  words += " tangential ";
  words += to_string(m.tangential);
  if (m.rolling != RollingModel::off) {
    words += " rolling_friction ";
    words += to_string(m.rolling);
  }
  return words;
}

double hooke_stiffness(const ContactPair& c, double v) {
  const double sqrtval = std::sqrt(c.r_star);
  return 16. / 15. * sqrtval * (c.y_star) * std::pow(15. * c.m_star * v * v / (16. * sqrtval * c.y_star), 0.2);
}

namespace {
// Each law's formulas (a head-on collision's: physics.md section 5 for Hertz; v sqrt(m*/k_n) and
// pi sqrt(m*/k_n), whatever v, for Hooke's spring).
double hertz_force(const ContactModel&, const ContactPair& c, double d) {
  return 4.0 / 3.0 * c.y_star * std::sqrt(c.r_star) * d * std::sqrt(d);
}
double hertz_energy(const ContactModel&, const ContactPair& c, double d) { return hertz_elastic_energy(c.y_star, c.r_star, d); }
double hertz_overlap(const ContactModel&, const ContactPair& c, double v) { return hertz_max_overlap(c, v); }
double hertz_time(const ContactModel&, const ContactPair& c, double v) { return hertz_contact_time(c, v); }
double hooke_force(const ContactModel& m, const ContactPair& c, double d) {
  return hooke_stiffness(c, m.characteristic_velocity) * d;
}
double hooke_energy(const ContactModel& m, const ContactPair& c, double d) {
  return 0.5 * hooke_stiffness(c, m.characteristic_velocity) * d * d;
}
double hooke_overlap(const ContactModel& m, const ContactPair& c, double v) {
  return v * std::sqrt(c.m_star / hooke_stiffness(c, m.characteristic_velocity));
}
double hooke_time(const ContactModel& m, const ContactPair& c, double) {
  return kPi * std::sqrt(c.m_star / hooke_stiffness(c, m.characteristic_velocity));
}

// The elastic-plastic laws' elastic branch is Hertz's (below yield).
double no_energy(const ContactModel&, const ContactPair&, double) {
  throw std::logic_error("an elastic-plastic contact's energy depends on its largest overlap, not on the overlap alone");
}

constexpr SubModelInfo kHertzInfo{"hertz", "hertz (the study's)", "", ""};
constexpr SubModelInfo kHookeInfo{
    "hooke", "hooke",
    "`hooke`: a linear spring with Hertz's largest overlap at `characteristic_velocity` and restitution exactly e "
    "([physics](../physics.md#other-contact-models))",
    "normal_model = 'hooke' has no counterpart in LAMMPS's granular styles (its hooke spring is a constant per type "
    "pair, LIGGGHTS's depends on each pair's masses and the characteristic velocity); use normal_model = 'hertz'"};
constexpr SubModelInfo kThorntonInfo{
    "thornton", "thornton (Thornton 1997: elastic-perfectly-plastic, refsim)",
    "`thornton`: Thornton (1997)'s elastic-perfectly-plastic contact, yield at `yield_pressure_factor` times the "
    "softer yield strength ([physics](../physics.md#contacts-that-yield)); refsim only",
    "normal_model = 'thornton' has no counterpart in LAMMPS 29 Sep 2021 (its granular styles have no elastic-plastic "
    "normal model); run it on refsim (run --engine refsim)",
    "normal_model = 'thornton' (Thornton 1997) has no counterpart in LIGGGHTS 3.8: its nearest law is thornton_ning "
    "(unloading about R*, first order in dt); run thornton on refsim (run --engine refsim), or set normal_model = "
    "'thornton_ning' to run LIGGGHTS's"};
constexpr SubModelInfo kThorntonNingInfo{
    "thornton_ning", "thornton_ning (LIGGGHTS 3.8's elastic-plastic law)",
    "`thornton_ning`: LIGGGHTS 3.8's elastic-plastic law (surfaceEnergy 0), one yield radius per chain of touching "
    "types ([physics](../physics.md#contacts-that-yield))",
    "normal_model = 'thornton_ning' has no counterpart in LAMMPS 29 Sep 2021 (its granular styles have no "
    "elastic-plastic normal model); run it on LIGGGHTS or refsim"};

// In NormalModel's order: one row per model, the table as long as the enum.
constexpr auto kNormalLaws = std::to_array<NormalLaw>({
    {kHertzInfo, "Hertz", false, true, false, false, false, false, 100.0, NormalModel::hertz, hertz_force, hertz_energy,
     hertz_overlap, hertz_time},
    {kHookeInfo, "Hooke", true, false, false, false, false, false, 100.0, NormalModel::hooke, hooke_force, hooke_energy,
     hooke_overlap, hooke_time},
    {kThorntonInfo, "Thornton", false, true, true, true, true, true, 100.0, NormalModel::thornton_ning, hertz_force,
     no_energy, hertz_overlap, hertz_time},
    {kThorntonNingInfo, "LIGGGHTS's thornton_ning", false, true, true, true, true, false, 1000.0,
     NormalModel::thornton_ning, hertz_force, no_energy, hertz_overlap, hertz_time},
});
static_assert(kNormalLaws.size() == kNormalModelCount, "one row per NormalModel");
}  // namespace

const NormalLaw& normal_law(NormalModel m) { return kNormalLaws.at(static_cast<std::size_t>(m)); }

double elastic_normal_force(const ContactModel& m, const ContactPair& c, double d) {
  return normal_law(m.normal).force(m, c, d);
}
double elastic_energy(const ContactModel& m, const ContactPair& c, double d) { return normal_law(m.normal).energy(m, c, d); }
double max_overlap(const ContactModel& m, const ContactPair& c, double v) { return normal_law(m.normal).max_overlap(m, c, v); }

ThorntonLaw thornton_law(const ContactPair& c, double p_y) {
  const double a_y = kPi * c.r_star * p_y / (2.0 * c.y_star);
  const double d_y = a_y * a_y / c.r_star;
  return {c.y_star, c.r_star, p_y, d_y, 4.0 / 3.0 * c.y_star * std::sqrt(c.r_star) * d_y * std::sqrt(d_y),
          kPi * p_y * c.r_star};
}

namespace {
// The unloading curve from d_max > d_y: F_max, R_p and d_max - d_p.
struct Unloading {
  double f_max, r_p, w_max;
};
Unloading unloading(const ThorntonLaw& l, double d_max) {
  const double f_max = l.yield_force + l.slope * (d_max - l.yield_overlap);
  const double a_p = std::sqrt(l.r_star * d_max);
  const double r_p = 4.0 * l.y_star * a_p * a_p * a_p / (3.0 * f_max);
  return {f_max, r_p, l.r_star * d_max / r_p};
}
}  // namespace

double thornton_force(const ThorntonLaw& l, double d, double d_max) {
  if (d <= 0.0) return 0.0;
  if (d_max <= l.yield_overlap) return 4.0 / 3.0 * l.y_star * std::sqrt(l.r_star) * d * std::sqrt(d);
  if (d >= d_max) return l.yield_force + l.slope * (d - l.yield_overlap);
  const Unloading u = unloading(l, d_max);
  const double w = d - (d_max - u.w_max);
  return w <= 0.0 ? 0.0 : 4.0 / 3.0 * l.y_star * std::sqrt(u.r_p) * w * std::sqrt(w);
}

ThorntonState thornton_state(const ThorntonLaw& l, double d, double d_max) {
  d = std::max(d, 0.0);
  d_max = std::max(d_max, d);
  if (d_max <= l.yield_overlap) return {thornton_force(l, d, d_max), hertz_elastic_energy(l.y_star, l.r_star, d), 0.0};
  const Unloading u = unloading(l, d_max);
  const double beyond = d_max - l.yield_overlap;
  const double loading_work = hertz_elastic_energy(l.y_star, l.r_star, l.yield_overlap) +
                              (l.yield_force + 0.5 * l.slope * beyond) * beyond;
  const double dissipated = loading_work - hertz_elastic_energy(l.y_star, u.r_p, u.w_max);
  const double w = d - (d_max - u.w_max);
  return {thornton_force(l, d, d_max), w <= 0.0 ? 0.0 : hertz_elastic_energy(l.y_star, u.r_p, w), dissipated};
}

double thornton_yield_velocity(const ContactPair& c, double p_y) {
  return std::sqrt(2.0 * hertz_elastic_energy(c.y_star, c.r_star, thornton_law(c, p_y).yield_overlap) / c.m_star);
}

double thornton_restitution(double v_y, double v) {
  if (v <= v_y) return 1.0;
  const double x = v_y / v;
  return std::sqrt(6.0 * std::sqrt(3.0) / 5.0) * std::sqrt(1.0 - x * x / 6.0) *
         std::pow(x / (x + 2.0 * std::sqrt(6.0 / 5.0 - x * x / 5.0)), 0.25);
}
double contact_time(const ContactModel& m, const ContactPair& c, double v) { return normal_law(m.normal).contact_time(m, c, v); }

namespace {

// LAMMPS's MathSpecial::powint: x^n by repeated squaring.
double powint(double x, int n) {
  if (n == 0) return 1.0;
  if (x == 0.0) return 0.0;
  double result = 1.0;
  double w = x;
  for (int k = n; k != 0; k >>= 1, w *= w) {
    if ((k & 1) != 0) result *= w;
  }
  return result;
}

}  // namespace

double tsuji_alpha(double e) {
  return 1.2728 - 4.2783 * e + 11.087 * (e * e) - 22.348 * (e * e * e) + 27.467 * powint(e, 4) - 18.022 * powint(e, 5) +
         4.8218 * powint(e, 6);
}

double tsuji_restitution_for(double alpha) {
  // Bisection on [0, 1] down to neighbouring doubles, then the nearer of the two.
  double lo = 0.0, hi = 1.0;  // tsuji_alpha(lo) >= alpha >= tsuji_alpha(hi)
  while (std::nextafter(lo, 1.0) < hi) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (tsuji_alpha(mid) >= alpha ? lo : hi) = mid;
  }
  return std::abs(tsuji_alpha(lo) - alpha) <= std::abs(tsuji_alpha(hi) - alpha) ? lo : hi;
}

double lammps_tsuji_restitution(double e) {
  const double alpha = std::sqrt(5.0) * std::abs(restitution_beta(e));
  if (alpha > tsuji_alpha(0.0) || alpha < tsuji_alpha(1.0)) return -1.0;
  return tsuji_restitution_for(alpha);
}

}  // namespace granstack::model
