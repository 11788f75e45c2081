#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace granstack::model {

namespace {
int cadence(long steps, long samples) {
  return static_cast<int>(std::max<long>(1, (steps + samples - 1) / samples));
}
}  // namespace

Resolution resolve(const Stack& stack) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  const double v = spec.striker_speed;
  Resolution r;

  // Every kind of contact the stack has: within a block, across an interface, striker on block 1,
  // and sphere on wall. The shortest contact sets the time step.
  r.min_contact_time = std::numeric_limits<double>::infinity();
  auto consider = [&](const ContactPair& c, std::string what) {
    const double tc = hertz_contact_time(c, v);
    if (tc < r.min_contact_time) {
      r.min_contact_time = tc;
      r.min_contact_pair = std::move(what);
    }
  };
  const auto& blocks = stack.blocks();
  double min_rayleigh = std::numeric_limits<double>::infinity();
  for (const auto& b : blocks) {
    const auto& m = lib.at(b.material);
    consider(sphere_sphere(m, b.radius, m, b.radius), fmt::format("block {} - block {}", b.index, b.index));
    if (b.index < spec.blocks) {
      const auto& below = stack.block(b.index + 1);
      consider(sphere_sphere(m, b.radius, lib.at(below.material), below.radius),
               fmt::format("block {} - block {}", b.index, below.index));
    }
    if (stack.has_walls()) {
      consider(sphere_wall(m, b.radius, lib.at(spec.effective_wall_material())), fmt::format("block {} - wall", b.index));
    }
    min_rayleigh = std::min(min_rayleigh, rayleigh_time(m, b.radius));
  }
  r.min_rayleigh_time = min_rayleigh;

  // Arrival at the bottom face: each block's rows, plus its entry, in its own contact time.
  double arrival = 0.0;
  for (const auto& b : blocks) {
    const auto& m = lib.at(b.material);
    arrival += (kRowTransitPerContact * b.rows + kBlockEntryPerContact) *
               hertz_contact_time(sphere_sphere(m, b.radius, m, b.radius), v);
  }
  r.arrival_estimate = arrival;

  r.dt_auto = !spec.dt.has_value();
  r.duration_auto = !spec.duration.has_value();
  r.dt = spec.dt.value_or(r.min_contact_time / kStepsPerContact);
  const double wanted = spec.duration.value_or(kDurationPerArrival * arrival);
  r.steps = std::max<long>(1, std::lround(std::ceil(wanted / r.dt - 1e-9)));
  const int wave_cadence = static_cast<int>(std::max(1.0, std::floor(kDumpPerContact * r.min_contact_time / r.dt)));
  r.dump_every = spec.dump_every.value_or(std::min(cadence(r.steps, kAutoDumpFrames), wave_cadence));
  if (spec.dump_every && *spec.dump_every > r.steps) r.dump_every = static_cast<int>(r.steps);
  // The last step is always dumped, so reduce sees the final state.
  r.steps = (r.steps + r.dump_every - 1) / r.dump_every * r.dump_every;
  r.duration = static_cast<double>(r.steps) * r.dt;
  r.series_every = spec.series_every.value_or(cadence(r.steps, kAutoSeriesSamples));
  r.thermo_every = cadence(r.steps, kAutoThermoLines);
  r.skin = 0.25 * blocks.back().radius;
  return r;
}

}  // namespace granstack::model
