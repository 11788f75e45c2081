#pragma once
// How a spec's contacts map onto LAMMPS's `pair_style granular` and `fix wall/gran granular`
// (Debian 12's LAMMPS, 29 Sep 2021 - Update 2; docs/explanation/lammps.md): which of its models
// gives LIGGGHTS 3.8's force law, with which coefficients, and what cannot be mapped.
//
//   normal: hertz/material E nu, F = 4/3 E* sqrt(R* d) d with E* from (E, nu) as LIGGGHTS's Y*;
//     LAMMPS takes one (E, nu) per type pair, so a pair of two materials gets the (E', nu')
//     whose E* and G* are the pair's (lammps_moduli).
//   damping: LIGGGHTS's gamma_n = 2 sqrt(5/6) |beta(e)| sqrt(2 Y* sqrt(R* d) m*) is LAMMPS's
//     tsuji eta_n = alpha(e') sqrt(m* 4/3 E* sqrt(R* d)) when alpha(e') = sqrt(5) |beta(e)|:
//     the same function of the overlap, so e' is chosen where LAMMPS's polynomial alpha gives that
//     value (tsuji_restitution_for). Restitution 1: no damping (coefficient 0).
//   tangential: friction 0 gives no tangential force in LAMMPS (linear_nohistory 0 0); friction
//     above 0 maps to `mindlin` with k_t = 8 G* sqrt(R* d) (the 8 G* given, not NULL) and
//     eta_t / eta_n = sqrt(4 G* / Y*), LIGGGHTS's ratio, but LAMMPS updates and caps the spring
//     its own way (a model difference); the spec's mindlin_rescale (LAMMPS's own) to
//     `mindlin_rescale` with the same coefficients.
//   walls: 29 Sep 2021's fix wall/gran forms hertz/material's E* as E / (2 (1 - nu)), not
//     pair_granular's E / (2 (1 - nu^2)) (measured: a bottom-wall case agrees with LIGGGHTS to
//     1e-14 only with E' = 2 (1 - nu') E*), so a wall's E' is chosen for that form; the granular
//     rewrite of 2023 forms the wall's E* as the pair's.
// Which LAMMPS forms what is version by version (LammpsRules): the version `lmp -h` reports
// chooses the rules, and a version whose rules are not known is refused.
#include <granstack/model/contact.hpp>
#include <granstack/model/material.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::model {

class Stack;
struct StackSpec;

// A LAMMPS release, as `lmp -h` names it ("29 Sep 2021 - Update 2"): its date and update number.
struct LammpsVersion {
  int year = 0, month = 0, day = 0;
  int update = 0;
  std::string text;  // as LAMMPS printed it
  long ordinal() const { return (year * 100L + month) * 100L + day; }
};
// What every LAMMPS prints of its name, `lmp -h` and its log alike.
inline constexpr std::string_view kLammpsBanner = "Large-scale Atomic/Molecular Massively Parallel Simulator";
// The version in `lmp -h`'s text (its line "Large-scale Atomic/Molecular Massively Parallel
// Simulator - 29 Sep 2021 - Update 2"); none when no such line is there.
std::optional<LammpsVersion> parse_lammps_version(std::string_view help_text);

// How a family of LAMMPS releases forms what the mapping depends on, each read from that
// release's source (the ranges and sources in lammps_rule_sets()):
enum class LammpsWallModulus {
  one_minus_nu,          // fix wall/gran's hertz/material E* = E / (2 (1 - nu)) (fix_wall_gran.cpp, 2021)
  one_minus_nu_squared,  // E / (2 (1 - nu^2)), as pair granular (gran_sub_mod.cpp's mix_stiffnessE_wall)
};
enum class LammpsDamping {
  tsuji_match,        // `damping tsuji` with the e' whose polynomial alpha(e') is sqrt(5) |beta(e)|
  coeff_restitution,  // `damping coeff_restitution` with e itself: LIGGGHTS's law (gran_sub_mod_damping.cpp)
};
struct LammpsRules {
  std::string name;                 // e.g. "LAMMPS 29 Sep 2021"
  LammpsVersion first, last;        // the releases covered (by date; every update of them)
  LammpsWallModulus wall = LammpsWallModulus::one_minus_nu;
  LammpsDamping damping = LammpsDamping::tsuji_match;
  bool run_here = false;            // checked against a real binary of the family (else from source only)
  std::string source;               // where the forms were read, and how they were checked
  bool covers(const LammpsVersion& v) const { return v.ordinal() >= first.ordinal() && v.ordinal() <= last.ordinal(); }
};
// Every family of releases whose rules granstack knows, oldest first.
const std::vector<LammpsRules>& lammps_rule_sets();
// The family `v` belongs to; none for a release whose rules are not known.
const LammpsRules* lammps_rules_for(const LammpsVersion& v);
// The rules of the LAMMPS this project runs its tests on (Debian 12's, 29 Sep 2021): refsim's
// LAMMPS contact rules reproduce this release's arithmetic.
const LammpsRules& lammps_rules_run_here();
// "29 Sep 2021 (every update; run against Debian 12's binary); 27 Jun 2024 to 22 Jul 2025 (written
// from their source, not run)": for the refusal of another version and the docs.
std::string known_lammps_versions();

// One type pair's (or a wall's) coefficients for LAMMPS.
struct LammpsContact {
  double youngs_modulus = 0.0;  // E', Pa
  double poisson_ratio = 0.0;   // nu'
  double tsuji_restitution = -1.0;  // e' for `damping tsuji`; < 0: undamped (restitution 1)
  double tangential_stiffness = 0.0;  // mindlin's k_t / sqrt(R* d) = 8 G*, Pa
  double tangential_damping = 0.0;    // mindlin's eta_t / eta_n
  double friction = 0.0;              // mu
};

// The (E', nu') that LAMMPS turns into the E* and G* of materials a and b: a's own values when
// a and b are the same material.
void lammps_moduli(const Material& a, const Material& b, double& youngs_modulus, double& poisson_ratio);
// A sphere of material a against a sphere of material b (`wall`: against a wall of material b),
// for a LAMMPS of the family `rules`.
LammpsContact lammps_contact(const Material& a, const Material& b, double restitution, double friction, bool wall,
                             const LammpsRules& rules);
// The words after `pair_coeff I J` (or `wall/gran granular`): "hertz/material E D nu damping
// tsuji tangential ...", every number with 17 significant digits; D is e' for tsuji, e itself for
// coeff_restitution.
// The tangential word is the tangential model's (`mindlin`, or `mindlin_rescale`) where c has friction.
std::string lammps_contact_words(const LammpsContact& c, const LammpsRules& rules,
                                 TangentialModel tangential = TangentialModel::history);

// Why this spec cannot run on a LAMMPS of the family `rules` with granstack's mapping ("" when it
// can): the normal model hooke, rolling friction, restitution whose damping tsuji cannot give
// (releases without coeff_restitution), per-rank dumps.
std::string lammps_unmappable(const StackSpec& spec, const LammpsRules& rules);
// ... its contact law alone (all but the dumps): what refsim by LAMMPS's rules needs too.
std::string lammps_contact_unmappable(const StackSpec& spec, const LammpsRules& rules);

}  // namespace granstack::model
