#include <granstack/model/contact.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/refsim/in_situ.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <tuple>

#include "frame_judge.hpp"

namespace granstack::refsim {

using detail::momentum_z;
using detail::touches_nothing;

namespace {
// The earliest step at which `blow`, judged at the frame `step` and not ended, can end: its
// condition held from the frame it began holding (or, not holding, from the next frame) for the
// hold, at a frame.
long earliest_end(const model::BlowEnd& blow, long step, long dump_every) {
  const long from = blow.holding_since().value_or(step + dump_every) + blow.hold_steps();
  return (from + dump_every - 1) / dump_every * dump_every;
}

double sphere_ke(const System& s, std::size_t i) {
  const auto v = s.v(i), w = s.omega(i);
  return model::translational_energy(s.mass(i), v[0], v[1], v[2]) +
         model::rotational_energy(s.mass(i), s.radius(i), w[0], w[1], w[2]);
}
}  // namespace

InSituResult run_in_situ(const model::Stack& stack, std::vector<Particle> particles, const InSituOptions& options) {
  const auto res = model::resolve(stack);
  auto params = case_parameters(stack);
  params.threads = options.threads;
  params.kernel = options.kernel;
  const bool wall = stack.spec().bottom == model::Boundary::wall;
  const auto t0 = std::chrono::steady_clock::now();
  System system(std::move(particles), params);
  const auto out = static_cast<std::size_t>(stack.output_sphere_id() - 1);
  InSituResult r;
  r.e_in = stack.incident_energy();
  system.setup();
  // reduce reads the free output sphere's energy in the last dump frame, its peaks in the series.
  // The run ends at `end`: the resolution's steps, or (stopping at the blow's end) the frame where
  // the blow ended, at most the cap.
  // A case that stops at the blow's end has its cap in its resolution already.
  const bool stops = options.stop_at_blow_end || res.stops_at_blow_end;
  long end = options.stop_at_blow_end && !res.stops_at_blow_end ? model::blow_end_cap_steps(res, options.cap_durations)
                                                                  : res.steps;
  const bool abandon = stops && options.abandon_when_censored && stack.spec().gravity == 0.0;
  const auto bottom_row = stack.bottom_row_ids();
  // The output sphere's energy and the bottom row's, in the order reduce sums them (ids ascending).
  const auto final_energies = [&] {
    double row = 0.0;
    for (const int id : bottom_row) row += sphere_ke(system, static_cast<std::size_t>(id - 1));
    return std::tuple{sphere_ke(system, out), row, momentum_z(system)};
  };
  auto final_ke = final_energies();
  // Where the energy is at the last frame (read there, with final_ke).
  const auto energy_at_end = [&] {
    r.end_block_ke.assign(stack.blocks().size(), 0.0);
    r.end_striker_ke = r.end_sideways_ke = 0.0;
    r.end_striker_vz = system.v(0)[2];
    const auto vo = system.v(out);
    r.end_output_speed = std::sqrt(vo[0] * vo[0] + vo[1] * vo[1] + vo[2] * vo[2]);
    for (const auto& sphere : stack.spheres()) {
      const auto i = static_cast<std::size_t>(sphere.id - 1);
      const double ke = sphere_ke(system, i);
      if (sphere.block == 0) {
        r.end_striker_ke += ke;
      } else if (!stack.is_matrix(sphere)) {
        const auto v = system.v(i);
        r.end_block_ke[static_cast<std::size_t>(sphere.block - 1)] += ke;
        r.end_sideways_ke += 0.5 * system.mass(i) * (v[0] * v[0] + v[1] * v[1]);
      }
    }
    const auto contacts = system.contact_energies();
    r.end_block_dissipated.assign(contacts.dissipated.empty() ? 0 : stack.blocks().size(), 0.0);
    r.end_dissipated = 0.0;
    if (contacts.dissipated.empty()) return;
    for (const auto& sphere : stack.spheres()) {
      const double w = contacts.dissipated[static_cast<std::size_t>(sphere.id - 1)];
      r.end_dissipated += w;
      if (sphere.block > 0 && !stack.is_matrix(sphere)) r.end_block_dissipated[static_cast<std::size_t>(sphere.block - 1)] += w;
    }
  };
  model::CrushMeter crush(stack);
  detail::FramePressures pressures(stack);
  model::BlowEnd blow(stack, res);
  // Every dump frame up to `step` (the frames are every dump_every steps, step 0 the first): the
  // crush and the blow's end are judged at the frames, as reduce judges them from the dump; the
  // last frame's energies are read there. False when the run ended (at a frame) before `step`.
  long next_frame = 0;
  const auto advance_to = [&](long step) {
    for (; next_frame <= std::min(step, end); next_frame += res.dump_every) {
      if (next_frame > system.step_count()) system.advance(next_frame - system.step_count());
      crush.add(detail::crush_at(crush, system));
      pressures.add(system);
      const bool stopped = blow.stop_at().has_value();
      detail::judge_blow_end(blow, stack, system);
      if (stops && !stopped && blow.stop_at()) end = next_frame;
      if (abandon && !blow.ended_at() && earliest_end(blow, next_frame, res.dump_every) > end) {  // it cannot end by the cap
        r.abandoned_at = next_frame;
        end = next_frame;
      }
      if (next_frame == end) {
        final_ke = final_energies();
        energy_at_end();
      }
    }
    if (step > end) return false;
    if (step > system.step_count()) system.advance(step - system.step_count());
    return true;
  };
  std::vector<long> sample_steps;
  std::vector<double> sample_ke;
  for (long step = res.series_every; step <= end; step += res.series_every) {
    if (options.stop && options.stop()) {
      throw InSituStopped(fmt::format("stopped at step {} of {}", system.step_count(), end));
    }
    if (!advance_to(step)) break;
    // The series' output-sphere columns hold its translational and rotational energy; reduce adds them.
    const double ke = sphere_ke(system, out);
    sample_steps.push_back(step);
    sample_ke.push_back(ke);
    r.output_peak_fraction = std::max(r.output_peak_fraction, ke / r.e_in);
    if (wall) {
      const double f = bottom_wall_force(system);
      r.wall_force.push_back(f);
      if (stack.spec().has_plate()) r.plate_acceleration.push_back(system.plate_acceleration());
      if (!r.peak_wall_force || f > *r.peak_wall_force) {
        r.peak_wall_force = f;
        r.peak_wall_force_time = static_cast<double>(step) * res.dt;
      }
    }
    if (options.settle && sample_steps.size() % kSettleEvery == 0) {
      r.wall_force_interval = static_cast<double>(res.series_every) * res.dt;
      r.crush = crush.crush();
      r.penetration = crush.penetration();
      if (pressures.meter().judged()) r.yield_ratio = pressures.meter().largest().ratio;
      if (options.settle(r)) {
        r.settled_at = step;
        end = step;
        break;
      }
    }
  }
  if (!r.settled_at) advance_to(end);
  r.crush = crush.crush();
  r.penetration = crush.penetration();
  if (pressures.meter().judged()) {
    r.yield = pressures.meter().largest();
    r.yield_ratio = r.yield.ratio;
  }
  r.wall_force_interval = static_cast<double>(res.series_every) * res.dt;
  if (const auto at = blow.ended_at()) r.blow_end_time = static_cast<double>(*at) * res.dt;
  r.blow_not_ended = blow.why_not_ended();
  if (r.abandoned_at) {
    r.blow_not_ended += fmt::format("; abandoned at step {}: held from {}, the blow could end at step {} at the earliest, "
                                    "past the cap", *r.abandoned_at, blow.holding_since() ? "when it began holding" : "the next frame",
                                    earliest_end(blow, *r.abandoned_at, res.dump_every));
  }
  r.output_fraction = wall ? r.output_peak_fraction : std::get<0>(final_ke) / r.e_in;
  r.bottom_row_fraction = std::get<1>(final_ke) / r.e_in;
  r.final_momentum_ratio = std::get<2>(final_ke) / (stack.striker_mass() * stack.spec().striker_speed * stack.strikers());
  r.run_time = static_cast<double>(end) * res.dt;
  const long last_change = model::last_output_change(sample_steps, sample_ke, r.e_in);
  r.output_last_change_time = static_cast<double>(last_change) * res.dt;
  r.output_settled = wall ? model::wall_load_settled(r.peak_wall_force_time, r.run_time, r.final_momentum_ratio)
                          : model::output_settled(last_change, end);
  r.output_separated = !wall && touches_nothing(system, out);
  r.steps = end;
  r.dump_every = res.dump_every;
  r.series_every = res.series_every;
  r.atoms = static_cast<long>(system.size());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.kernel = system.kernel();
  return r;
}

}  // namespace granstack::refsim
