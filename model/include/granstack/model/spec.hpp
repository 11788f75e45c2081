#pragma once
// The specification of one nested-stack case (physics.md section 1), with its validation.
#include <granstack/model/contact.hpp>
#include <granstack/model/material.hpp>

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granstack::model {

enum class Boundary { free_surface, wall };
// The study's strip (one sphere thick, every centre at y = 0); nested 3D blocks: each block
// a cubic lattice of C_k x C_k columns, each sphere of a block's bottom layer resting on four of
// the block below (Sen, Krishna Mohan and Tiwari's 3D nests); or the study's container: P strips
// side by side along y at a pitch of the top spheres' diameter, with a separator between them.
enum class Geometry { strip, nested3d, panels };
// What fills the step-shaped gap between neighbouring panels: a matrix of soft spheres (chains
// bridging each pocket of a panel to the same pocket of the next), rigid walls (planes midway
// between panels), or nothing.
enum class Separator { matrix, walls, none };
// How a block's bottom row rests on the block below: by the ratio's parity (the study's: an even
// ratio nests each sphere on two below, an odd one sets it on the one straight below), nested on
// two at every interface, or aligned on the one straight below at every interface. Where the
// choice goes against the ratio's parity, the lower block has one column more (n C_k + 1), so
// that every sphere of the row above rests as chosen (model::columns_below).
enum class Stacking { by_ratio, nested, aligned };
enum class DumpFormat { text, binary };
// How a run ends: after its duration, or at the dump frame where the blow has ended
// (model::BlowEnd, docs/physics.md section 7), at most cap_durations automatic durations.
enum class StopRule { duration, blow_end };
// One dump file; one per dumped step (LIGGGHTS's '*'); one per MPI rank (its '%').
enum class DumpFiles { single, per_step, per_rank };
// A thornton_ning case no yield ratios make order-independent (model::thornton_ning_plan: an atom
// type of two radii): refused, or accepted by name, its contacts' yield then depending on which
// sphere LIGGGHTS calls i.
enum class OrderDependentYield { refuse, accept };

std::string_view to_string(Boundary b);       // "free" | "wall"
std::string_view to_string(DumpFormat f);     // "text" | "binary"
std::optional<Boundary> parse_boundary(std::string_view s);
std::string_view to_string(Geometry g);
std::optional<Geometry> parse_geometry(std::string_view s);
std::string_view to_string(Separator s);  // "matrix" | "walls" | "none"
std::optional<Separator> parse_separator(std::string_view s);
std::string_view to_string(Stacking s);   // "by_ratio" | "nested" | "aligned"
std::optional<Stacking> parse_stacking(std::string_view s);
std::optional<DumpFormat> parse_dump_format(std::string_view s);
std::string_view to_string(DumpFiles f);      // "single" | "per_step" | "per_rank"
std::optional<DumpFiles> parse_dump_files(std::string_view s);
std::string_view to_string(StopRule r);       // "duration" | "blow_end"
std::string_view to_string(OrderDependentYield o);  // "refuse" | "accept"
std::optional<OrderDependentYield> parse_order_dependent_yield(std::string_view s);
std::optional<StopRule> parse_stop_rule(std::string_view s);

// A run that stops at the blow's end runs at most this many automatic durations by default (the
// cap): a blow not ended by then is censored, its measures not final. At least
// kMinBlowEndCapDurations: the hold alone lasts up to one automatic duration (two arrivals of a
// soft cavity's seven), so a shorter cap could end no blow that starts late in the run.
inline constexpr double kBlowEndCapDurations = 20.0;
inline constexpr double kMinBlowEndCapDurations = 2.0;
inline constexpr double kMaxBlowEndCapDurations = 1000.0;

// A coefficient that has one value for every material pair, optionally overridden for
// particular (unordered) pairs, e.g. restitution 0.9 but 0.8 between steel and teflon.
struct PairTable {
  double value = 0.0;
  std::map<std::pair<std::string, std::string>, double> pairs;  // keys stored with first <= second

  double get(const std::string& a, const std::string& b) const;
  void set(const std::string& a, const std::string& b, double v);
  // Whether every pair has v (the default and every pair given).
  bool everywhere(double v) const;
  bool operator==(const PairTable&) const = default;
};

struct StackSpec {
  Geometry geometry = Geometry::strip;
  // geometry = panels only (refused elsewhere when set): the number of panels P, 2..kMaxPanels;
  // the panel the striker hits (1 = smallest y; 0 = the centre one, (P + 1) / 2; kAllPanels: a
  // striker on every panel); what separates them; and the matrix's material (empty: the
  // study's soft material, teflon).
  int panels = 0;
  int impact_panel = 0;
  Separator separator = Separator::matrix;
  std::string matrix_material;
  int blocks = 4;                              // N_B; block 1 is the top (impacted) block
  int rows = 8;                                // spheres per column, the same in every block
  std::vector<int> block_rows;                 // per block, top first; empty: `rows` in every block
  int top_columns = 2;                         // columns of block 1 (even; per direction in 3D); block k has top_columns * ratio^(k-1)
  double bottom_radius = 1e-3;                 // m, radius of the bottom block's spheres
  int radius_ratio = 2;                        // R_k / R_{k+1} at every interface
  std::vector<int> radius_ratios;              // per interface, top first (N_B - 1); empty: radius_ratio at each
  Stacking stacking = Stacking::by_ratio;      // how a block rests on the one below
  std::vector<std::string> materials{"steel"}; // per block, top first; one name means every block
  std::vector<Material> custom_materials;      // defined by the spec
  PairTable restitution{1.0, {}};              // e, 0.05 < e <= 1
  PairTable friction{0.0, {}};                 // Coulomb mu >= 0
  double striker_speed = 1.0;                  // m/s, along -z
  // The striker's radius over the top block's, from 1 to 16: it rests on the two central top
  // spheres (the four in 3D; seat_height). 2 with one row of two spheres is the isolated collision of physics.md
  // section 5 (a large sphere on two small ones, the interface's geometry).
  double striker_radius_ratio = 1.0;
  std::string striker_material;                // empty: the top block's material
  // An off-centre blow: the striker rests on top spheres C/2 + k and C/2 + k + 1 of block 1's C
  // columns, k top-sphere diameters along +x from the centre (|k| <= C/2 - 1; along x only in 3D).
  int impact_offset = 0;
  Boundary bottom = Boundary::free_surface;
  Boundary sides = Boundary::free_surface;
  std::string wall_material;                   // empty: the bottom block's material
  // The protected object (docs/physics.md section 7): with a bottom wall, a plate of plate_mass
  // (kg) that the stack strikes, moving along z on a mount to the ground of mount_stiffness (N/m)
  // and mount_damping (N s/m); 0: the rigid wall, a plate of infinite mass.
  double plate_mass = 0.0;
  double mount_stiffness = 0.0;
  double mount_damping = 0.0;
  double gravity = 0.0;                        // m/s^2 along -z; 0 = off
  std::optional<double> dt;                    // s; nullopt = automatic rule
  std::optional<double> duration;              // s; nullopt = automatic rule
  // blow_end: the run stops at the dump frame where the blow has ended, at most cap_durations
  // automatic durations (duration stays automatic; gravity is refused: the stack comes to rest).
  StopRule stop = StopRule::duration;
  double cap_durations = kBlowEndCapDurations;
  std::optional<int> dump_every;               // steps; nullopt = automatic
  std::optional<int> series_every;             // steps between in-situ energy samples; nullopt = automatic
  DumpFormat dump_format = DumpFormat::text;
  DumpFiles dump_files = DumpFiles::single;
  // The contact model (contact.hpp): the study's hertz / history / no rolling friction by default.
  NormalModel normal_model = NormalModel::hertz;
  TangentialModel tangential_model = TangentialModel::history;
  RollingModel rolling_model = RollingModel::off;
  PairTable rolling_friction{0.0, {}};         // mu_r, rolling_model = epsd2 only
  std::optional<double> characteristic_velocity;  // m/s, normal_model = hooke only; nullopt = striker_speed
  // p_y / Y of the elastic-plastic laws (thornton, thornton_ning): 1.6 first yield .. 3 fully plastic.
  double yield_pressure_factor = kDefaultYieldPressureFactor;
  OrderDependentYield order_dependent_yield = OrderDependentYield::refuse;  // thornton_ning only
  // Commands a deck template of the user's adds to granstack's ("fix viscous", "displace_atoms"):
  // a run executing them is accepted and names them (formats/deck_rules.hpp).
  std::vector<std::string> deck_additions;

  // The contact model with hooke's characteristic velocity resolved.
  ContactModel contact_model() const;

  // The material name of block k (1 = top).
  const std::string& block_material(int k) const;
  // Block k's rows, and R_k / R_(k+1) at the interface below block k (1 <= k < N_B).
  int rows_of(int k) const;
  int ratio_below(int k) const;
  // R_k / R_N: the product of the ratios from block k down (an integer, exact in a double).
  double radius_factor(int k) const;
  // The wall's material name (wall_material, or the bottom block's).
  const std::string& effective_wall_material() const;
  // Whether the stack has a wall: a bottom or side wall, or a container's rigid separators.
  bool has_walls() const;
  // Whether the bottom wall is a plate of finite mass on a mount (plate_mass > 0).
  bool has_plate() const { return plate_mass > 0.0; }
  // The striker's material name (striker_material, or the top block's).
  const std::string& effective_striker_material() const;
  // The matrix's material name (matrix_material, or teflon).
  const std::string& effective_matrix_material() const;
  // A container's panel whose impact path, output sphere and bottom row are measured: the one
  // the striker hits, the centre one by default and when every panel is hit; 1 otherwise.
  int measured_panel() const;
  bool strikes_every_panel() const;
  // Built-in materials plus custom_materials.
  MaterialLibrary material_library() const;
  bool operator==(const StackSpec&) const = default;
};

// What LIGGGHTS runs for `spec` where a run is confirmed on it (design confirm): the spec itself, or
// the same stack under the nearest normal law LIGGGHTS has (NormalLaw::on_liggghts: Thornton
// 1997's law as thornton_ning, the same yield pressure factor), its time step and its dump and
// series cadences that law's own (automatic: thornton_ning needs ten times Hertz's steps).
StackSpec liggghts_counterpart(const StackSpec& spec);

// One problem with a spec: the field (as named in spec files and flags) and what is wrong,
// including the allowed range.
struct SpecIssue {
  std::string field;
  std::string message;
};

class SpecError : public std::runtime_error {
 public:
  explicit SpecError(std::vector<SpecIssue> issues);
  const std::vector<SpecIssue>& issues() const { return issues_; }

 private:
  std::vector<SpecIssue> issues_;
};

// Every problem of the spec, empty when it is valid.
std::vector<SpecIssue> validate(const StackSpec& spec);
// Throws SpecError when validate() finds anything.
void require_valid(const StackSpec& spec);

// Bounds of physical sense, refused outside (docs/reference/spec.md's table states them):
// radii from 100 nm, the smallest scale the study claims (a steel sphere of that radius still
// holds about 4e8 atoms, but surface layers and adhesion, which Hertz contact leaves out, matter
// more and more below a micrometre, most at low impact speeds: docs/physics.md), to a metre;
inline constexpr double kMinRadius = 1e-7, kMaxRadius = 1.0;
// gravity up to 1000 m/s^2 (about 100 g, the top of geotechnical centrifuges);
inline constexpr double kMaxGravity = 1000.0;
// a protected plate's mass (kg), its mount's stiffness (N/m) and damping (N s/m) up to 1e12, far
// beyond a rigid wall's behaviour for any stack the radii allow;
inline constexpr double kMaxPlateValue = 1e12;
// Coulomb friction up to 10 (real materials stay below about 1.5; above, every contact sticks);
inline constexpr double kMaxFriction = 10.0;
// rolling friction up to 1 (the torque cap mu_r R* |F_n| is then the contact's whole lever);
inline constexpr double kMaxRollingFriction = 1.0;
// LIGGGHTS refuses a characteristic velocity below 1e-2 m/s in SI units (global_properties.cpp:235);
inline constexpr double kMinCharacteristicVelocity = 1e-2;
// The range of yield_pressure_factor: from first yield under the surface (Johnson: 1.6 Y at nu =
// 0.3, 1.5 Y at nu = 0.2) to the fully plastic indentation pressure (about 3 Y, Tabor's hardness).
inline constexpr double kMinYieldPressureFactor = 1.5;
inline constexpr double kMaxYieldPressureFactor = 3.0;
// a striker from 1 to 16 times the top spheres' radius (the range of radius_ratio);
inline constexpr double kMaxStrikerRadiusRatio = 16.0;
// densities from 1 kg/m^3 to 1e5 (osmium is 22 590) and Young's moduli from 1 kPa (soft gels) to
// 10 TPa (diamond is 1.2 TPa).
inline constexpr double kMinDensity = 1.0, kMaxDensity = 1e5;
inline constexpr double kMinYoungsModulus = 1e3, kMaxYoungsModulus = 1e13;
// The most panels side by side (a container of the study's Fig. 1b has a handful).
inline constexpr int kMaxPanels = 64;
// impact_panel's value for a striker on every panel (spec files and flags: "all").
inline constexpr int kAllPanels = -1;

// The most spheres granstack will lay out in one case (a guard against typos such as 40 blocks).
// refsim's peak memory per million spheres of a 3D nest (bench/nest_scale.sh: 1.51 GB at 1 048 513).
inline constexpr double kRefsimGigabytesPerMillionSpheres = 1.5;
inline constexpr long kMaxSpheres = 4'000'000;
// True when nothing dissipates or adds energy: restitution 1 and friction 0 for every material
// pair, no dissipating rolling friction, no gravity, and a normal law that does not yield. Then
// kinetic plus elastic energy must stay at E_in.
bool is_conservative(const StackSpec& spec);
// ... but for the normal law's own dissipation (yield): then, where the run reports the work the
// law dissipated (model::series_contact_columns), kinetic plus elastic energy plus that work must
// stay at E_in.
bool only_the_law_dissipates(const StackSpec& spec);

// Spheres of the stack including the striker (8 C (2^N_B - 1) + 1 for the study's stacks).
long sphere_count(const StackSpec& spec);

}  // namespace granstack::model
