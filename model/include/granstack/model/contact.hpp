#pragma once
// Hertz contact parameters and the analytic formulas of physics.md sections 2 and 5.
#include <granstack/model/material.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::model {

inline constexpr double kPi = 3.14159265358979323846;
// A Hertz contact starts to yield when its peak pressure reaches 1.6 Y of the softer body (Johnson,
// Contact Mechanics, section 6.2; nu = 0.3): the elastic-plastic laws' default p_y / Y.
inline constexpr double kDefaultYieldPressureFactor = 1.6;

// Effective quantities of one contact, as LIGGGHTS 3.8.0 forms them (docs/liggghts.md section 1).
struct ContactPair {
  double y_star = 0.0;  // Pa: 1/Y* = (1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j
  double g_star = 0.0;  // Pa: 1/G* = 2(2-nu_i)(1+nu_i)/Y_i + 2(2-nu_j)(1+nu_j)/Y_j
  double r_star = 0.0;  // m: R_i R_j / (R_i + R_j); a wall contributes R* = R_i
  double m_star = 0.0;  // kg: m_i m_j / (m_i + m_j); a wall contributes m* = m_i
};

// Sphere mass, in LIGGGHTS's operation order (4/3 pi r^3 rho).
double sphere_mass(double radius, double density);
// A sphere's kinetic energies, J: 1/2 m |v|^2, and 1/2 I |w|^2 with I = 0.4 m r^2 (a solid sphere,
// fix nve/sphere's), in the order reduce and refsim's in-situ evaluation both take them.
inline double translational_energy(double m, double vx, double vy, double vz) {
  return 0.5 * m * (vx * vx + vy * vy + vz * vz);
}
inline double rotational_energy(double m, double radius, double wx, double wy, double wz) {
  return 0.5 * (0.4 * m * radius * radius) * (wx * wx + wy * wy + wz * wz);
}

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

// The contact model: LIGGGHTS 3.8's normal, tangential and rolling-friction models that
// granstack runs in both engines (refsim to the bit, tests/data/twobody). The formulas of each
// live here; the engines evaluate them in LIGGGHTS's operation order.
//   normal hertz (normal_model_hertz.h): F = 4/3 Y* sqrt(R* d) d, damped with beta(e);
//   normal hooke (normal_model_hooke.h): F = k_n d, k_n = hooke_stiffness (a linear spring
//     whose largest overlap at the characteristic velocity is Hertz's), damped with
//     gamma_n = sqrt(4 m* k_n ln(e)^2 / (ln(e)^2 + pi^2)): restitution exactly e;
//   tangential history: an elastic-Coulomb spring on the sliding displacement;
//     no_history: viscous, F_t = -min(gamma_t, mu |F_n| / |v_t|) v_t (no spring, no memory);
//     mindlin_rescale (LAMMPS's pair_style granular; LIGGGHTS has none): history's Mindlin
//     spring, k_t = 8 G* a with a = sqrt(R* d), whose displacement is scaled by a / a_last when
//     the contact radius shrinks (unloading), so the spring's force follows the contact's area;
//   rolling epsd2 (rolling_model_epsd2.h): an elastic-plastic torque spring of stiffness
//     k_t R*^2 on the relative rotation, capped at mu_r R* |F_n|.
//   rolling cdt (rolling_model_cdt.h): a constant directional torque, mu_r R* k_n delta against
//     the relative rotation (no spring, no history).
//   normal thornton (Thornton 1997, ASME J. Appl. Mech. 64:383): elastic-perfectly-plastic, Hertz up
//     to the yield pressure p_y, then loading linear in d, unloading Hertzian about the enlarged
//     radius R_p; the force a function of (d, d_max), evaluated exactly each step (refsim only);
//   normal thornton_ning (normal_model_thornton_ning.h, surfaceEnergy 0): LIGGGHTS 3.8's
//     incremental elastic-plastic law, yield at a_y = r_i * coefficientYieldRatio[type_i], unloading
//     about R* (physics.md section 7 says how it differs from Thornton's).
enum class NormalModel { hertz, hooke, thornton, thornton_ning };
inline constexpr std::size_t kNormalModelCount = 4;  // the rows of every table by NormalModel
enum class TangentialModel { history, no_history, mindlin_rescale };
inline constexpr std::size_t kTangentialModelCount = 3;  // the rows of contact_models.cpp's table
enum class RollingModel { off, epsd2, cdt };
inline constexpr std::size_t kRollingModelCount = 3;

// A sub-model as the spec, the decks and the reference name it: one row of contact_models.cpp's
// table per model, in the enum's order (a new model is a row there).
struct SubModelInfo {
  std::string_view keyword;         // the spec's value, and LIGGGHTS's keyword where LIGGGHTS has it
  std::string_view help;            // for the spec's help: the keyword and, in brackets, what it is
  std::string_view doc;             // the reference's note on it, or ""
  std::string_view lammps_refusal;  // why the LAMMPS mapping cannot run it, or "" where it does
  std::string_view liggghts_refusal = {};  // why LIGGGHTS 3.8 cannot run it, or "" where it does
  std::string_view lammps_word = {};  // a tangential model's word in LAMMPS's pair_coeff and wall/gran
};
const SubModelInfo& info(NormalModel m);
const SubModelInfo& info(TangentialModel m);
const SubModelInfo& info(RollingModel m);
template <typename Model>
std::vector<Model> all_models();  // every NormalModel, TangentialModel or RollingModel, in order
// "'hertz' or 'hooke'": the keywords as the spec's error messages list them; without the
// default's and unquoted (`beyond_default`), "epsd2 or cdt": the models that are on.
template <typename Model>
std::string keyword_list(bool beyond_default = false);

std::string_view to_string(NormalModel m);      // info(m).keyword
std::string_view to_string(TangentialModel m);
std::string_view to_string(RollingModel m);
std::optional<NormalModel> parse_normal_model(std::string_view s);
std::optional<TangentialModel> parse_tangential_model(std::string_view s);
std::optional<RollingModel> parse_rolling_model(std::string_view s);

struct ContactModel {
  NormalModel normal = NormalModel::hertz;
  TangentialModel tangential = TangentialModel::history;
  RollingModel rolling = RollingModel::off;
  double characteristic_velocity = 0.0;  // m/s, hooke's calibration speed (unused by hertz)
  // The elastic-plastic laws' yield pressure p_y over the softer body's yield strength Y: 1.6 at
  // first yield (Johnson), about 3 fully plastic (physics.md section 7).
  double yield_pressure_factor = kDefaultYieldPressureFactor;
  // hertz, history, no rolling friction: the study's model (refsim's vector kernels run it).
  bool is_study_model() const {
    return normal == NormalModel::hertz && tangential == TangentialModel::history && rolling == RollingModel::off;
  }
  bool operator==(const ContactModel&) const = default;
};
// Why granstack's LAMMPS mapping has no counterpart for a sub-model of `m` (its row's
// lammps_refusal, the first that has one), or "".
std::string_view lammps_refusal(const ContactModel& m);
// ... LIGGGHTS 3.8 has no counterpart for (its row's liggghts_refusal), or "".
std::string_view liggghts_refusal(const ContactModel& m);
// ... refsim by LIGGGHTS's rules cannot run: LIGGGHTS's refusals of the tangential and rolling
// models alone (refsim has a kernel in LIGGGHTS's frame for every normal model, its own
// thornton included).
std::string_view refsim_liggghts_refusal(const ContactModel& m);

// The words after 'pair_style gran' and 'fix ... wall/gran': "model hertz tangential history",
// with " rolling_friction epsd2" (or cdt) when a rolling model is on.
std::string liggghts_model_words(const ContactModel& m);

// Hooke's spring constant, 16/15 sqrt(R*) Y* (15 m* v_c^2 / (16 sqrt(R*) Y*))^(1/5), in
// normal_model_hooke.h's operation order (so refsim gets LIGGGHTS's double).
double hooke_stiffness(const ContactPair& c, double characteristic_velocity);
// A normal model's law, one row per NormalModel (contact.cpp's table, of kNormalModelCount rows):
// its name in messages, whether its stiffness takes m* (Hooke's calibration), whether it is
// Hertz's d^(3/2) while elastic (whose chains carry Nesterenko's solitary waves), whether it
// dissipates without damping (yield) and whether its force depends on the contact's past (its
// largest overlap), and its formulas. A path-dependent law has no energy of the overlap alone
// (`energy` is null: a dump's overlaps cannot give it); force, max_overlap and contact_time are
// its elastic branch (below yield), which the time step and the wave analysis take.
struct NormalLaw {
  SubModelInfo info;  // its keyword, help, reference note and the engines' refusals
  const char* name;
  bool needs_mass;
  bool hertzian;
  bool dissipative;
  bool path_dependent;
  bool needs_yield;  // p_y from the yield strengths: every material of its contacts needs one
  // Its run reports each contact's elastic energy and dissipated work in the in-situ series
  // (series_contact_columns, stack.hpp): refsim's own thornton, whose energies are functions of
  // the overlap and the largest overlap; no other engine runs it.
  bool series_energy;
  // The automatic time step's steps per (Hertz) contact time: 100 for the laws evaluated exactly
  // each step; 1000 for thornton_ning, whose incremental force is first order in dt (an elastic
  // impact gains e - 1 = 1.4 dt / t_c: 0.15 % at t_c / 1000, physics.md section 7).
  double steps_per_contact;
  // The law LIGGGHTS runs for it where a run is confirmed on LIGGGHTS (design confirm): itself, or
  // the nearest LIGGGHTS 3.8 has where it has none (Thornton 1997's: thornton_ning, physics.md
  // section 7 says how they differ).
  NormalModel on_liggghts;
  double (*force)(const ContactModel& m, const ContactPair& c, double overlap);
  double (*energy)(const ContactModel& m, const ContactPair& c, double overlap);
  double (*max_overlap)(const ContactModel& m, const ContactPair& c, double relative_speed);
  double (*contact_time)(const ContactModel& m, const ContactPair& c, double relative_speed);
};
const NormalLaw& normal_law(NormalModel m);
// The elastic part of the normal force at overlap d, and the energy stored in it (a
// path-dependent law's: std::logic_error, ask has_overlap_energy first).
double elastic_normal_force(const ContactModel& m, const ContactPair& c, double overlap);
double elastic_energy(const ContactModel& m, const ContactPair& c, double overlap);
inline bool has_overlap_energy(const ContactModel& m) { return !normal_law(m.normal).path_dependent; }

// Thornton (1997)'s elastic-perfectly-plastic contact of a pair (its E* = y_star, R*, m*) at yield
// pressure p_y (physics.md section 7): the contact radius and overlap at first yield, a_y = pi R*
// p_y / (2 E*) and d_y = a_y^2 / R*; the force at overlap d after the largest overlap d_max >= d
// (Hertz to d_y, then F_y + pi p_y R* (d - d_y) while loading; unloading Hertz about R_p = 4 E*
// a_p^3 / (3 F_max), a_p^2 = R* d_max, from the residual overlap d_p = d_max - R* d_max / R_p,
// zero below it); the elastic energy it would return from there, and the work it has dissipated
// (loading work to d_max less what unloading returns); the speed V_y of a head-on impact that
// just reaches yield (1/2 m* V_y^2 = Hertz's energy at d_y), and the restitution of the closed
// form at x = V_y / V <= 1 (1 at and below V_y).
struct ThorntonLaw {
  double y_star, r_star;  // E*, R*
  double yield_pressure;  // p_y, Pa
  double yield_overlap;   // d_y
  double yield_force;     // F_y, Hertz's at d_y
  double slope;           // pi p_y R*, the plastic loading stiffness
  bool operator==(const ThorntonLaw&) const = default;
};
ThorntonLaw thornton_law(const ContactPair& c, double yield_pressure);
double thornton_force(const ThorntonLaw& l, double overlap, double max_overlap);
struct ThorntonState {
  double force;       // N
  double elastic;     // J, returned on unloading to d_p
  double dissipated;  // J, at d_max
};
ThorntonState thornton_state(const ThorntonLaw& l, double overlap, double max_overlap);
double thornton_yield_velocity(const ContactPair& c, double yield_pressure);
double thornton_restitution(double yield_velocity, double impact_velocity);
// An undamped head-on collision at relative speed v: its largest overlap and its duration
// (Hertz: physics.md section 5; Hooke: v sqrt(m*/k_n) and pi sqrt(m*/k_n), whatever v).
double max_overlap(const ContactModel& m, const ContactPair& c, double relative_speed);
double contact_time(const ContactModel& m, const ContactPair& c, double relative_speed);

// Restitution damping coefficient beta = ln(e) / sqrt(ln(e)^2 + pi^2) (docs/liggghts.md section 1).
double restitution_beta(double e);

// LAMMPS's tsuji damping (model/lammps.hpp maps LIGGGHTS's restitution onto it): its
// coefficient alpha(e), 1.2728 - 4.2783 e + ... + 4.8218 e^6, in
// pair_granular.cpp's operation order (so the double is LAMMPS's own).
double tsuji_alpha(double e);
// The restitution e' in [0, 1] whose tsuji_alpha is nearest `alpha`; alpha must lie within
// [tsuji_alpha(1), tsuji_alpha(0)] (tsuji_alpha falls monotonically there).
double tsuji_restitution_for(double alpha);
// The LAMMPS tsuji restitution that gives LIGGGHTS's damping for restitution e (e < 1), or a
// negative number where no e' in [0, 1] does.
double lammps_tsuji_restitution(double e);

}  // namespace granstack::model
