#include <granstack/model/contact.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/model/spec.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstdio>
#include <set>

namespace granstack::model {

namespace {

// LAMMPS's mix_stiffnessE and mix_stiffnessG for a pair given one (E, nu), as pair_granular.cpp
// forms them from the pair_coeff line.
double lammps_e_star(double e, double nu) { return 1 / ((1 - nu * nu) / e + (1 - nu * nu) / e); }
double lammps_g_star(double e, double nu) { return 1 / (2 * (2 - nu) * (1 + nu) / e + 2 * (2 - nu) * (1 + nu) / e); }

}  // namespace

std::optional<LammpsVersion> parse_lammps_version(std::string_view help_text) {
  constexpr std::string_view kDash = " - ";
  const auto at = help_text.find(kLammpsBanner);
  if (at == std::string_view::npos || help_text.substr(at + kLammpsBanner.size(), kDash.size()) != kDash) return std::nullopt;
  auto line = help_text.substr(at + kLammpsBanner.size() + kDash.size());
  line = line.substr(0, line.find('\n'));
  static const char* const kMonths[] = {"Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};
  LammpsVersion v;
  char month[4] = {};
  int used = 0;
  const std::string text(line);
  if (std::sscanf(text.c_str(), "%d %3s %d%n", &v.day, month, &v.year, &used) != 3) return std::nullopt;
  for (int m = 0; m < 12; ++m) {
    if (std::string_view(month) == kMonths[m]) v.month = m + 1;
  }
  if (v.month == 0 || v.day < 1 || v.day > 31 || v.year < 1990) return std::nullopt;
  int update = 0;
  if (std::sscanf(text.c_str() + used, " - Update %d", &update) == 1) v.update = update;
  v.text = text;
  while (!v.text.empty() && (v.text.back() == ' ' || v.text.back() == '\r')) v.text.pop_back();
  return v;
}

namespace {
LammpsVersion release(int day, int month, int year, const char* text) { return {year, month, day, 0, text}; }
}  // namespace

const std::vector<LammpsRules>& lammps_rule_sets() {
  static const std::vector<LammpsRules> sets{
      {"LAMMPS 29 Sep 2021", release(29, 9, 2021, "29 Sep 2021"), release(29, 9, 2021, "29 Sep 2021"),
       LammpsWallModulus::one_minus_nu, LammpsDamping::tsuji_match, true,
       "src/GRANULAR/pair_granular.cpp and fix_wall_gran.cpp of the stable release 29 Sep 2021; run against Debian "
       "12's lmp (29 Sep 2021 - Update 2): the engines agree to round-off (docs/explanation/lammps.md)"},
      {"LAMMPS 27 Jun 2024 to 22 Jul 2025", release(27, 6, 2024, "27 Jun 2024"), release(22, 7, 2025, "22 Jul 2025"),
       LammpsWallModulus::one_minus_nu_squared, LammpsDamping::coeff_restitution, false,
       "src/GRANULAR/gran_sub_mod.cpp (mix_stiffnessE_wall) of the granular rewrite (lammps/lammps#3742) and "
       "gran_sub_mod_damping.cpp (damping coeff_restitution, lammps/lammps#4068); written from that source, not run: no "
       "such LAMMPS is packaged for Debian 12"},
  };
  return sets;
}

const LammpsRules* lammps_rules_for(const LammpsVersion& v) {
  for (const auto& r : lammps_rule_sets()) {
    if (r.covers(v)) return &r;
  }
  return nullptr;
}

const LammpsRules& lammps_rules_run_here() { return lammps_rule_sets().front(); }

std::string known_lammps_versions() {
  std::vector<std::string> parts;
  for (const auto& r : lammps_rule_sets()) {
    const auto range = r.first.ordinal() == r.last.ordinal() ? r.first.text + " (every update)"
                                                             : fmt::format("{} to {}", r.first.text, r.last.text);
    parts.push_back(fmt::format("{}, {}", range, r.run_here ? "run against a real binary" : "written from its source, not run"));
  }
  return fmt::format("{}", fmt::join(parts, "; "));
}

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

LammpsContact lammps_contact(const Material& a, const Material& b, double restitution, double friction, bool wall,
                             const LammpsRules& rules) {
  LammpsContact c;
  lammps_moduli(a, b, c.youngs_modulus, c.poisson_ratio);
  const double y_star = lammps_e_star(c.youngs_modulus, c.poisson_ratio);
  const double g_star = lammps_g_star(c.youngs_modulus, c.poisson_ratio);
  // 2021's fix wall/gran forms E* = E' / (2 (1 - nu')): the E' that gives the pair's E*. The rewrite
  // forms a wall's E* as a pair's, which lammps_moduli's E' gives already.
  if (wall && rules.wall == LammpsWallModulus::one_minus_nu) {
    c.youngs_modulus = 2.0 * (1.0 - c.poisson_ratio) * effective_youngs_modulus(a, b);
  }
  if (restitution < 1.0) {
    c.tsuji_restitution = rules.damping == LammpsDamping::coeff_restitution ? restitution : lammps_tsuji_restitution(restitution);
  }
  c.friction = friction;
  c.tangential_stiffness = 8.0 * effective_shear_modulus(a, b);
  // LIGGGHTS: gamma_t / gamma_n = sqrt(S_t / S_n) = sqrt(8 G* / (2 Y*)).
  c.tangential_damping = std::sqrt(4.0 * g_star / y_star);
  return c;
}

std::string lammps_contact_words(const LammpsContact& c, const LammpsRules& rules, TangentialModel tangential) {
  const bool damped = c.tsuji_restitution >= 0.0;
  std::string words = fmt::format("hertz/material {:.17g} {:.17g} {:.17g}", c.youngs_modulus,
                                  damped ? c.tsuji_restitution : 0.0, c.poisson_ratio);
  words += !damped ? " damping viscoelastic"
                   : rules.damping == LammpsDamping::coeff_restitution ? " damping coeff_restitution" : " damping tsuji";
  if (c.friction > 0.0) {
    words += fmt::format(" tangential {} {:.17g} {:.17g} {:.17g}", info(tangential).lammps_word, c.tangential_stiffness,
                         c.tangential_damping, c.friction);
  } else {
    words += " tangential linear_nohistory 0 0";
  }
  return words;
}

std::string lammps_unmappable(const StackSpec& spec, const LammpsRules& rules) {
  if (const auto why = lammps_contact_unmappable(spec, rules); !why.empty()) return why;
  if (spec.dump_files == DumpFiles::per_rank) {
    return "dump_files = 'per_rank' is not supported on LAMMPS; generate the case with --dump-files single";
  }
  return "";
}

std::string lammps_contact_unmappable(const StackSpec& spec, const LammpsRules& rules) {
  if (const auto why = lammps_refusal(spec.contact_model()); !why.empty()) return std::string(why);
  std::set<double> restitutions{spec.restitution.value};
  for (const auto& [pair, e] : spec.restitution.pairs) restitutions.insert(e);
  for (const double e : restitutions) {
    if (rules.damping == LammpsDamping::tsuji_match && e < 1.0 && lammps_tsuji_restitution(e) < 0.0) {
      return fmt::format("restitution {}: the tsuji damping of {} spans LIGGGHTS's restitution damping only from e = "
                         "0.1137 to e = 0.99957 (its coefficient alpha(e') stays within [{:.4g}, {:.4g}]); use a "
                         "restitution in that range, or 1 (or a LAMMPS with damping coeff_restitution, from 27 Jun 2024)",
                         e, rules.name, tsuji_alpha(1.0), tsuji_alpha(0.0));
    }
  }
  return "";
}

}  // namespace granstack::model
