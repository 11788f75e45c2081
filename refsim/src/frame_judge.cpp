#include "frame_judge.hpp"

#include <algorithm>
#include <array>

namespace granstack::refsim::detail {

bool touches_nothing(const System& s, std::size_t i) {
  const auto xi = s.x(i);
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (j == i) continue;
    const auto xj = s.x(j);
    if (model::spheres_touch(xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2], s.radius(i), s.radius(j))) return false;
  }
  return true;
}

bool threatened(const System& s, std::size_t i) {
  const auto xi = s.x(i), vi = s.v(i);
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (j == i) continue;
    const auto xj = s.x(j), vj = s.v(j);
    if (model::on_collision_course(xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2], vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2],
                                   s.radius(i) + s.radius(j))) {
      return true;
    }
  }
  return false;
}

double momentum_z(const System& s) {
  double p = 0.0;  // in id order, as reduce sums a frame
  for (std::size_t i = 0; i < s.size(); ++i) p += s.mass(i) * s.v(i)[2];
  return p;
}

double lowest_striker_z(const System& s, int strikers) {
  double z = s.x(0)[2];
  for (std::size_t i = 1; i < static_cast<std::size_t>(strikers); ++i) z = std::min(z, s.x(i)[2]);
  return z;
}

void judge_blow_end(model::BlowEnd& blow, const model::Stack& stack, const System& s) {
  if (stack.spec().bottom == model::Boundary::wall) {
    const auto over = model::over_footprint(stack, s.size(), [&](std::size_t i) {
      const auto x = s.x(i);
      return std::array<double, 6>{x[0], x[1], x[2], s.radius(i), s.mass(i), s.v(i)[2]};
    });
    blow.frame(s.step_count(), over, false, false);
    return;
  }
  const auto out = static_cast<std::size_t>(stack.output_sphere_id() - 1);
  blow.frame(s.step_count(), model::OverFootprint{}, touches_nothing(s, out), threatened(s, out));
}

}  // namespace granstack::refsim::detail
