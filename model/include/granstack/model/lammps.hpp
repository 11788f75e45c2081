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
//     its own way (a model difference).
//   walls: this LAMMPS's fix wall/gran forms hertz/material's E* as E / (2 (1 - nu)), not
//     pair_granular's E / (2 (1 - nu^2)) (measured: a bottom-wall case agrees with LIGGGHTS to
//     1e-14 only with E' = 2 (1 - nu') E*), so a wall's E' is chosen for that form.
#include <granstack/model/contact.hpp>
#include <granstack/model/material.hpp>

#include <string>

namespace granstack::model {

class Stack;
struct StackSpec;

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
// A sphere of material a against a sphere of material b (`wall`: against a wall of material b).
LammpsContact lammps_contact(const Material& a, const Material& b, double restitution, double friction, bool wall);
// The words after `pair_coeff I J` (or `wall/gran granular`): "hertz/material E D nu damping
// tsuji tangential ...", every number with 17 significant digits.
std::string lammps_contact_words(const LammpsContact& c);

// Why this spec cannot run on LAMMPS with granstack's mapping ("" when it can): the normal model
// hooke, rolling friction, restitution whose damping LAMMPS's tsuji cannot give, per-rank
// dumps.
std::string lammps_unmappable(const StackSpec& spec);

}  // namespace granstack::model
