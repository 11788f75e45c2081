#include <granstack/model/contact.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/model/spec.hpp>

#include <fmt/format.h>

#include <cmath>
#include <set>

namespace granstack::model {

namespace {

// LAMMPS's mix_stiffnessE and mix_stiffnessG for a pair given one (E, nu), as pair_granular.cpp
// forms them from the pair_coeff line.
double lammps_e_star(double e, double nu) { return 1 / ((1 - nu * nu) / e + (1 - nu * nu) / e); }
double lammps_g_star(double e, double nu) { return 1 / (2 * (2 - nu) * (1 + nu) / e + 2 * (2 - nu) * (1 + nu) / e); }

}  // namespace

void lammps_moduli(const Material& a, const Material& b, double& youngs_modulus, double& poisson_ratio) {
  if (a.youngs_modulus == b.youngs_modulus && a.poisson_ratio == b.poisson_ratio) {
    youngs_modulus = a.youngs_modulus;
    poisson_ratio = a.poisson_ratio;
    return;
  }
  // E* = E' / (2 (1 - nu'^2)) and G* = E' / (4 (2 - nu') (1 + nu')): their ratio r = E*/G* =
  // 2 (2 - nu') / (1 - nu') fixes nu' = (4 - r) / (2 - r), then E' = 2 (1 - nu'^2) E*.
  const double y_star = effective_youngs_modulus(a, b);
  const double r = y_star / effective_shear_modulus(a, b);
  poisson_ratio = (4.0 - r) / (2.0 - r);
  youngs_modulus = 2.0 * (1.0 - poisson_ratio * poisson_ratio) * y_star;
}

LammpsContact lammps_contact(const Material& a, const Material& b, double restitution, double friction, bool wall) {
  LammpsContact c;
  lammps_moduli(a, b, c.youngs_modulus, c.poisson_ratio);
  const double y_star = lammps_e_star(c.youngs_modulus, c.poisson_ratio);
  const double g_star = lammps_g_star(c.youngs_modulus, c.poisson_ratio);
  // fix wall/gran's E* = E' / (2 (1 - nu')): the E' that gives the pair's E*.
  if (wall) c.youngs_modulus = 2.0 * (1.0 - c.poisson_ratio) * effective_youngs_modulus(a, b);
  if (restitution < 1.0) c.tsuji_restitution = lammps_tsuji_restitution(restitution);
  c.friction = friction;
  c.tangential_stiffness = 8.0 * effective_shear_modulus(a, b);
  // LIGGGHTS: gamma_t / gamma_n = sqrt(S_t / S_n) = sqrt(8 G* / (2 Y*)).
  c.tangential_damping = std::sqrt(4.0 * g_star / y_star);
  return c;
}

std::string lammps_contact_words(const LammpsContact& c) {
  const bool damped = c.tsuji_restitution >= 0.0;
  std::string words = fmt::format("hertz/material {:.17g} {:.17g} {:.17g}", c.youngs_modulus,
                                  damped ? c.tsuji_restitution : 0.0, c.poisson_ratio);
  words += damped ? " damping tsuji" : " damping viscoelastic";
  if (c.friction > 0.0) {
    words += fmt::format(" tangential mindlin {:.17g} {:.17g} {:.17g}", c.tangential_stiffness, c.tangential_damping,
                         c.friction);
  } else {
    words += " tangential linear_nohistory 0 0";
  }
  return words;
}

std::string lammps_unmappable(const StackSpec& spec) {
  const auto model = spec.contact_model();
  if (model.normal != NormalModel::hertz) {
    return "normal_model = 'hooke' has no counterpart in LAMMPS's granular styles (its hooke spring is a constant per "
           "type pair, LIGGGHTS's depends on each pair's masses and the characteristic velocity); use normal_model = "
           "'hertz'";
  }
  if (model.tangential != TangentialModel::history) {
    return "tangential_model = 'no_history' is not mapped onto LAMMPS (its linear_nohistory damps with a constant, "
           "LIGGGHTS's with the Hertz overlap); use tangential_model = 'history'";
  }
  if (model.rolling != RollingModel::off) {
    return "rolling_model = 'epsd2' has no counterpart in this LAMMPS (its rolling sds is a spring without "
           "LIGGGHTS's plastic cap on R* |F_n|); use rolling_model = 'off'";
  }
  if (spec.dump_files == DumpFiles::per_rank) {
    return "dump_files = 'per_rank' is not supported on LAMMPS; generate the case with --dump-files single";
  }
  std::set<double> restitutions{spec.restitution.value};
  for (const auto& [pair, e] : spec.restitution.pairs) restitutions.insert(e);
  for (const double e : restitutions) {
    if (e < 1.0 && lammps_tsuji_restitution(e) < 0.0) {
      return fmt::format("restitution {}: LAMMPS's tsuji damping spans LIGGGHTS's restitution damping only from e = "
                         "0.1137 to e = 0.99957 (its coefficient alpha(e') stays within [{:.4g}, {:.4g}]); use a "
                         "restitution in that range, or 1",
                         e, tsuji_alpha(1.0), tsuji_alpha(0.0));
    }
  }
  return "";
}

}  // namespace granstack::model
