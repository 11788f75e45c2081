#include <granstack/model/contact.hpp>
#include <granstack/model/protection.hpp>
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

ContactPair striker_contact(const Stack& stack) {
  const auto lib = stack.spec().material_library();
  const auto& top = stack.block(1);
  return sphere_sphere(lib.at(stack.spec().effective_striker_material()), stack.striker_radius(), lib.at(top.material),
                       top.radius);
}

namespace {
// The Hertz contact time of two equal spheres of the material, 1 m in radius, at speed v: the
// contact time of any equal pair scales with the radius, so this orders materials by softness.
double slowness(const Material& m, double v) { return hertz_contact_time(sphere_sphere(m, 1.0, m, 1.0), v); }
// The contact time of a pair under the spec's contact model, at the striker speed.
double spec_contact_time(const StackSpec& spec, const ContactPair& c) {
  return contact_time(spec.contact_model(), c, spec.striker_speed);
}
}  // namespace

bool has_soft_cavity(const Stack& stack) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  const double v = spec.striker_speed;
  double stiffest_above = slowness(lib.at(spec.effective_striker_material()), v);
  for (const auto& b : stack.blocks()) {
    const double s = slowness(lib.at(b.material), v);
    if (b.index < spec.blocks && stiffest_above < s && slowness(lib.at(stack.block(b.index + 1).material), v) < s) {
      return true;
    }
    stiffest_above = std::min(stiffest_above, s);
  }
  return false;
}

Resolution resolve(const Stack& stack) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  Resolution r;

  // Every kind of contact the stack has: within a block, across an interface, striker on block 1,
  // and sphere on wall. The shortest contact sets the time step.
  r.min_contact_time = std::numeric_limits<double>::infinity();
  auto consider = [&](const ContactPair& c, std::string what) {
    const double tc = spec_contact_time(spec, c);
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
    if (const auto chain = stack.chain_beside(b); chain.count > 0) {
      const auto& matrix = lib.at(spec.effective_matrix_material());
      consider(sphere_sphere(m, b.radius, matrix, chain.radius), fmt::format("block {} - matrix", b.index));
      consider(sphere_sphere(matrix, chain.radius, matrix, chain.radius), fmt::format("matrix beside block {}", b.index));
      min_rayleigh = std::min(min_rayleigh, rayleigh_time(matrix, chain.radius));
    }
  }
  r.min_rayleigh_time = min_rayleigh;
  consider(striker_contact(stack), "striker - block 1");

  // Arrival at the bottom face: each block's rows, plus its entry, in its own contact time.
  double arrival = 0.0;
  for (const auto& b : blocks) {
    const auto& m = lib.at(b.material);
    arrival += (kRowTransitPerContact * b.rows + kBlockEntryPerContact) *
               spec_contact_time(spec, sphere_sphere(m, b.radius, m, b.radius));
  }
  r.arrival_estimate = arrival;
  r.soft_cavity = has_soft_cavity(stack);

  r.dt_auto = !spec.dt.has_value();
  r.duration_auto = !spec.duration.has_value();
  r.dt = spec.dt.value_or(r.min_contact_time / normal_law(spec.normal_model).steps_per_contact);
  const double wanted = spec.duration.value_or((r.soft_cavity ? kCavityDurationPerArrival : kDurationPerArrival) * arrival);
  // Counts beyond kMaxSteps are held just above it (check_resolution refuses them) rather than
  // overflowing.
  const double wanted_steps = std::ceil(wanted / r.dt - 1e-9);
  r.steps_asked = wanted_steps;
  r.steps = wanted_steps <= static_cast<double>(kMaxSteps) ? std::max<long>(1, std::lround(wanted_steps)) : kMaxSteps + 1;
  const int wave_cadence = static_cast<int>(
      std::clamp(std::floor(kDumpPerContact * r.min_contact_time / r.dt), 1.0, static_cast<double>(1 << 30)));
  r.dump_every = spec.dump_every.value_or(std::min(cadence(r.steps, kAutoDumpFrames), wave_cadence));
  if (spec.dump_every && *spec.dump_every > r.steps) r.dump_every = static_cast<int>(r.steps);
  // The last step is always dumped, so reduce sees the final state.
  r.steps = (r.steps + r.dump_every - 1) / r.dump_every * r.dump_every;
  r.duration = static_cast<double>(r.steps) * r.dt;
  r.series_every = spec.series_every.value_or(cadence(r.steps, kAutoSeriesSamples));
  if (spec.bottom == Boundary::wall) {
    const auto& bottom = blocks.back();
    r.wall_contact_time =
        spec_contact_time(spec, sphere_wall(lib.at(bottom.material), bottom.radius, lib.at(spec.effective_wall_material())));
    const double per_contact = std::floor(r.wall_contact_time / (kSeriesPerWallContact * r.dt));
    if (!spec.series_every) r.series_every = std::min(r.series_every, static_cast<int>(std::clamp(per_contact, 1.0, 1e9)));
  }
  // Where the series is read at every dump frame (series_on_every_frame), the samples fall on every
  // frame (the largest divisor of the dump's cadence at most the series' own).
  if (series_on_every_frame(spec) && !spec.series_every) {
    while (r.dump_every % r.series_every != 0) --r.series_every;
  }
  r.thermo_every = cadence(r.steps, kAutoThermoLines);
  r.skin = 0.25 * blocks.back().radius;
  if (spec.stop == StopRule::blow_end) {
    r.stops_at_blow_end = true;
    r.steps = blow_end_cap_steps(r, spec.cap_durations);
    r.duration = static_cast<double>(r.steps) * r.dt;
    r.thermo_every = cadence(r.steps, kAutoThermoLines);
  }
  return r;
}

namespace {
const char* law_name(const StackSpec& spec) { return normal_law(spec.normal_model).name; }
}  // namespace

bool series_on_every_frame(const StackSpec& spec) {
  return blow_end_reads_wall_force(spec) || (spec.stop == StopRule::blow_end && normal_law(spec.normal_model).series_energy) ||
         spec.has_plate();
}

std::vector<SpecIssue> check_resolution(const Stack& stack, const Resolution& r) {
  std::vector<SpecIssue> issues;
  const auto& spec = stack.spec();
  if (!(r.dt <= r.min_contact_time / kMinStepsPerContact)) {
    issues.push_back({"dt", fmt::format("{:.4g} s is more than 1/{:g} of the shortest {} contact time ({:.4g} s, {}): "
                                        "the integration would not conserve energy; use at most {:.4g} s, or 'auto' "
                                        "({:.4g} s)",
                                        r.dt, kMinStepsPerContact, law_name(spec), r.min_contact_time, r.min_contact_pair,
                                        r.min_contact_time / kMinStepsPerContact,
                                        r.min_contact_time / normal_law(spec.normal_model).steps_per_contact)});
  }
  const auto& top = stack.block(1);
  // A Hooke spring calibrated beyond Hertz's range makes every overlap meaningless, the striker's too:
  // that is said alone.
  bool calibration_bad = false;
  if (spec.characteristic_velocity) {
    const double calibrated = hertz_max_overlap(striker_contact(stack), *spec.characteristic_velocity);
    if (!(calibrated <= kMaxOverlapPerRadius * top.radius)) {
      calibration_bad = true;
      issues.push_back({"characteristic_velocity",
                        fmt::format("{} m/s calibrates the Hooke spring on a Hertz overlap of {:.3g} of a radius, beyond "
                                    "the {:g} where Hertz's law holds: use a lower speed, or 'auto' (the striker speed)",
                                    *spec.characteristic_velocity, calibrated / top.radius, kMaxOverlapPerRadius)});
    }
  }
  const double overlap = max_overlap(spec.contact_model(), striker_contact(stack), spec.striker_speed);
  const bool striker_bad = !calibration_bad && !(overlap <= kMaxOverlapPerRadius * top.radius);
  // A run's length that cannot be computed comes from a problem said above (a speed beyond any
  // contact law's range): only a length that can be is refused on its own.
  if ((!(r.steps <= kMaxSteps) || !std::isfinite(r.duration)) &&
      (std::isfinite(r.steps_asked) || (!calibration_bad && !striker_bad))) {
    issues.push_back({spec.duration ? "duration" : "dt",
                      std::isfinite(r.steps_asked)
                          ? fmt::format("the run would take {:.3g} steps (duration / dt), more than the {:.0e} granstack "
                                        "allows; shorten --duration or use the automatic dt",
                                        r.steps_asked, static_cast<double>(kMaxSteps))
                          : std::string("the run's length (duration / dt) is not a number for this spec; give --duration "
                                        "and --dt, or values within their ranges")});
  }
  if (calibration_bad) {
  } else if (striker_bad) {
    issues.push_back({"striker_speed", fmt::format("{} m/s presses the striker {:.3g} of a radius into the top spheres; "
                                                   "{} contact holds for small overlaps only (at most {:g}): use a "
                                                   "lower speed",
                                                   spec.striker_speed, overlap / top.radius, law_name(spec),
                                                   kMaxOverlapPerRadius)});
  } else if (!(overlap >= kMinOverlapPerRadius * top.radius)) {
    issues.push_back({"striker_speed", fmt::format("{} m/s presses the striker only {:.3g} of a radius into the top "
                                                   "spheres, below the {:g} that double precision resolves (positions "
                                                   "hold 16 digits of a radius): its forces would be round-off; use "
                                                   "a higher speed",
                                                   spec.striker_speed, overlap / top.radius, kMinOverlapPerRadius)});
  }
  if (series_on_every_frame(spec) && r.dump_every % r.series_every != 0) {
    issues.push_back({"series_every", fmt::format("{} steps does not divide the dump's {}: under {} {}; give a divisor "
                                                  "of it, or 'auto'",
                                                  r.series_every, r.dump_every, law_name(spec),
                                                  blow_end_reads_wall_force(spec)
                                                      ? "the blow's end reads the wall's force from the series at every dump frame"
                                                      : "reduce reads the work the contacts dissipated from the series at "
                                                        "the frame where the blow ends, which may be any frame")});
  }
  if (spec.dump_every && *spec.dump_every > r.steps) {
    issues.push_back({"dump_every", fmt::format("{} steps is more than the run's {} steps: the dump would hold its first "
                                                "and last frames only; give at most {}, or 'auto'",
                                                *spec.dump_every, r.steps, r.steps)});
  }
  return issues;
}

Cost estimate_cost(const StackSpec& spec, long spheres, long steps, long dump_every, long series_every) {
  Cost c;
  c.spheres = spheres;
  c.steps = steps;
  c.frames = steps / std::max(1L, dump_every) + 1;
  const double per_atom = spec.dump_format == DumpFormat::binary ? kBinaryDumpBytesPerAtom : kTextDumpBytesPerAtom;
  c.dump_bytes = static_cast<double>(c.frames) * static_cast<double>(c.spheres) * per_atom;
  const double samples = static_cast<double>(steps / std::max(1L, series_every) + 1);
  c.series_bytes = samples * (2.0 * (spec.blocks + 3) + 1) * kSeriesBytesPerValue;
  c.liggghts_seconds = static_cast<double>(c.spheres) * static_cast<double>(c.steps) / kLiggghtsParticleStepsPerSecond;
  return c;
}

Cost estimate_cost(const Stack& stack, const Resolution& r) {
  return estimate_cost(stack.spec(), static_cast<long>(stack.spheres().size()), r.steps, r.dump_every, r.series_every);
}

std::string why_large(const Cost& c) {
  std::string why;
  if (c.dump_bytes + c.series_bytes > kLargeDumpBytes) {
    why = fmt::format("its outputs would take about {:.3g} GB (more than {:.3g} GB)", (c.dump_bytes + c.series_bytes) / 1e9,
                      kLargeDumpBytes / 1e9);
  }
  if (c.liggghts_seconds > kLargeLiggghtsSeconds) {
    why += fmt::format("{}LIGGGHTS would run for about {:.3g} hours on one core (more than {:.3g})", why.empty() ? "" : "; ",
                       c.liggghts_seconds / 3600, kLargeLiggghtsSeconds / 3600);
  }
  return why;
}

long last_output_change(const std::vector<long>& steps, const std::vector<double>& ke, double e_in) {
  if (ke.empty()) return 0;
  const double final_ke = ke.back();
  long last = 0;
  for (std::size_t i = 1; i < ke.size(); ++i) {
    const double change = std::fabs(ke[i] - ke[i - 1]);
    if (change > 1e-3 * final_ke && change > 1e-12 * e_in) last = steps[i];
  }
  return last;
}

}  // namespace granstack::model
