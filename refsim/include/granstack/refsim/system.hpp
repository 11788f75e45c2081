#pragma once
// The in-house reference integrator: Hertz contact with tangential history and planar walls,
// integrated with nve/sphere velocity Verlet, following LIGGGHTS 3.8.0 operation by operation
// (liggghts-3.8.md sections 1 to 3) so that two-body cases reproduce its dumps to round-off.
#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

namespace granstack::refsim {

using Vec3 = std::array<double, 3>;

// A planar wall perpendicular to `axis` (0 = x, 1 = y, 2 = z) at `position`, two-sided, of
// material type `type` (1-based, indexes the property tables).
struct Wall {
  int axis = 2;
  double position = 0.0;
  int type = 0;
};

struct Parameters {
  double dt = 0.0;
  double skin = 0.0;                     // neighbour skin, m
  double contact_distance_factor = 1.01; // the deck's neigh_modify contact_distance_factor
  Vec3 gravity{0.0, 0.0, 0.0};           // m/s^2 (fix gravity's acceleration vector)
  int types = 0;
  // Per type pair, index (a - 1) * types + (b - 1): effective moduli, damping beta, friction.
  std::vector<double> y_star, g_star, beta, friction;
  std::vector<Wall> walls;               // applied after the pair forces, in this order
  bool tangential_damping = true;
  // Threads for the force and integration loops. Every per-particle sum keeps the pair order
  // of one thread, so the result does not depend on the thread count, to the bit.
  int threads = 1;
};

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

  long step_count() const { return step_; }
  std::size_t size() const { return n_; }
  int type(std::size_t i) const { return type_[i]; }
  double radius(std::size_t i) const { return radius_[i]; }
  double mass(std::size_t i) const { return mass_[i]; }
  Vec3 x(std::size_t i) const { return {x_[3 * i], x_[3 * i + 1], x_[3 * i + 2]}; }
  Vec3 v(std::size_t i) const { return {v_[3 * i], v_[3 * i + 1], v_[3 * i + 2]}; }
  Vec3 omega(std::size_t i) const { return {w_[3 * i], w_[3 * i + 1], w_[3 * i + 2]}; }
  Vec3 force(std::size_t i) const { return {f_[3 * i], f_[3 * i + 1], f_[3 * i + 2]}; }
  Vec3 torque(std::size_t i) const { return {t_[3 * i], t_[3 * i + 1], t_[3 * i + 2]}; }
  long neighbor_builds() const { return builds_; }

 private:
  // What one contact adds to its two particles, and whether it touches at all.
  struct Contribution {
    double fi[3], ti[3], fj[3], tj[3];
    bool touching;
  };

  void build_pairs();
  bool needs_rebuild() const;
  void compute_forces(bool update_history);
  void pair_force(std::size_t p, bool update_history, Contribution& c);
  void wall_force(std::size_t i, std::size_t w, bool update_history);
  void external_forces(std::size_t i, bool update_history);  // walls then gravity, in the deck's order
  void first_half(std::size_t begin, std::size_t end);
  void second_half(std::size_t begin, std::size_t end);

  // Threads: workers wait for a job and run it on their share; the caller runs share 0.
  void parallel(const std::function<void(int)>& job);
  void worker(int index);
  std::pair<std::size_t, std::size_t> share(std::size_t count, int index) const;
  // job(begin, end) on every thread's share of [0, count); on the caller alone with one thread.
  void for_shares(std::size_t count, const std::function<void(std::size_t, std::size_t)>& job);
  void threaded_forces(bool update_history);

  std::size_t n_ = 0;
  Parameters p_;
  std::vector<int> type_;
  std::vector<double> radius_, mass_;
  std::vector<double> kick_, spin_kick_;  // dtf / m and dtfrotate / (r^2 m), as fix nve/sphere forms them
  // Structure of arrays, xyz interleaved per particle (the access pattern of the pair loop).
  std::vector<double> x_, v_, w_, f_, t_, x_at_build_;

  // Per type pair, the left-most factors of LIGGGHTS's expressions, evaluated once: the same
  // doubles it computes in every contact (4./3.*Y, 2.*Y, 8.*G, -2.*sqrt(5/6)*beta), so hoisting
  // them changes no bit.
  struct PairConstants {
    double kn_factor, sn_factor, st_factor, damping_factor, friction;
    bool damped;
  };
  std::vector<PairConstants> type_constants_;

  // Candidate pairs (i < j), rebuilt when a particle has moved more than half the skin, with
  // what does not change between rebuilds.
  std::vector<std::size_t> pair_i_, pair_j_;
  std::vector<double> pair_reff_, pair_meff_;
  std::vector<const PairConstants*> pair_constants_;
  std::vector<double> pair_history_;    // 3 per pair: the tangential displacement
  std::vector<unsigned char> pair_flag_; // touching at its last evaluation (kept across rebuilds)
  std::vector<double> wall_history_;    // 3 per particle and wall

  long step_ = 0;
  long builds_ = 0;

  int threads_ = 1;
  std::vector<std::thread> workers_;
  std::function<void(int)> job_;
  std::atomic<long> generation_{0};
  std::atomic<int> finished_{0};
  std::atomic<bool> stop_{false};
  std::vector<Contribution> contributions_;  // per pair, threaded runs only
  // Per particle, the pairs it belongs to, in pair order (2 p for side i, 2 p + 1 for side j).
  std::vector<std::size_t> atom_pair_offsets_, atom_pairs_;
};

}  // namespace granstack::refsim
