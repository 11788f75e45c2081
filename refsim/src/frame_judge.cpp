#include "frame_judge.hpp"

#include <granstack/refsim/case_run.hpp>

#include <algorithm>
#include <array>

namespace granstack::refsim::detail {

namespace {
// Sphere i's centre, velocity and radius, as model::touches_nothing and model::threatened read them.
auto state(const System& s) {
  return [&s](std::size_t i) {
    const auto x = s.x(i), v = s.v(i);
    return std::array<double, 7>{x[0], x[1], x[2], v[0], v[1], v[2], s.radius(i)};
  };
}
}  // namespace

bool touches_nothing(const System& s, std::size_t i) { return model::touches_nothing(s.size(), i, state(s)); }

bool threatened(const System& s, std::size_t i) { return model::threatened(s.size(), i, state(s)); }

double momentum_z(const System& s) {
  double p = 0.0;  // in id order, as reduce sums a frame
  for (std::size_t i = 0; i < s.size(); ++i) p += s.mass(i) * s.v(i)[2];
  return p;
}

model::Crush crush_at(const model::CrushMeter& meter, const System& s) { return meter.at(state(s), s.plate_displacement()); }

void FramePressures::add(const System& s) {
  if (!meter_.judged()) return;
  const std::size_t n = s.size();
  x_.resize(n);
  y_.resize(n);
  z_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto x = s.x(i);
    x_[i] = x[0];
    y_[i] = x[1];
    z_[i] = x[2];
  }
  meter_.add(meter_.at(s.step_count(), x_, y_, z_, candidates_.pairs(x_, y_, z_), s.plate_displacement()));
}

void judge_blow_end(model::BlowEnd& blow, const model::Stack& stack, const System& s) {
  const auto coming = model::striker_course(stack, s.size(), state(s));
  if (stack.spec().bottom == model::Boundary::wall) {
    auto over = model::over_footprint(
        stack, s.size(),
        [&](std::size_t i) {
          const auto x = s.x(i);
          return std::array<double, 6>{x[0], x[1], x[2], s.radius(i), s.mass(i), s.v(i)[2]};
        },
        s.plate_velocity());
    if (model::blow_end_reads_wall_force(stack.spec())) over.pressing = bottom_wall_force(s) > 0.0;
    blow.frame(s.step_count(), over, false, false, coming);
    return;
  }
  const auto out = static_cast<std::size_t>(stack.output_sphere_id() - 1);
  blow.frame(s.step_count(), model::OverFootprint{}, touches_nothing(s, out), threatened(s, out), coming);
}

}  // namespace granstack::refsim::detail
