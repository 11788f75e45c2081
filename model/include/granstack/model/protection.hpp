#pragma once
// What the protected object under a stack takes from a blow: granstack's protection measures
// (docs/physics.md section 7). The protected object is the bottom wall, a rigid force sensor of
// the footprint's size, the same for every design of a space. Each measure is one function here,
// fed the same samples by refsim's in-situ run and by reduce of a LIGGGHTS or refsim case, so the
// two engines give the same number from the same run.
#include <granstack/model/plate.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>

#include <vector>

namespace granstack::model {

// The protected plate's mechanical energy, J: its kinetic energy and its mount spring's, at
// displacement z (m) and velocity vz (m/s); 0 for a rigid wall.
inline double plate_energy(const StackSpec& s, double z, double vz) {
  return s.has_plate() ? 0.5 * s.plate_mass * vz * vz + 0.5 * s.mount_stiffness * z * z : 0.0;
}

// The protected plate on its mount, as a single-degree-of-freedom system (the plate alone): its
// natural frequency sqrt(k / M) / (2 pi), Hz (0 on a free plate), its damping ratio
// c / (2 sqrt(k M)) (none on a free plate), and its mass over the stack's (Stack::lattice_mass).
struct PlateMount {
  double natural_frequency = 0.0;
  std::optional<double> damping_ratio;
  double mass_ratio = 0.0;
};
PlateMount plate_mount(const Stack& stack);

// The protected plate as LIGGGHTS carries it (its primitive walls move only as prescribed): a mesh
// of one triangle in the bottom wall's plane (z = 0), moved by fix move/mesh at the velocity of the
// plate's body, an atom of the plate's mass under it that fix nve/sphere integrates as it does every
// sphere and fix addforce pushes with model::plate_force. The triangle is anticlockwise seen from
// above (its normal +z), its centroid at the footprint's centre and its edges a margin (the stack's
// height and width) beyond the footprint, so that every sphere meets its face and none an edge; the
// body lies 3/4 R_1 under the plate, on the footprint's axis and inside the data file's box (its
// z from -R_1), with a quarter of the smallest radius, out of the reach (skin included) of the
// plate and of every sphere. refsim follows the body's arithmetic: the mount's spring reads its z
// less its start, as the deck writes it (bench/plate_on_liggghts.sh measured the route).
struct PlateBody {
  int id = 0;    // after every sphere's
  int type = 0;  // the wall's
  std::array<double, 3> start{};
  double radius = 0.0;  // m
  double mass = 0.0;    // kg: StackSpec::plate_mass
  std::array<std::array<double, 3>, 3> mesh{};  // the triangle's vertices, m
};
PlateBody plate_body(const Stack& stack);

// The largest impulse (N s) the wall takes in a window of `window` seconds: the peak over the
// samples' times t of the integral of F from t to t + window, F linear between its samples. `force` holds the
// wall's force every `interval` seconds (the series' samples, from one interval after the start).
// A window longer than the samples gives the whole run's impulse. Over the mean force it is what
// a body behind the wall feels as a sustained load, where the peak force is what breaks it.
double peak_window_impulse(const std::vector<double>& force, double interval, double window);

// The protector's crush and the striker's penetration at one frame (docs/physics.md section 7):
// - crush: the stack's largest loss of height, the largest travel toward the wall of a sphere
//   centre of the stack over the footprint (|x| <= half_width, |y| <= half_depth), z(0) - z(t),
//   >= 0: how much closer to the protected object any layer came, by the compression of the
//   contacts under it and by spheres pushed aside or down. While the stack crushes as a whole it
//   is the top surface's travel; the top row, struck, can also spring back up (with no gravity it
//   flies off) while the layers under it go on crushing, which the top's travel alone would miss
//   (steel on Teflon: the top row 30 um, the Teflon under it 290 um). The striker's indentation
//   into a top sphere moves no centre of the stack and is not crush.
// - penetration: the depth of the strikers' lowest point below the stack's initial top surface
//   (the plane z = Stack::lattice_height()), >= 0. The striker first touches in the groove between
//   the top spheres, so it starts at the seat depth (seat_depth(): (2 - sqrt(3)) R_1 for the
//   study's striker of radius R_1) and grows by the striker's indentation and by its descent into
//   the stack between spheres pushed aside.
struct Crush {
  double crush = 0.0;        // m
  double penetration = 0.0;  // m
};
class CrushMeter {
 public:
  explicit CrushMeter(const Stack& stack);
  // One frame's crush and penetration; `sphere(i)` for i in 0..n-1 (id order) gives at least
  // {x, y, z} of sphere i + 1 (the positions are read alone). Over a protected plate displaced by
  // `plate_z`, heights count from the plate: the crush is how much closer to it a layer came.
  template <class Sphere>
  Crush at(const Sphere& sphere, double plate_z = 0.0) const {
    Crush c;
    for (std::size_t k = 0; k < stack_.size(); ++k) {
      const auto s = sphere(stack_[k]);
      if (std::fabs(s[0]) <= half_width_ && std::fabs(s[1]) <= half_depth_) c.crush = std::max(c.crush, z0_[k] - (s[2] - plate_z));
    }
    for (std::size_t k = 0; k < striker_radius_.size(); ++k) {
      c.penetration = std::max(c.penetration, surface_z_ - ((sphere(k)[2] - plate_z) - striker_radius_[k]));
    }
    return c;
  }
  // The largest over the frames given.
  void add(const Crush& frame) {
    largest_.crush = std::max(largest_.crush, frame.crush);
    largest_.penetration = std::max(largest_.penetration, frame.penetration);
  }
  double crush() const { return largest_.crush; }              // m, >= 0
  double penetration() const { return largest_.penetration; }  // m, >= 0
  double seat_depth() const { return seat_depth_; }            // m: the penetration at first touch

 private:
  std::vector<std::size_t> stack_;  // the blocks' spheres (no striker, no container matrix), indices (id - 1)
  std::vector<double> z0_, striker_radius_;
  double half_width_ = 0.0, half_depth_ = 0.0, surface_z_ = 0.0, seat_depth_ = 0.0;
  Crush largest_;
};

// Whether two spheres overlap: centres closer than the sum of their radii (LIGGGHTS's contact
// test, pair_gran_base.h: r^2 < (R_i + R_j)^2).
inline bool spheres_touch(double dx, double dy, double dz, double ri, double rj) {
  return dx * dx + dy * dy + dz * dz < (ri + rj) * (ri + rj);
}
// Whether two spheres moving in straight lines will touch: d the second's centre less the
// first's, u its velocity less the first's, r_sum their radii's sum. They approach when d.u < 0,
// and pass closest at the distance^2 d.d - (d.u)^2 / u.u.
inline bool on_collision_course(double dx, double dy, double dz, double ux, double uy, double uz, double r_sum) {
  const double du = dx * ux + dy * uy + dz * uz;
  if (!(du < 0.0)) return false;
  const double uu = ux * ux + uy * uy + uz * uz;
  return dx * dx + dy * dy + dz * dz - du * du / uu < r_sum * r_sum;
}
// When two spheres on a collision course (on_collision_course, the same arguments) first touch,
// in straight lines from now: 0 when they touch already, the smaller root of |d + u t| = r_sum
// otherwise; none when they are not on course.
inline std::optional<double> first_contact_time(double dx, double dy, double dz, double ux, double uy, double uz,
                                                double r_sum) {
  if (!on_collision_course(dx, dy, dz, ux, uy, uz, r_sum)) return std::nullopt;
  const double dd = dx * dx + dy * dy + dz * dz, rr = r_sum * r_sum;
  if (dd < rr) return 0.0;
  const double du = dx * ux + dy * uy + dz * uz, uu = ux * ux + uy * uy + uz * uz;
  return (-du - std::sqrt(std::max(0.0, du * du - uu * (dd - rr)))) / uu;
}
// Sphere `out` of n against every other, in id order: whether it touches none (spheres_touch) and
// whether any is on course to hit it (on_collision_course), each taken as the other's centre and
// velocity less out's. `sphere(i)` for i in 0..n-1 gives {x, y, z, vx, vy, vz, radius}: refsim's
// state, a dump frame, or the stack as generated give the same answers from the same numbers.
template <class Sphere, class Test>
bool any_other(std::size_t n, std::size_t out, const Sphere& sphere, Test&& test) {
  const auto o = sphere(out);
  for (std::size_t j = 0; j < n; ++j) {
    if (j != out && test(sphere(j), o)) return true;
  }
  return false;
}
template <class Sphere>
bool touches_nothing(std::size_t n, std::size_t out, const Sphere& sphere) {
  return !any_other(n, out, sphere, [](const auto& s, const auto& o) {
    return spheres_touch(s[0] - o[0], s[1] - o[1], s[2] - o[2], o[6], s[6]);
  });
}
template <class Sphere>
bool threatened(std::size_t n, std::size_t out, const Sphere& sphere) {
  return any_other(n, out, sphere, [](const auto& s, const auto& o) {
    return on_collision_course(s[0] - o[0], s[1] - o[1], s[2] - o[2], s[3] - o[3], s[4] - o[4], s[5] - o[5], o[6] + s[6]);
  });
}

// Whether sphere `j`'s straight course hits sphere `target` before any other sphere of the n:
// on course to it (first_contact_time), and no other sphere touched first (a tie is the target's).
// A sphere whose course to the target runs into other spheres first is not coming: its straight
// line ends at the first of them (a sphere rattling between its neighbours deep in a stack, on a
// course to a striker 0.1 m above, never gets there). `sphere(i)` as for touches_nothing; the
// others are tried outward from j (its neighbours first, in the generator's order), which changes
// only how soon a blocked course is found.
template <class Sphere>
bool clear_course(std::size_t n, std::size_t j, std::size_t target, const Sphere& sphere) {
  const auto a = sphere(j);
  const auto time_to = [&](std::size_t m) {
    const auto b = sphere(m);
    return first_contact_time(b[0] - a[0], b[1] - a[1], b[2] - a[2], b[3] - a[3], b[4] - a[4], b[5] - a[5], a[6] + b[6]);
  };
  const auto t = time_to(target);
  if (!t) return false;
  for (std::size_t step = 1; step < n; ++step) {
    for (const std::size_t m : {j + step, j - step}) {  // j - step wraps past 0 to a value >= n
      if (m >= n || m == target) continue;
      if (const auto tm = time_to(m); tm && *tm < *t) return false;
    }
  }
  return true;
}

// Whether a striker (ids 1..stack.strikers(), the first spheres of `sphere`) still has a blow to
// give: against a bottom wall, one over the footprint and moving down, toward the stack and the
// protected object under it (a striker that turned back, or flew off beside the footprint, gives
// the protected object no more); or another sphere on course to hit one. With a free bottom the
// stack drifts down after the blow and the striker with it: there only a course counts. Two readings:
// - `coming`: every course (threatened: each other sphere taken in a straight line however far):
//   what a run stops on (BlowEnd::stop_at), in the arithmetic a LIGGGHTS or LAMMPS deck computes
//   with atom-style variables, sphere by sphere against the striker;
// - `clear`: the same with only the courses no other sphere blocks (clear_course): what the blow's
//   end reads (BlowEnd::ended_at). A deck cannot judge it (it is pairwise); refsim and reduce judge
//   it at the same frames from the same numbers.
struct StrikerCourse {
  bool coming = false;
  bool clear = false;
  // What made `clear`: a striker moving down over the footprint, or the first sphere found on a
  // clear course (its index, id - 1) and when it would meet its striker (s, straight lines).
  bool moving_down = false;
  std::size_t sphere = 0;
  double meets_in = 0.0;
};
template <class Sphere>
StrikerCourse striker_course(const Stack& stack, std::size_t n, const Sphere& sphere) {
  const bool wall = stack.spec().bottom == Boundary::wall;
  const double hw = stack.half_width(), hd = stack.half_depth();
  StrikerCourse c;
  for (std::size_t k = 0; k < static_cast<std::size_t>(stack.strikers()) && k < n; ++k) {
    const auto s = sphere(k);
    if (wall && s[5] < 0.0 && std::fabs(s[0]) <= hw && std::fabs(s[1]) <= hd) return {true, true, true};
    for (std::size_t j = 0; j < n; ++j) {
      if (j == k) continue;
      const auto o = sphere(j);
      const auto t = first_contact_time(o[0] - s[0], o[1] - s[1], o[2] - s[2], o[3] - s[3], o[4] - s[4], o[5] - s[5], s[6] + o[6]);
      if (!t) continue;
      c.coming = true;
      if (clear_course(n, j, k, sphere)) return {true, true, false, j, *t};
    }
  }
  return c;
}

// Whether a sphere at height z of radius r presses the bottom wall (the plane z = 0, Stack::walls):
// it overlaps it, so the wall pushes on it (at zero overlap, resting, it does not).
inline bool presses_bottom_wall(double z, double r) { return z - r < 0.0; }

// Whether the blow's end reads the bottom wall's force instead of the overlaps over the footprint:
// under an elastic-plastic law (a path-dependent one) a contact that has yielded carries no force
// below its residual overlap (the dent it keeps), so a stack come to rest on the wall overlaps it
// for good while the wall carries nothing, and an overlap would keep every such blow open to its
// cap. There "spheres press the wall" is "the wall carries a force": the sum of its normal forces
// on every sphere (each >= 0, no law here pulls), what a load cell under the wall reads, which the
// run's series records (kBottomWallForceColumn) and both engines hold per sphere. The same over a
// protected plate, which moves: whether the wall carries a force is the plate's load.
bool blow_end_reads_wall_force(const StackSpec& spec);

// What the protected object (the bottom wall under the footprint, |x| <= half_width and
// |y| <= half_depth) still has coming at one frame: the momentum along z of the spheres over it
// (summed in id order) and whether any of them presses the wall. A sphere that has flown off
// beside the footprint lands beside the protected object, not on it.
struct OverFootprint {
  double momentum_z = 0.0;
  bool pressing = false;
};
// `sphere(i)` for i in 0..n-1 (id order) gives {x, y, z, radius, mass, vz}. Over a protected plate
// moving at `plate_vz`, the momentum is the spheres' relative to it: what still comes toward it.
template <class Sphere>
OverFootprint over_footprint(const Stack& stack, std::size_t n, const Sphere& sphere, double plate_vz = 0.0) {
  OverFootprint f;
  const double hw = stack.half_width(), hd = stack.half_depth();
  for (std::size_t i = 0; i < n; ++i) {
    const auto [x, y, z, r, m, vz] = sphere(i);
    if (std::fabs(x) > hw || std::fabs(y) > hd) continue;
    f.momentum_z += m * (vz - plate_vz);  // m * vz to the bit where it is 0
    f.pressing = f.pressing || presses_bottom_wall(z, r);
  }
  return f;
}

// When the blow has ended for what a run measures (docs/physics.md section 7), judged at the
// dump's frames, the same in both engines:
// - against a bottom wall (the protected object): the momentum along z of the spheres over the
//   footprint (over_footprint) is no longer downward and none of them presses the wall (under an
//   elastic-plastic law: the wall carries no force, blow_end_reads_wall_force);
// - with a free bottom: the output sphere touches no sphere (its energy cannot change) and no
//   sphere is on course to hit it (on_collision_course, every other sphere taken in a straight
//   line from where it is, however far: a horizon as short as the hold let a sphere of the stack
//   that followed the output sphere hit it again, 45 % more energy, after the blow's end);
// and, in both, no striker still coming (striker_course: a striker the stack's spheres moving up
// hid from the momentum's sum went on into the stack after its blow had been called over);
// held at every frame for kBlowEndHoldArrivals estimated arrivals of the pulse (the time a pulse
// still inside the stack needs to reach the bottom; twice that with a soft cavity, whose bursts
// come up to 0.8 arrivals apart), so a pulse still on its way cannot be missed. With gravity the
// stack comes to rest on the wall, so the blow has no such end: never ended.
//
// The run stops (stop_at) where the same condition, with every course to a striker counted
// (StrikerCourse::coming), has held for the hold: what LIGGGHTS's and LAMMPS's decks judge, so
// that every engine stops at the same frame. The blow's end (ended_at) counts only the clear
// courses (StrikerCourse::clear): a sphere rattling between its neighbours in a lossless box, on
// a course to a striker far above that runs through the stack, kept a blow open to any cap while
// the wall carried nothing and the striker flew on untouched. It comes no later than the stop, and
// the frames between show whether it was right: a frame after the blow's end where its condition
// fails (the striker struck again, the wall loaded again) takes the end back, and the blow is
// judged on from there.
inline constexpr double kBlowEndHoldArrivals = 1.0;
// A run that stops at the blow's end runs at most kBlowEndCapDurations automatic durations by
// default (spec.hpp; a design space may set its own, [measures] cap_durations).

class BlowEnd {
 public:
  BlowEnd(const Stack& stack, const Resolution& res);
  // One dump frame: its step, what is over the footprint (momentum along z, up positive; whether a
  // sphere presses the wall), whether the output sphere touches no other sphere, whether another
  // is on course to hit it, and what the strikers have coming (striker_course).
  void frame(long step, const OverFootprint& over, bool output_free, bool output_threatened, StrikerCourse striker);
  // The step at which the blow ended (the frame at which its condition had held for the hold), or
  // none yet (or taken back by a later frame).
  std::optional<long> ended_at() const { return end_.at; }
  // The first frame of the condition's current run of frames, or none (it does not hold now).
  std::optional<long> holding_since() const { return end_.since; }
  // The step at which the run stops (every course counted; the decks' judgement), or none yet.
  std::optional<long> stop_at() const { return stop_.at; }
  std::optional<long> stop_holding_since() const { return stop_.since; }
  long hold_steps() const { return hold_steps_; }
  // The rules in words (the blow's end; the run's stop), and why the blow has not ended (for a
  // censored measure).
  std::string rule() const { return rule_of(true); }
  std::string stop_rule() const { return rule_of(false); }
  std::string why_not_ended() const;

 private:
  // One condition's run of frames: its first frame, and the frame where it had held for the hold.
  struct Hold {
    std::optional<long> since, at;
    void frame(long step, bool holds, long hold_steps);
  };
  std::string condition(bool clear_courses) const;
  std::string rule_of(bool clear_courses) const;
  std::string why_open() const;  // why_not_ended's reading of the last frame
  bool wall_ = false, wall_force_ = false, gravity_ = false;
  long hold_steps_ = 0;
  Hold end_, stop_;
  std::optional<long> taken_back_;  // the end a later frame took back, and that frame
  long taken_back_by_ = 0;
  long last_step_ = 0;
  double last_momentum_ = 0.0;
  bool last_on_wall_ = false, last_free_ = false;
  bool last_threatened_ = false;
  StrikerCourse last_striker_;
};

// Gives `blow` frame 0, read from the stack as generated (every sphere at rest but the strikers,
// moving down at the striker speed): what LIGGGHTS's deck is given as its first frame's judgement,
// since LIGGGHTS can reduce its spheres between runs only after a run of at least one step.
void judge_start(BlowEnd& blow, const Stack& stack);
// The steps the blow's end must hold for: kBlowEndHoldArrivals estimated arrivals (twice with a
// soft cavity), at least one.
long blow_end_hold_steps(const Resolution& res);
// The steps a run that stops at the blow's end may take at most (`cap_durations` automatic
// durations, a whole number of dump frames).
long blow_end_cap_steps(const Resolution& res, double cap_durations = kBlowEndCapDurations);

}  // namespace granstack::model
