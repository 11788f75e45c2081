// The protected plate on its mount (StackSpec::plate_mass) against closed forms: one sphere struck
// on a free plate leaves with the elastic collision's velocities, on a spring the sphere's, the
// plate's and the spring's energy is kept, a dashpot takes the work c v^2 dt it does, and a plate
// far heavier than the stack is the rigid wall.
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/refsim/case_run.hpp>

#include <granstack/formats/series.hpp>

#include "../support/scratch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace granstack;
using refsim::System;

namespace {

const model::Material& steel() {
  static const auto m = model::MaterialLibrary::builtin().at("steel");
  return m;
}

// One steel sphere (radius r, 1 m/s down) resting on a steel plate of mass `mass` at z = 0, its
// mount of stiffness k and damping c; dt a 3000th of the Hertz time of the sphere on a rigid wall.
struct Blow {
  double r = 5e-3, v = 1.0, m = model::sphere_mass(r, steel().density), dt = 0.0;
  System system;
  Blow(double mass, double k, double c) : system(make(mass, k, c)) { system.setup(); }

  System make(double mass, double k, double c) {
    dt = model::hertz_contact_time(model::sphere_wall(steel(), r, steel()), v) / 3000.0;
    auto p = refsim::uniform_parameters({steel(), steel()}, 1.0, 0.0, dt, 2e-4);
    p.walls = {{2, 0.0, 2}};
    p.stored_wall = 0;
    p.plate = {0, mass, k, c};
    return System({{1, r, m, {0.0, 0.0, r}, {0.0, 0.0, -v}, {0.0, 0.0, 0.0}}}, p);
  }
  // Steps until the sphere has left the plate (it touched and no longer does), at most 40 contacts.
  void until_apart(const std::function<void()>& each_step = {}) {
    bool touched = false;
    for (long k = 0; k < 120000; ++k) {
      system.step();
      if (each_step) each_step();
      const bool touching = system.x(0)[2] - r < system.plate_displacement();
      touched = touched || touching;
      if (touched && !touching) return;
    }
    FAIL() << "the sphere did not leave the plate";
  }
  double energy(double k) const {
    const double u = system.v(0)[2], z = system.plate_displacement(), w = system.plate_velocity();
    return 0.5 * m * u * u + 0.5 * system_mass * w * w + 0.5 * k * z * z;
  }
  double system_mass = 0.0;
};

}  // namespace

// An elastic collision of m at v with a free plate of M = 2 m at rest: the sphere rebounds at
// v (M - m) / (m + M) = v / 3, the plate leaves at 2 m v / (m + M) = 2 v / 3. Velocity Verlet at
// 3000 steps a contact gives both to 1e-8 (measured: 9e-10 on LIGGGHTS's mesh plate at the same
// resolution, bench/results/plate-on-liggghts-2026-12-07.md); the momentum m v is kept to
// round-off (1e-12 of it: the contact's 3,000 steps each round once, 3000 x 1.1e-16 = 3.3e-13).
TEST(Plate, AFreePlateTakesTheElasticCollisionsVelocities) {
  const double m = Blow(1.0, 0.0, 0.0).m;
  Blow b(2.0 * m, 0.0, 0.0);
  b.until_apart();
  std::printf("free plate: the sphere %+.3g off v/3, the plate %+.3g off -2v/3 (m/s)\n", b.system.v(0)[2] - 1.0 / 3.0,
              b.system.plate_velocity() + 2.0 / 3.0);
  EXPECT_NEAR(b.system.v(0)[2], 1.0 / 3.0, 1e-8);
  EXPECT_NEAR(b.system.plate_velocity(), -2.0 / 3.0, 1e-8);
  EXPECT_NEAR(b.m * b.system.v(0)[2] + 2.0 * m * b.system.plate_velocity(), -b.m * b.v, 1e-12 * b.m * b.v);
}

// On a spring (its period about eight contacts) the plate is struck and swings back: the sphere's,
// the plate's and the spring's energy stays E_in once they are apart, to the second-order error of
// velocity Verlet (2e-9 measured on LIGGGHTS at this resolution; 1e-7 allowed), and the plate
// carries part of it away (the sphere leaves slower than it came).
TEST(Plate, OnASpringTheSpherePlateAndSpringKeepTheEnergy) {
  const double m = Blow(1.0, 0.0, 0.0).m;
  Blow b(2.0 * m, 1e6, 0.0);
  b.system_mass = 2.0 * m;
  const double e_in = 0.5 * b.m * b.v * b.v;
  b.until_apart();
  std::printf("sprung plate: energy after / before 1 %+.3g\n", b.energy(1e6) / e_in - 1.0);
  EXPECT_NEAR(b.energy(1e6) / e_in, 1.0, 1e-7);
  EXPECT_LT(0.5 * b.m * b.system.v(0)[2] * b.system.v(0)[2], 0.99 * e_in);
}

// Once the sphere has left it, a sprung plate swings freely at its mount's natural frequency,
// model::plate_mount's sqrt(k / M) / (2 pi): the period between upward zero crossings of its
// displacement (each placed by linear interpolation between steps) over five swings, to 1e-7
// (velocity Verlet's frequency error (omega dt)^2 / 24 is a few 1e-9 at the tens of thousands of
// steps a period takes here; the crossings' interpolation adds less).
TEST(Plate, ASprungPlateSwingsAtItsMountsNaturalFrequency) {
  const double m = Blow(1.0, 0.0, 0.0).m;
  const double k = 1e6;
  Blow b(2.0 * m, k, 0.0);
  b.until_apart();
  std::vector<double> crossings;
  double z = b.system.plate_displacement();
  for (long step = 0; crossings.size() < 6 && step < 400000; ++step) {
    b.system.step();
    const double next = b.system.plate_displacement();
    if (z < 0.0 && next >= 0.0) crossings.push_back(static_cast<double>(step) + z / (z - next));
    z = next;
  }
  ASSERT_EQ(crossings.size(), 6u);
  const double period = (crossings.back() - crossings.front()) / 5.0 * b.dt;
  model::StackSpec spec;
  spec.bottom = model::Boundary::wall;
  spec.plate_mass = 2.0 * m;
  spec.mount_stiffness = k;
  const double expected = 1.0 / model::plate_mount(model::Stack::build(spec)).natural_frequency;
  std::printf("sprung plate: period %.9g s, closed form %.9g s (1 %+.2g)\n", period, expected, period / expected - 1.0);
  EXPECT_NEAR(period / expected, 1.0, 1e-7);
}

// A dashpot takes c v^2 per second: the energy lost over the blow is the sum of c v^2 dt over its
// steps, to the first-order error of that sum (1e-3 of it allowed; the loss itself is a tenth of
// E_in or more, so the check cannot pass with no dashpot).
TEST(Plate, ADashpotTakesTheWorkItDoes) {
  const double m = Blow(1.0, 0.0, 0.0).m;
  const double c = 100.0;
  Blow b(2.0 * m, 1e6, c);
  b.system_mass = 2.0 * m;
  const double e_in = 0.5 * b.m * b.v * b.v;
  double work = 0.0;
  b.until_apart([&] { work += c * b.system.plate_velocity() * b.system.plate_velocity() * b.dt; });
  const double lost = e_in - b.energy(1e6);
  std::printf("dashpot: %.3g of E_in lost, over the sum of c v^2 dt 1 %+.3g\n", lost / e_in, lost / work - 1.0);
  EXPECT_GT(lost, 0.1 * e_in);
  EXPECT_NEAR(lost / work, 1.0, 1e-3);
}

// A plate a billion times the stack's mass is the rigid wall: the same stack run on refsim over
// each gives the same series (every group's energy and the wall's force at every sample) to 1e-9
// of E_in and of the peak force (the plate moves about 1e-20 m a step), and its own columns say it
// hardly moved.
TEST(Plate, APlateFarHeavierThanTheStackIsTheRigidWall) {
  model::StackSpec spec;
  spec.blocks = 2;
  spec.rows = 4;
  spec.bottom = model::Boundary::wall;
  spec.duration = 2e-4;
  const auto run = [&](const std::string& name, double mass) {
    auto s = spec;
    s.plate_mass = mass;
    generator::GenerateOptions o;
    o.output = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / "Plate.heavy" / name);
    o.force = true;
    generator::generate({{name, s}}, o);
    refsim::run_case(o.output.string());
    return formats::read_series((o.output / "ke_series.txt").string());
  };
  const auto rigid = run("rigid", 0.0), heavy = run("heavy", 1e9);
  const double e_in = model::Stack::build(spec).incident_energy();
  const int force = rigid.column(model::kBottomWallForceColumn);
  ASSERT_GE(force, 0);
  double peak = 0.0;
  for (const auto& row : rigid.rows) peak = std::max(peak, row[static_cast<std::size_t>(force)]);
  ASSERT_GT(peak, 0.0) << "the stack struck the wall";
  ASSERT_EQ(heavy.rows.size(), rigid.rows.size());
  ASSERT_EQ(heavy.columns.size(), rigid.columns.size() + model::kPlateColumns.size());
  for (std::size_t i = 0; i < rigid.rows.size(); ++i) {
    for (std::size_t j = 1; j < rigid.columns.size(); ++j) {
      const double scale = static_cast<int>(j) == force ? peak : e_in;
      ASSERT_NEAR(heavy.rows[i][j], rigid.rows[i][j], 1e-9 * scale) << rigid.columns[j] << " at row " << i;
    }
    EXPECT_LT(std::fabs(heavy.rows[i][static_cast<std::size_t>(heavy.column("plate_z"))]), 1e-15);
  }
}
