#pragma once
// The in-house reference integrator: Hertz contact with tangential history and planar walls,
// integrated with nve/sphere velocity Verlet, following LIGGGHTS 3.8.0 operation by operation
// (docs/liggghts.md sections 1 to 3) so that two-body cases reproduce its dumps to round-off.
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <granstack/model/contact.hpp>
#include <granstack/os/workers.hpp>
#include <granstack/refsim/aligned.hpp>

namespace granstack::refsim {

namespace detail {
struct PairTable;
struct PairConstants;
struct ModelConstants;
struct Motion;
struct SumPlan;
struct VectorKernels;
struct ContactEnergy;
struct ContactStep;
}  // namespace detail

using Vec3 = std::array<double, 3>;

// A planar wall perpendicular to `axis` (0 = x, 1 = y, 2 = z) at `position`, two-sided, of
// material type `type` (1-based, indexes the property tables).
struct Wall {
  int axis = 2;
  double position = 0.0;
  int type = 0;
};

// A wall that is a plate of finite mass on a mount (model::StackSpec::plate_mass), moving along
// its wall's axis: pushed by the force the particles take from it (the stored wall's, summed as
// System::stored_wall_total does) and by its mount (model::plate_force), integrated as fix
// nve/sphere integrates an atom of its mass; its particles' contacts see its velocity. LIGGGHTS's
// deck moves a mesh with such an atom, its body (model::plate_body), whose own position the
// mount's spring reads: refsim keeps both, the wall's travel (the mesh's, summed from 0) and the
// body's position (from `body_start`), each in its engine's arithmetic.
struct Plate {
  int wall = -1;  // into Parameters::walls, the stored wall; -1: none
  double mass = 0.0, stiffness = 0.0, damping = 0.0;
  double body_start = 0.0;  // m, along the wall's axis
};

struct Parameters {
  double dt = 0.0;
  double skin = 0.0;                     // neighbour skin, m
  double contact_distance_factor = 1.01; // the deck's neigh_modify contact_distance_factor
  Vec3 gravity{0.0, 0.0, 0.0};           // m/s^2 (fix gravity's acceleration vector)
  int types = 0;
  // Per type pair, index (a - 1) * types + (b - 1): effective moduli, damping beta, friction.
  std::vector<double> y_star, g_star, beta, friction;
  // The contact model (model/contact.hpp); any but the study's runs on the reference kernels.
  // With it, per type pair: the restitution e (hooke's damping takes ln e) and epsd2's mu_r.
  model::ContactModel contact;
  std::vector<double> restitution, rolling_friction;
  // thornton: the yield pressure p_y per type pair (Pa); thornton_ning: coefficientYieldRatio per
  // type (index type - 1), as the deck writes it.
  std::vector<double> yield_pressure, yield_ratio;
  std::vector<Wall> walls;               // applied after the pair forces, in this order
  // The wall (index into walls) whose force on each particle is kept, as fix wall/gran's
  // store_force yes keeps it (System::stored_wall_force); -1: none.
  int stored_wall = -1;
  Plate plate;
  bool tangential_damping = true;
  // LAMMPS's rules instead of LIGGGHTS's for the same spec (model/lammps.hpp; the sub-models they
  // choose, refsim/src/contact_models/choice.hpp): LAMMPS's frame, hertz/material with tsuji damping
  // of the mapped coefficient, mindlin with friction and no tangential force without, fix
  // wall/gran's walls. The reference kernels run them; a model LAMMPS lacks is refused.
  bool lammps_rules = false;
  // Threads for the force and integration loops. Every per-particle sum keeps the pair order
  // of one thread, so the result does not depend on the thread count, to the bit.
  int threads = 1;
  // The kernels: "reference" (scalar, the model written out), a vector instruction set of
  // vector_kernels() (same operations in the same order, so the same bits), or "auto", the
  // first of vector_kernels().
  std::string kernel = "auto";
};

// The instruction sets this CPU runs refsim's vector kernels in, best first ("avx512", "avx2",
// "sse4", "ssse3" on x86, "neon" on ARM, "scalar" everywhere: those this build has).
std::vector<std::string> vector_kernels();

struct Particle {
  int type = 1;
  double radius = 0.0;
  double mass = 0.0;
  Vec3 x{}, v{}, omega{};
};

class System {
 public:
  System(std::vector<Particle> particles, Parameters params);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // The force call at the start of a run: forces and torques without advancing the
  // tangential history (LIGGGHTS's setup, shearupdate = 0).
  void setup();
  // One step: half kick and drift, neighbour check, forces, half kick.
  void step();
  // `steps` steps, each step's last half kick and the next one's first half taken together
  // particle by particle (the same operations): the state is observable only at the end.
  void advance(long steps);

  long step_count() const { return step_; }
  std::size_t size() const { return n_; }
  int type(std::size_t i) const { return type_[i]; }
  double radius(std::size_t i) const { return radius_[i]; }
  double mass(std::size_t i) const { return mass_[i]; }
  Vec3 x(std::size_t i) const { return get(x_, i); }
  Vec3 v(std::size_t i) const { return get(v_, i); }
  Vec3 omega(std::size_t i) const { return get(w_, i); }
  Vec3 force(std::size_t i) const { return get(f_, i); }
  Vec3 torque(std::size_t i) const { return get(t_, i); }
  long neighbor_builds() const { return builds_; }
  // Parameters::stored_wall's force on particle i in the last force call: i's force after the
  // wall's contribution minus before it (fix_wall_gran_base.h), 0 when it does not touch.
  Vec3 stored_wall_force(std::size_t i) const {
    return {wall_store_[3 * i], wall_store_[3 * i + 1], wall_store_[3 * i + 2]};
  }
  // The stored wall's force on every particle along its axis, summed from 0 in particle order (as
  // the deck's compute reduce sum takes it): the load the wall carries, its push on the particles.
  double stored_wall_total() const;
  // Parameters::plate's state after the last step: its displacement from where its wall stood at
  // the start (m, along the wall's axis: its body's travel, as the deck's series writes it), its
  // velocity (m/s) and the force on it (N); 0 without one.
  double plate_displacement() const { return plate_body_ - p_.plate.body_start; }
  double plate_velocity() const { return plate_v_; }
  double plate_force() const { return plate_f_; }
  double plate_acceleration() const { return p_.plate.wall >= 0 ? plate_f_ / p_.plate.mass : 0.0; }  // m/s^2
  // The kinetic energies of particles [begin, end), translational and rotational, as the
  // in-situ series reports them (0.5 m |v|^2 and 0.5 I |w|^2 with I = 0.4 m r^2, fix
  // nve/sphere's solid spheres). Each sum is taken in eight partial sums (particle begin + k
  // into sum k mod 8) added pairwise, ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7)): the same
  // bits with every kernel.
  std::array<double, 2> kinetic_energy(std::size_t begin, std::size_t end) const;
  // "reference", a vector instruction set, or one with kReferencePairs appended: a model the vector
  // pair kernels do not run (other than thornton without friction, whose pairs they run in lanes)
  // has its pairs on the reference kernel, its particles on the vector kernels (the same bits as
  // the reference, either way).
  const std::string& kernel() const { return kernel_; }
  static constexpr const char* kReferencePairs = ", pairs on the reference";

  // Where the normal law keeps each contact's energy with its history (refsim's thornton), per
  // particle: the elastic energy in its contacts now and the work they have dissipated since the
  // start, opened contacts' included; a pair contact's half to each sphere, a wall contact's all
  // to the sphere. Empty vectors for a law that keeps none.
  struct ContactEnergies {
    std::vector<double> elastic, dissipated;
  };
  ContactEnergies contact_energies() const;

  // Runs job(begin, end) over shares of [0, count) on this system's threads, between steps
  // (for outputs written in line, while the threads would only wait).
  void run_in_shares(std::size_t count, const std::function<void(std::size_t, std::size_t)>& job) { for_shares(count, job); }

 private:
  Vec3 get(const detail::AlignedVector<double>& a, std::size_t i) const { return {a[i], a[stride_ + i], a[2 * stride_ + i]}; }
  void choose_kernels();
  void choose_pair_kernels(const std::string& target);
  void build_pairs();
  void compute_forces(bool update_history, bool kick, bool drift);
  void sum_forces(std::size_t begin, std::size_t end, bool update_history, bool kick, bool drift);
  void wall_force(std::size_t i, std::size_t w, bool update_history);
  std::size_t wall_type_pair(std::size_t i, std::size_t w) const;  // into the type-pair tables
  detail::ContactEnergy wall_contact_energy(std::size_t i, std::size_t w, double overlap) const;
  void bank_lost_pairs(const detail::PairTable& old, const std::vector<std::size_t>& kept);
  void external_forces(std::size_t begin, std::size_t end, bool update_history);  // walls then gravity
  detail::Motion motion();

  // job(begin, end) on every thread's share of [0, count), its bounds multiples of `align`; on
  // the caller alone with one thread.
  void for_shares(std::size_t count, const std::function<void(std::size_t, std::size_t)>& job, std::size_t align = 1) {
    workers_->for_shares(count, job, align);
  }

  std::size_t n_ = 0;
  Parameters p_;
  std::vector<int> type_;
  std::vector<double> radius_, mass_;
  detail::AlignedVector<double> kick_, spin_kick_;  // dtf / m and dtfrotate / (r^2 m), as fix nve/sphere forms them
  // Structure of arrays: component d of particle i at d * stride_ + i. The stride, a multiple
  // of eight, keeps every component on cache lines and leaves room for the contact kernel's
  // 16-wide loads past the last particle.
  std::size_t stride_ = 0;
  detail::AlignedVector<double> x_, v_, w_, f_, t_, x_at_build_;
  // Per group of eight particles, bit k: particle 8 * group + k got a new position in the last
  // drift (the vector first halves write it; the elastic contact kernel skips still pairs).
  std::vector<std::uint8_t> position_changed_;
  // Per group of eight particles: whether its force sums must be taken again this step (the
  // elastic kernel evaluated one of its pairs); skip_sums_ when that is known (compute_forces).
  std::vector<std::uint8_t> sums_due_;
  bool skip_sums_ = false;
  std::atomic<std::size_t> kept_sums_{0};  // groups whose sums the step kept

  std::vector<detail::PairConstants> type_constants_;  // per type pair, (a - 1) * types + (b - 1)
  std::vector<detail::ModelConstants> model_constants_;  // the same, for the contact models beyond hertz/history
  // Candidate pairs (i < j), rebuilt when a particle has moved more than half the skin.
  std::unique_ptr<detail::PairTable> pairs_;
  // Per particle, the other particle and its entry in the pair table's contribution arrays, in
  // LIGGGHTS's pair order: contributions_[contribution_offsets_[k] .. contribution_offsets_[k + 1]].
  std::vector<std::size_t> contribution_offsets_;
  std::vector<std::pair<std::int32_t, std::uint32_t>> contributions_;
  std::unique_ptr<detail::SumPlan> sum_plan_;  // the same sums a group of particles at a time (vector kernels)
  // Particles in tiles of kTile; the pairs whose i is in tile t are [tile_first_[t], tile_first_[t + 1]).
  static constexpr std::size_t kTile = 64;
  std::vector<std::size_t> tile_first_;
  // Each wall contact's history, history_layout(...).size values per particle and wall.
  std::vector<double> wall_history_;
  std::vector<double> wall_store_;    // stored_wall_force, 3 per particle
  // Per particle, the work dissipated by its contacts that have opened (ContactStep::banked),
  // where the normal law keeps it; empty otherwise.
  std::vector<double> banked_;
  // Per particle and wall: it touched the wall at its last force call, so its history or stored
  // force may be nonzero. One that did not, and does not touch it now, has nothing to compute or
  // clear: external_forces skips it (most of a stack's spheres, most steps).
  std::vector<std::uint8_t> wall_touched_;
  // Per wall, the particles that may touch it before the next neighbour build (in order): those
  // within a skin of it at the build, or touching it. A particle moves less than half a skin
  // between builds (the rebuild test), so no other can reach the wall until the next one.
  std::vector<std::vector<std::uint32_t>> wall_near_;
  void find_wall_candidates();
  // Where wall w stands now: its position, moved by the plate's displacement where it is the plate.
  double wall_position(std::size_t w) const {
    return static_cast<int>(w) == p_.plate.wall ? p_.walls[w].position + plate_z_ : p_.walls[w].position;
  }
  // The plate's force after the particles' sums, its second half kick (kick) and the next step's
  // first half (drift); plate_first_half alone where the particles take theirs apart.
  void plate_after_forces(bool kick, bool drift);
  void plate_first_half();
  double plate_z_ = 0.0, plate_v_ = 0.0, plate_f_ = 0.0;
  double plate_body_ = 0.0;           // its body's position (Plate::body_start at the start)
  double plate_body_at_build_ = 0.0;  // and at the last neighbour build
  bool external_ = false;             // walls or gravity
  bool negative_zero_spin_ = false;   // an angular velocity component starts at -0
  std::string kernel_;
  std::unique_ptr<detail::VectorKernels> vector_;  // the vector kernels, unless the reference runs
  bool vector_contacts_ = false;  // ... which compute the pairs' forces too (the study's model)
  // ... or, on a torque_free table, Thornton's law in lanes or another positional law's reference
  // forces, still blocks kept (VectorKernels::thornton, ::still_reference); null otherwise.
  void (*still_kernel_)(detail::PairTable&, const detail::ContactStep&, std::size_t, std::size_t) = nullptr;

  long step_ = 0;
  long builds_ = 0;
  bool drifted_ = false;              // the next step's first half is done
  std::atomic<bool> moved_{false};    // a particle moved half a skin in the last first half

  std::unique_ptr<os::Workers> workers_;  // the caller is its thread 0
};

}  // namespace granstack::refsim
