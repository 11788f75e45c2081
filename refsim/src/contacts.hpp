#pragma once
// refsim's inner loops, private to refsim: the sphere-sphere contacts over candidate pairs in
// structure-of-arrays form, each particle's force sums and the integrator's two halves, each in
// two implementations, the scalar reference (contacts.cpp, the model written out line by line)
// and the vector kernels (contacts_simd.cpp, one Highway source compiled for every instruction
// set, up to eight pairs or particles per instruction). All perform every floating-point
// operation of LIGGGHTS's hertz/history model and nve/sphere in its order, so they give the same
// bits; a test holds every target this CPU runs to that.
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <granstack/model/contact.hpp>
#include <granstack/refsim/aligned.hpp>
#include <granstack/refsim/neighbors.hpp>

#include "contact_models/choice.hpp"

namespace granstack::refsim::detail {

// Where eight lanes' values lie in an array: anywhere; within kWindow entries of a window; or
// at window + their lane number. The vector kernels load a run and gather the others; a window
// also tells which particles a block of pairs uses (the still test of the elastic kernel).
enum Fetch : std::uint8_t { kGather, kWindowed, kRun };

// The tables' groups (pairs or particles that share a window, a record, a sum plan's round: the
// lanes of an AVX-512 register, two AVX2 registers, four SSE or NEON ones), and the pairs of an
// elastic block (two groups). The tables are padded to whole blocks with entries of zero radius
// that never touch.
inline constexpr std::size_t kLanes = 8;
inline constexpr std::size_t kPairBlock = 2 * kLanes;

// What the Hertz model needs of one type pair: the left-most factors of LIGGGHTS's expressions
// (4./3.*Y, 2.*Y, 8.*G, -2.*sqrt(5/6)*beta), evaluated once as it evaluates them in every
// contact, so hoisting them changes no bit.
struct PairConstants {
  double kn_factor = 0.0, sn_factor = 0.0, st_factor = 0.0, damping_factor = 0.0, friction = 0.0;
  bool damped() const { return damping_factor != 0.0; }  // beta != 0, i.e. e < 1
};

// What a pair's contact needs of its two spheres, the same for every pair of two given types
// in a generated stack: the table keeps each distinct one once.
struct PairRecord {
  double radi, radj, reff, meff;
  double kn_factor, sn_factor, st_factor, damping_factor, friction;
  PairConstants constants() const { return {kn_factor, sn_factor, st_factor, damping_factor, friction}; }
  // e = 1 and mu = 0: both damping coefficients are +-0 and every path of the tangential model
  // gives a force of +-0, so the contact force is kn delta n and there is no torque (signs of
  // zeros aside, which never change a force sum that starts at +0), for finite velocities.
  bool elastic_frictionless() const { return damping_factor == 0.0 && friction == 0.0; }
};

// What the contact models beyond hertz/history need of one type pair (contact.hpp): hooke's
// Y* and ln(e) (normal_model_hooke.h takes the raw Y*, not 4/3 Y*), epsd2's mu_r, and hooke's
// characteristic velocity.
struct ModelConstants {
  double y_star = 0.0, restitution_log = 0.0, rolling_friction = 0.0, characteristic_velocity = 0.0;
  // LAMMPS's hertz/material with tsuji damping (contact_models/normal_tsuji.cpp): tsuji's alpha
  // (0: undamped) and mindlin's eta_t / eta_n.
  double lammps_alpha = 0.0, lammps_tangential_ratio = 0.0;
  // The elastic-plastic laws: Thornton's yield pressure p_y of the type pair (its factor times the
  // softer yield strength), and thornton_ning's coefficientYieldRatio of the pair's first type.
  double yield_pressure = 0.0, yield_ratio = 0.0;
};
// ... and of one pair, evaluated once per distinct pair as LIGGGHTS evaluates them in every
// contact: the normal model's own values (`law`, each model's record fills and its kernel reads
// them: hooke's k_n and gamma_n of R* and m*, Thornton's law of the pair, ...), and mu_r.
inline constexpr std::size_t kLawValues = 6;
struct ModelRecord {
  double rolling_friction = 0.0;
  double law[kLawValues] = {};
  bool operator==(const ModelRecord&) const = default;
};

// The candidate pairs (i < j), what does not change between neighbour-list builds, the
// tangential history, and what each contact gives its two spheres at the last force call.
// Non-touching pairs give zeros: adding +-0 to a force sum that started at +0 changes no bit.
// The order of the pairs is free (each particle adds its contributions in its own order), so
// they are ordered by the tile of i (System), then j - i, then i: in a lattice, eight
// consecutive pairs then mostly have consecutive i and consecutive j, which one load fetches
// (else mostly within 16 particles). The arrays start on cache lines
// (aligned.hpp) and blocks of pairs at multiples of kLanes, so the kernels' 64-byte accesses
// to a block's entries never split a line.
// Distinct records, each numbered as first met; number 0 is the padding's (all zero).
struct RecordSet {
  std::vector<PairRecord> records{PairRecord{}};
  std::vector<ModelRecord> models{ModelRecord{}};
  // The number of a record bitwise equal to r (and mr), newest first (neighbouring pairs mostly
  // share one); a new one is added.
  std::int32_t intern(const PairRecord& r, const ModelRecord& mr);
};

struct PairTable {
  std::size_t count = 0;  // entries, padding (record 0) included; the arrays hold padded()
  AlignedVector<std::int32_t> i, j;
  std::vector<PairRecord> records;                  // distinct records, the first all zero (padding)
  // The contact model, the sub-models the engine's rules make of it (the vector kernels run the
  // study's only), and per record what the models beyond hertz/history need (parallel to records).
  model::ContactModel model;
  SubModels sub_models;
  std::vector<ModelRecord> model_records;
  AlignedVector<std::int32_t> record;               // per pair, its record
  // Each contact's history, value by value (history_layout(sub_models): each sub-model's slice;
  // the study's model keeps the tangential displacement x, y, z in history[0..2], which the
  // vector kernels read and write).
  std::vector<AlignedVector<double>> history;
  // At its last evaluation (kept across rebuilds); not kept by the vector kernels for a
  // torque_free table of the study's model, whose history is +0 throughout, so that which history
  // survives a rebuild does not matter (the reference kernel keeps them for every model).
  std::vector<std::uint8_t> touching;
  // Per kLanes pairs: the lowest i and j (the windows), where each side's particles lie (kRun
  // if every real pair's is the window plus its lane, kWindowed if all lie within kWindow of
  // it), whether they are all elastic and frictionless, and the record they share.
  static constexpr std::int32_t kWindow = 2 * static_cast<std::int32_t>(kLanes);
  std::vector<std::int32_t> window_i, window_j;
  std::vector<Fetch> fetch_i, fetch_j;
  std::vector<std::uint8_t> elastic_frictionless;
  std::vector<std::int32_t> shared_record;  // the record all real pairs of the eight share, or -1
  bool torque_free = false;  // every pair elastic and frictionless: no torque anywhere
  std::vector<std::uint8_t> forces_stored;  // per kPairBlock pairs: a force entry may be nonzero
  // Per kPairBlock pairs: its force entries are those of the positions it was last evaluated
  // at (cleared by finish()). Per kLanes pairs: which particles of the windows they use (bit
  // k: window + k), for the still-particle test of torque_free tables.
  std::vector<std::uint8_t> evaluated;
  std::vector<std::uint16_t> particles_i, particles_j;
  // What each contact gives its spheres. The force on i at entry p; the force on j is its exact
  // negative, which the sums subtract (x - y is x + -y in IEEE arithmetic). The torques differ
  // by their lever arms: entry p for i, entry padded() + p for j.
  AlignedVector<double> fx, fy, fz, tx, ty, tz;

  std::size_t padded() const { return (count + kPairBlock - 1) / kPairBlock * kPairBlock; }
  void clear();
  // `entries` entries, all padding (record 0, no history) until filled in; the large arrays
  // written in `shares`' shares where there are any.
  void resize(std::size_t entries, const ForShares& shares = {});
  // What a pair of spheres of radii ra, rb and masses ma, mb with their type pair's constants
  // gives the table.
  static std::pair<PairRecord, ModelRecord> describe(const SubModels& model, double ra, double rb, double ma,
                                                     double mb, const PairConstants& k, const ModelConstants& mk);
  // Takes a set's records into the table's; returns each one's number in the table.
  std::vector<std::int32_t> merge_records(const RecordSet& set);
  // Once filled: pads, and finds each block's windows (in `shares`' shares of the blocks).
  void finish(const ForShares& shares = {});
  void describe_block(std::size_t block);  // finish's, for the kLanes pairs from block * kLanes
};

// How eight particles at a time add their contributions. Each particle adds its contributions
// in LIGGGHTS's pair order, by the other particle's index; a round takes one contribution of
// some of the eight, and a particle's contributions fall in successive rounds, so the sums are
// the reference's. Rounds follow the offset (other - self) upwards and merge while no particle
// is in both, so a lattice's eight neighbours read eight consecutive entries. A group's rounds
// with negative offsets come first: there the particles are the pairs' j, whose forces they
// subtract and whose torques they read padded() entries on; the two kinds never merge.
struct SumPlan {
  std::vector<std::size_t> first_round;  // per group of kLanes particles, and one past the last
  std::vector<std::size_t> first_added;  // per group, its first round of positive offsets
  // Per round: which lanes take part, and whether their entries are a run (at `window` plus
  // their lane: one load) or gathered (`entry`).
  AlignedVector<std::uint8_t> lanes_in;
  AlignedVector<Fetch> fetch;
  std::vector<std::int32_t> window;
  AlignedVector<std::int32_t> entry;   // kLanes per round
  // contributions[offsets[k] .. offsets[k + 1]]: particle k's (other particle, entry), in order.
  // From PairTable entries as the contributions give them (j's at padded + p, `j_side`).
  // The groups are planned in for_shares' shares (empty: in one); the plan does not depend on them.
  void build(const std::vector<std::size_t>& offsets, const std::vector<std::pair<std::int32_t, std::uint32_t>>& contributions,
             std::size_t j_side, const ForShares& for_shares = {});
};


// One force call's inputs beyond the tables.
struct ContactStep {
  // Particle positions, velocities, angular velocities: component d of particle k at
  // d * stride + k, with at least kWindow entries after the last particle's.
  const double* x;
  const double* v;
  const double* w;
  std::size_t stride = 0;
  double dt = 0.0;
  double contact_distance_factor = 1.0;
  bool update_history = true;
  bool tangential_damping = true;
  // Motion::position_changed of the last drift, with room for a 4-byte read past its last byte.
  const std::uint8_t* position_changed = nullptr;
  // If not null, per group of kLanes particles: set to 1 for the groups of both spheres of every
  // pair the elastic kernel evaluates (a group left at 0 has the contributions it had at the
  // last step, so its sums need not be taken again).
  std::uint8_t* sums_due = nullptr;
  // Where the normal law keeps a contact's energy with its history (has_contact_energy), per
  // particle: the work dissipated by its contacts that have opened (half of a pair contact's,
  // all of a wall contact's), added with bank_work; null otherwise.
  double* banked = nullptr;
};

// Adds `work` to particle i's banked work: atomically, as a pair's spheres may lie in two
// threads' shares (a contact opens rarely, so they hardly ever meet).
inline void bank_work(double* banked, std::size_t i, double work) {
  std::atomic_ref<double>(banked[i]).fetch_add(work, std::memory_order_relaxed);
}
// The work pair p's contact has dissipated, as it opens (or loses its history at a rebuild),
// banked half to each sphere (contacts.cpp; where the law keeps it: has_contact_energy).
void bank_opened(const PairTable& t, double* banked, std::size_t p);

// Pair p's two spheres as both contact rules begin: i, j, their separation (i minus j), its
// square and the pair's record.
struct PairGeometry {
  std::size_t i, j;
  double delx, dely, delz, rsq;
  const PairRecord* rec;
};
inline PairGeometry pair_geometry(const PairTable& t, const ContactStep& s, std::size_t p) {
  const std::size_t i = static_cast<std::size_t>(t.i[p]), j = static_cast<std::size_t>(t.j[p]);
  const std::size_t y = s.stride, z = 2 * s.stride;
  const double delx = s.x[i] - s.x[j];
  const double dely = s.x[y + i] - s.x[y + j];
  const double delz = s.x[z + i] - s.x[z + j];
  return {i, j, delx, dely, delz, delx * delx + dely * dely + delz * delz,
          &t.records[static_cast<std::size_t>(t.record[p])]};
}

// A touching pair's frame, as both contact rules take it: the distance, the unit normal from j
// to i, the relative velocity, its normal speed and its tangential part.
struct ContactFrame {
  double r, rinv, en[3], vr[3], vn, vt[3];
};
inline ContactFrame contact_frame(const PairGeometry& g, const ContactStep& s) {
  const std::size_t i = g.i, j = g.j, y = s.stride, z = 2 * s.stride;
  ContactFrame f;
  f.r = std::sqrt(g.rsq);
  f.rinv = 1.0 / f.r;
  f.en[0] = g.delx * f.rinv;
  f.en[1] = g.dely * f.rinv;
  f.en[2] = g.delz * f.rinv;
  f.vr[0] = s.v[i] - s.v[j];
  f.vr[1] = s.v[y + i] - s.v[y + j];
  f.vr[2] = s.v[z + i] - s.v[z + j];
  f.vn = f.vr[0] * f.en[0] + f.vr[1] * f.en[1] + f.vr[2] * f.en[2];
  for (int d = 0; d < 3; ++d) f.vt[d] = f.vr[d] - f.vn * f.en[d];
  return f;
}
// Pair p gives its spheres nothing (not touching).
void zero_contribution(PairTable& t, std::size_t p);

// Evaluates pairs [begin, end) of the table (both multiples of kPairBlock for the vector kernels).
void contacts_reference(PairTable& pairs, const ContactStep& s, std::size_t begin, std::size_t end);

// The particle arrays nve/sphere updates (component-major, as ContactStep; every array holds
// whole groups of kLanes particles, zero past the last).
struct Motion {
  double* x;
  double* v;
  double* w;
  const double* f;
  const double* t;
  const double* kick;       // dtf / m per particle
  const double* spin_kick;  // dtfrotate / (r^2 m) per particle
  const double* x_at_build;
  // Written by the vector first halves: per group of kLanes particles, bit k set if particle
  // kLanes * group + k has a new position (bitwise) after this drift.
  std::uint8_t* position_changed;
  std::size_t stride = 0;
  double dt = 0.0;
  double trigger = 0.0;  // (skin / 2)^2
  // False when every torque is +0 and stays so (no torque from any pair, no walls) and no
  // angular velocity is -0: then w + (dtfrotate / (r^2 m)) * t leaves w as it is, and the vector
  // kernels leave w and t alone.
  bool spin = true;
};

// nve/sphere's initial_integrate on particles [begin, end): kick, drift, spin kick. True if one
// of them is now more than half the skin from where it was at the last neighbour-list build.
bool first_half_reference(const Motion& m, std::size_t begin, std::size_t end);
void second_half_reference(const Motion& m, std::size_t begin, std::size_t end);  // final_integrate

// What the in-situ series adds up over particles [begin, end): m |v|^2 and |w|^2 r^2 m, particle
// begin + k into partial sum k mod kLanes (added to what the kLanes sums of `translational` and
// `rotational` hold), in the vector kernels' order lane by lane. m and r: per particle; v and w:
// component-major, as ContactStep; every array holds whole groups of kLanes particles.
struct KineticInput {
  const double* mass;
  const double* radius;
  const double* v;
  const double* w;
  std::size_t stride;
};
void kinetic_sums_reference(const KineticInput& in, std::size_t begin, std::size_t end, double* translational,
                            double* rotational);

// The vector kernels of one instruction set (contacts_simd.cpp). The contacts take pairs in
// whole kPairBlocks; the others take whole groups of particles (begin a multiple of kLanes, end
// rounded up to one).
struct VectorKernels {
  void (*contacts)(PairTable& pairs, const ContactStep& s, std::size_t begin, std::size_t end) = nullptr;
  // Adds up every particle's contributions in groups [group_begin, group_end) into f and t
  // (component-major, stride as ContactStep). With pairs.torque_free and !zero_torques, t is
  // left alone (it holds +0 already).
  void (*sum_contributions)(const PairTable& pairs, const SumPlan& plan, double* f, double* t, std::size_t stride,
                            std::size_t group_begin, std::size_t group_end, bool zero_torques) = nullptr;
  bool (*first_half)(const Motion& m, std::size_t begin, std::size_t end) = nullptr;
  void (*second_half)(const Motion& m, std::size_t begin, std::size_t end) = nullptr;
  // One step's second half and the next one's first half, each particle's operations in order.
  bool (*second_and_first_half)(const Motion& m, std::size_t begin, std::size_t end) = nullptr;
  void (*kinetic_sums)(const KineticInput& in, std::size_t begin, std::size_t end, double* translational,
                       double* rotational) = nullptr;
  // contacts_reference on a torque_free table of a model whose force and history are functions of
  // the positions alone (positional_force, composition.cpp): a block of kPairBlock pairs none of
  // whose spheres has a new position since its last evaluation keeps its entries (the same
  // inputs would give the same bits), as the elastic kernel's; marks ContactStep::sums_due.
  void (*still_reference)(PairTable& pairs, const ContactStep& s, std::size_t begin, std::size_t end) = nullptr;
  // contacts_reference of Thornton's law (normal_thornton.cpp) by LIGGGHTS's rules on a
  // torque_free table (no friction, no damping: the tangential force is +-0 and its history stays
  // +0), in lanes, still blocks kept as still_reference keeps them; the same bits.
  void (*thornton)(PairTable& pairs, const ContactStep& s, std::size_t begin, std::size_t end) = nullptr;
};
// The instruction sets this CPU runs the vector kernels in, best first ("avx512", "avx2",
// "sse4", "ssse3", "neon", "scalar", as the build has them).
std::vector<std::string> vector_targets();
// The kernels of one of vector_targets(), or of the best with "".
VectorKernels vector_kernels(const std::string& target);

}  // namespace granstack::refsim::detail
