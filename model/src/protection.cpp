#include <granstack/model/protection.hpp>

#include <granstack/model/contact.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace granstack::model {

namespace {
// The integral of F over [0, s] within the sample interval [a, b] of length h, F linear from fa to fb.
double partial(double fa, double fb, double h, double s) { return s * (fa + 0.5 * (fb - fa) * s / h); }
}  // namespace

double peak_window_impulse(const std::vector<double>& force, double interval, double window) {
  const std::size_t n = force.size();
  if (n < 2) return n == 1 ? force.front() * std::min(window, interval) : 0.0;
  // cumulative[k]: the trapezoid integral from sample 0 to sample k.
  std::vector<double> cumulative(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) cumulative[k] = cumulative[k - 1] + 0.5 * interval * (force[k - 1] + force[k]);
  const double span = interval * static_cast<double>(n - 1);
  const auto whole = static_cast<std::size_t>(std::floor(window / interval));
  if (window >= span || whole + 1 >= n) return cumulative.back();
  const double rest = window - interval * static_cast<double>(whole);
  double best = 0.0;
  for (std::size_t k = 0; k + whole < n; ++k) {
    const std::size_t end = k + whole;  // the window ends `rest` past sample `end`
    double impulse = cumulative[end] - cumulative[k];
    if (rest > 0.0) {
      if (end + 1 >= n) break;
      impulse += partial(force[end], force[end + 1], interval, rest);
    }
    best = std::max(best, impulse);
  }
  return best;
}

CrushMeter::CrushMeter(const Stack& stack)
    : half_width_(stack.half_width()), half_depth_(stack.half_depth()), surface_z_(stack.lattice_height()) {
  for (const auto& s : stack.spheres()) {
    if (s.block > 0 && !stack.is_matrix(s)) {
      stack_.push_back(static_cast<std::size_t>(s.id - 1));
      z0_.push_back(s.z);
    }
  }
  const auto& spheres = stack.spheres();
  for (int id = 1; id <= stack.strikers(); ++id) striker_radius_.push_back(spheres[static_cast<std::size_t>(id - 1)].radius);
  seat_depth_ = at([&](std::size_t i) { return std::array<double, 3>{spheres[i].x, spheres[i].y, spheres[i].z}; }).penetration;
  largest_.penetration = seat_depth_;
}

PlateMount plate_mount(const Stack& stack) {
  const auto& s = stack.spec();
  PlateMount m;
  if (!s.has_plate()) return m;
  m.mass_ratio = s.plate_mass / stack.lattice_mass();
  if (s.mount_stiffness > 0.0) {
    m.natural_frequency = std::sqrt(s.mount_stiffness / s.plate_mass) / (2.0 * std::numbers::pi);
    m.damping_ratio = s.mount_damping / (2.0 * std::sqrt(s.mount_stiffness * s.plate_mass));
  }
  return m;
}

PlateBody plate_body(const Stack& stack) {
  PlateBody b;
  if (!stack.spec().has_plate()) return b;
  const auto& spheres = stack.spheres();
  double smallest = spheres.front().radius;
  for (const auto& s : spheres) smallest = std::min(smallest, s.radius);
  const double r1 = stack.block(1).radius;
  b.id = static_cast<int>(spheres.size()) + 1;
  b.type = stack.wall_type();
  b.start = {0.0, 0.0, -0.75 * r1};
  b.radius = 0.25 * smallest;
  b.mass = stack.spec().plate_mass;
  const double margin = std::max(stack.top_z(), stack.half_width());
  const double a = stack.half_width() + margin, d = stack.half_depth() + margin;
  // Centroid (0, 0); at y = d its half width is 2a (4d - d) / 6d = a: the rectangle a x d is inside.
  b.mesh = {{{-2.0 * a, -2.0 * d, 0.0}, {2.0 * a, -2.0 * d, 0.0}, {0.0, 4.0 * d, 0.0}}};
  return b;
}

bool blow_end_reads_wall_force(const StackSpec& spec) {
  return spec.bottom == Boundary::wall && (normal_law(spec.normal_model).path_dependent || spec.has_plate());
}

BlowEnd::BlowEnd(const Stack& stack, const Resolution& res)
    : wall_(stack.spec().bottom == Boundary::wall), wall_force_(blow_end_reads_wall_force(stack.spec())),
      gravity_(stack.spec().gravity > 0.0) {
  hold_steps_ = blow_end_hold_steps(res);
}

void judge_start(BlowEnd& blow, const Stack& stack) {
  const auto& spheres = stack.spheres();
  const auto vz = [&](const Sphere& s) { return s.block == 0 ? -stack.spec().striker_speed : 0.0; };
  const auto state = [&](std::size_t i) {
    const auto& s = spheres[i];
    return std::array<double, 7>{s.x, s.y, s.z, 0.0, 0.0, vz(s), s.radius};
  };
  const auto coming = striker_course(stack, spheres.size(), state);
  if (stack.spec().bottom == Boundary::wall) {
    blow.frame(0, over_footprint(stack, spheres.size(), [&](std::size_t i) {
      const auto& s = spheres[i];
      return std::array<double, 6>{s.x, s.y, s.z, s.radius, stack.mass(s), vz(s)};
    }), false, false, coming);
    return;
  }
  const auto out = static_cast<std::size_t>(stack.output_sphere_id() - 1);
  blow.frame(0, OverFootprint{}, touches_nothing(spheres.size(), out, state), threatened(spheres.size(), out, state),
             coming);
}

long blow_end_hold_steps(const Resolution& res) {
  const double arrivals = kBlowEndHoldArrivals * (res.soft_cavity ? 2.0 : 1.0);
  return std::max<long>(1, static_cast<long>(std::ceil(arrivals * res.arrival_estimate / res.dt)));
}

void BlowEnd::Hold::frame(long step, bool holds, long hold_steps) {
  if (!holds) {
    since.reset();
    at.reset();
    return;
  }
  if (!since) since = step;
  if (!at && step - *since >= hold_steps) at = step;
}

void BlowEnd::frame(long step, const OverFootprint& over, bool output_free, bool output_threatened, StrikerCourse striker) {
  last_step_ = step;
  last_momentum_ = over.momentum_z;
  last_on_wall_ = over.pressing;
  last_free_ = output_free;
  last_threatened_ = output_threatened;
  last_striker_ = striker;
  if (gravity_) return;
  const bool rest = wall_ ? over.momentum_z >= 0.0 && !over.pressing : output_free && !output_threatened;
  if (!stop_.at) stop_.frame(step, rest && !striker.coming, hold_steps_);  // the run stops once
  const auto ended = end_.at;
  end_.frame(step, rest && !striker.clear, hold_steps_);
  if (ended && !end_.at) {
    taken_back_ = ended;
    taken_back_by_ = step;
  }
}

std::string BlowEnd::condition(bool clear_courses) const {
  const char* course = clear_courses ? "on a course to hit a sphere that no other sphere blocks" : "on course to hit a sphere";
  return wall_ ? fmt::format("the momentum over the footprint no longer downward, {}, and the striker neither moving "
                             "down over the footprint nor {}",
                             wall_force_ ? "the wall carrying no force (a yielded contact keeps its dent)"
                                         : "no sphere there pressing the wall",
                             course)
               : fmt::format("the output sphere touching no other sphere and none on course to hit it, nor the striker {}",
                             course);
}

std::string BlowEnd::rule_of(bool clear_courses) const {
  if (gravity_) return "none with gravity (the stack comes to rest on its support)";
  return fmt::format("{}, held for {} steps", condition(clear_courses), hold_steps_);
}

std::string BlowEnd::why_not_ended() const {
  if (end_.at) return "";
  if (gravity_) return "gravity: the stack comes to rest on its support, so the blow has no end to stop at";
  const auto taken_back = taken_back_ ? fmt::format(" (it seemed to end at step {}, until step {} showed otherwise)",
                                                    *taken_back_, taken_back_by_)
                                      : std::string();
  return why_open() + taken_back;
}

std::string BlowEnd::why_open() const {
  if (last_striker_.clear) {
    return last_striker_.moving_down
               ? fmt::format("at step {} the striker was still coming (moving down over the footprint)", last_step_)
               : fmt::format("at step {} the striker was still coming (sphere {} {}, no other sphere in the way)", last_step_,
                             last_striker_.sphere + 1,
                             last_striker_.meets_in > 0.0 ? fmt::format("on a course to hit it {:.3g} s later", last_striker_.meets_in)
                                                          : std::string("touching it and closing"));
  }
  if (wall_) {
    const char* wall = wall_force_ ? (last_on_wall_ ? "the wall still carried a force" : "the wall carried no force")
                                   : (last_on_wall_ ? "spheres still pressed the wall" : "no sphere pressed the wall");
    return fmt::format("at step {} the momentum over the footprint was {:.3g} kg m/s and {}{}", last_step_,
                       last_momentum_, wall, end_.since ? fmt::format(", clear since step {}", *end_.since) : "");
  }
  if (!last_free_) return fmt::format("at step {} the output sphere still touched another sphere", last_step_);
  if (last_threatened_) {
    return fmt::format("at step {} the output sphere was free but another sphere was on course to hit it", last_step_);
  }
  return fmt::format("at step {} the output sphere had been free and unthreatened since step {}, short of the {}-step hold",
                     last_step_, end_.since.value_or(last_step_), hold_steps_);
}

long blow_end_cap_steps(const Resolution& res, double cap_durations) {
  const auto cap = static_cast<long>(std::ceil(cap_durations * static_cast<double>(res.steps)));
  return (cap + res.dump_every - 1) / res.dump_every * res.dump_every;
}

}  // namespace granstack::model
