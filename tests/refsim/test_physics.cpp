// refsim against analytic physics (physics.md section 5): Hertz impacts, restitution, Coulomb
// friction, the interface collision, energy conservation and the solitary wave of a chain.
#include <granstack/formats/data_file.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/model/yield.hpp>
#include <granstack/refsim/case_run.hpp>

#include <fmt/format.h>

#include "../support/scratch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "kernel_cases.hpp"
#include "kernel_check.hpp"

using namespace granstack;
using refsim::Particle;
using refsim::System;

namespace {

model::Material material(const std::string& name) { return model::MaterialLibrary::builtin().at(name); }

Particle sphere(int type, const model::Material& m, double r, refsim::Vec3 x, refsim::Vec3 v,
                refsim::Vec3 w = {0.0, 0.0, 0.0}) {
  return {type, r, model::sphere_mass(r, m.density), x, v, w};
}

double kinetic(const System& s) {
  double e = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto v = s.v(i), w = s.omega(i);
    e += 0.5 * s.mass(i) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
         0.5 * 0.4 * s.mass(i) * s.radius(i) * s.radius(i) * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  }
  return e;
}

double overlap(const System& s, std::size_t i, std::size_t j) {
  const auto a = s.x(i), b = s.x(j);
  return s.radius(i) + s.radius(j) - std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// Steps until every contact in the system has ended (after at least one began).
void collide(System& s, long max_steps, const std::function<void()>& each_step = {}) {
  bool began = false;
  for (long k = 0; k < max_steps; ++k) {
    s.step();
    if (each_step) each_step();
    bool touching = false;
    for (std::size_t i = 0; i < s.size(); ++i) {
      for (std::size_t j = i + 1; j < s.size(); ++j) touching = touching || overlap(s, i, j) > 0.0;
    }
    began = began || touching;
    if (began && !touching) return;
  }
  FAIL() << "the collision did not end within " << max_steps << " steps";
}

class HeadOn : public ::testing::TestWithParam<double> {};

TEST_P(HeadOn, RestitutionContactTimeAndMaxOverlapAreHertzs) {
  const double e = GetParam();
  const auto steel = material("steel");
  const double r = 1e-3, v = 1.0, dt = 1e-9;
  auto p = refsim::uniform_parameters({steel}, e, 0.0, dt, 2e-4);
  System s({sphere(1, steel, r, {0, 0, 0}, {0, 0, 0.5 * v}), sphere(1, steel, r, {0, 0, 2 * r}, {0, 0, -0.5 * v})}, p);
  s.setup();
  long contact_steps = 0;
  double max_overlap = 0.0;
  collide(s, 100000, [&] {
    const double d = overlap(s, 0, 1);
    if (d > 0) ++contact_steps;
    max_overlap = std::max(max_overlap, d);
  });
  const double v_out = s.v(1)[2] - s.v(0)[2];
  // docs/liggghts.md 10.1 measured e to about 2e-5 with this damping formula.
  EXPECT_NEAR(v_out / v, e, 1e-4);
  if (e == 1.0) {
    const auto c = model::sphere_sphere(steel, r, steel, r);
    EXPECT_NEAR(max_overlap / model::hertz_max_overlap(c, v), 1.0, 1e-3);
    EXPECT_NEAR(static_cast<double>(contact_steps) * dt / model::hertz_contact_time(c, v), 1.0, 1e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(Restitution, HeadOn, ::testing::Values(0.3, 0.5, 0.9, 1.0),
                         [](const auto& param_info) { return fmt::format("e{:02}", std::lround(param_info.param * 10)); });

// A sphere hitting a wall obliquely: sliding throughout gives a tangential impulse of exactly
// mu times the normal one (no damping at e = 1, so the normal force never turns attractive).
TEST(Friction, SlidingImpulseIsMuTimesTheNormalImpulse) {
  const auto steel = material("steel");
  const double r = 1e-3, mu = 0.1;
  auto p = refsim::uniform_parameters({steel, steel}, 1.0, mu, 1e-9, 2e-4);
  p.walls = {{2, 0.0, 2}};
  System s({sphere(1, steel, r, {0, 0, r}, {2.0, 0, -1.0})}, p);
  s.setup();
  for (int k = 0; k < 20000; ++k) s.step();
  const double dvt = s.v(0)[0] - 2.0, dvn = s.v(0)[2] + 1.0;
  EXPECT_NEAR(dvn, 2.0, 1e-4);                // elastic normal rebound
  EXPECT_NEAR(-dvt / dvn, mu, 1e-3 * mu);     // Coulomb
  EXPECT_LT(kinetic(s), 0.5 * s.mass(0) * 5.0);  // sliding dissipates
}

// With a large mu the contact sticks: the tangential spring, not Coulomb, sets the outcome,
// which therefore does not depend on mu (only the micro-slip as the contact unloads does).
TEST(Friction, StickingOutcomeDoesNotDependOnMu) {
  const auto steel = material("steel");
  const double r = 1e-3;
  auto bounce = [&](double mu) {
    auto p = refsim::uniform_parameters({steel, steel}, 1.0, mu, 1e-9, 2e-4);
    p.walls = {{2, 0.0, 2}};
    System s({sphere(1, steel, r, {0, 0, r}, {0.3, 0, -1.0})}, p);
    s.setup();
    for (int k = 0; k < 20000; ++k) s.step();
    return std::make_pair(s.v(0)[0] - 0.3, s.omega(0)[1]);
  };
  const auto [dvt2, w2] = bounce(2.0);
  const auto [dvt20, w20] = bounce(20.0);
  const auto [dvt_slide, w_slide] = bounce(0.05);
  std::printf("sticking: dvt %.6g (mu 2) %.6g (mu 20); sliding (mu 0.05): %.6g\n", dvt2, dvt20, dvt_slide);
  EXPECT_NEAR(dvt2 / dvt20, 1.0, 0.01);
  EXPECT_NEAR(w2 / w20, 1.0, 0.01);
  EXPECT_GT(std::fabs(dvt_slide - dvt2), 0.1 * std::fabs(dvt2));  // the sliding contact is a different regime
}

TEST(Wall, BounceReproducesRestitutionAndTheHertzTimeOfAWall) {
  const auto steel = material("steel");
  const double r = 1e-3, v = 1.0, dt = 1e-9;
  for (const double e : {1.0, 0.7}) {
    auto p = refsim::uniform_parameters({steel, steel}, e, 0.0, dt, 2e-4);
    p.walls = {{2, 0.0, 2}};
    System s({sphere(1, steel, r, {0, 0, r}, {0, 0, -v})}, p);
    s.setup();
    long contact = 0;
    for (int k = 0; k < 30000; ++k) {
      s.step();
      if (s.x(0)[2] < r) ++contact;
    }
    EXPECT_NEAR(s.v(0)[2] / v, e, 1e-4) << e;
    if (e == 1.0) {
      const auto c = model::sphere_wall(steel, r, steel);  // R* = R, m* = m
      EXPECT_NEAR(static_cast<double>(contact) * dt / model::hertz_contact_time(c, v), 1.0, 1e-3);
    }
  }
}

// A sphere of `ball` (radius r) striking a wall of `wall` at v, 2000 steps a contact: the yield
// meter's largest contact pressure over the bounce, which the sphere leaves moving up.
model::YieldPeak bounce_yield(const model::Material& ball, const model::Material& wall, double r, double v) {
  const auto c = model::sphere_wall(ball, r, wall);
  const double dt = model::hertz_contact_time(c, v) / 2000.0;
  auto p = refsim::uniform_parameters({ball, wall}, 1.0, 0.0, dt, 2e-4);
  p.walls = {{2, 0.0, 2}};
  System s({sphere(1, ball, r, {0, 0, r}, {0, 0, -v})}, p);
  s.setup();
  model::YieldMeter meter(model::YieldContacts{{ball, wall}, {1}, {r}, {{"wall_bottom", 2, 0.0}}, wall, model::NormalModel::hertz});
  for (long k = 1; k <= 3000; ++k) {
    s.step();
    const auto x = s.x(0);
    meter.add(meter.at(k, {x[0]}, {x[1]}, {x[2]}, {}));
  }
  EXPECT_GT(s.v(0)[2], 0.0) << "the sphere bounced off";
  EXPECT_EQ(meter.largest().id_a, 1);
  EXPECT_EQ(meter.largest().wall, "wall_bottom");
  return meter.largest();
}

// First yield (docs/physics.md section 7): a steel sphere striking a steel wall starts to yield at
// Johnson's V_Y, rho V_Y^2 / Y = 26 (Y / E*)^4 (Contact Mechanics, section 11.4, given to two
// digits: 0.8^6 pi^4 = 25.5 for p0 = 1.6 Y), so granstack's yield ratio, the largest contact
// pressure of the bounce over 1.6 Y, is 1 there to Johnson's rounding ((26 / 25.5)^(1/5): 0.36 %),
// and grows as Hertz's p0, V^(2/5).
TEST(Yield, ASphereOnAWallFirstYieldsAtJohnsonsSpeed) {
  const auto steel = material("steel");
  ASSERT_TRUE(steel.yield_strength.has_value());
  const double y = *steel.yield_strength, r = 1e-3;
  const double e_star = model::effective_youngs_modulus(steel, steel);
  const double v_y = std::sqrt(26.0 * std::pow(y / e_star, 4) * y / steel.density);
  const auto largest_ratio = [&](double v) { return bounce_yield(steel, steel, r, v).ratio; };
  const double at_v_y = largest_ratio(v_y);
  EXPECT_NEAR(at_v_y, 1.0, 0.005);
  // And exactly the closed form behind Johnson's 26 (2000 steps a contact: the peak is resolved).
  EXPECT_NEAR(at_v_y, std::pow(26.0 / (std::pow(0.8, 6) * std::pow(model::kPi, 4)), 0.2), 1e-6);
  EXPECT_NEAR(largest_ratio(4.0 * v_y) / at_v_y, std::pow(4.0, 0.4), 1e-5);
  // docs/physics.md quotes this run and the steel's first-yield speed.
  std::ifstream in(std::filesystem::path(GRANSTACK_TWOBODY_DIR) / ".." / ".." / ".." / "docs" / "physics.md");
  const std::string physics((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(physics.find(fmt::format("reads a ratio of\n  {:.5g}, his rounding", at_v_y)), std::string::npos);
  EXPECT_NE(physics.find(fmt::format("For the study's steel (Y = {:.0f} MPa) that speed is {:.0f} mm/s", y / 1e6, 1e3 * v_y)),
            std::string::npos);
}

// A contact of two materials first yields in the softer (#65: every peak compared before fell on
// a one-material contact, so the higher yield strength would have passed): a steel sphere on a
// brass wall, whose largest pressure over 1.6 Y_brass is Hertz's closed form for the pair, and
// the first-yield pressure is the lower Y's whichever body is named first.
TEST(Yield, AMixedContactYieldsInTheSofterMaterial) {
  const auto steel = material("steel"), brass = material("brass");
  ASSERT_LT(*brass.yield_strength, *steel.yield_strength);
  EXPECT_EQ(model::first_yield_pressure(steel, brass), 1.6 * *brass.yield_strength);
  EXPECT_EQ(model::first_yield_pressure(brass, steel), 1.6 * *brass.yield_strength);
  const double r = 1e-3, v = 0.5;
  const double y_star = model::effective_youngs_modulus(steel, brass);
  const double p0 = 2.0 * y_star / model::kPi * std::sqrt(model::hertz_max_overlap(model::sphere_wall(steel, r, brass), v) / r);
  EXPECT_NEAR(bounce_yield(steel, brass, r, v).ratio / (p0 / (1.6 * *brass.yield_strength)), 1.0, 1e-5);
}

// A sphere that starts many skins from two walls meets them only after many neighbour builds,
// leaves each and comes back: the walls a particle may touch before the next build are found
// anew at each one (System::wall_near_), so it bounces every time, elastically, and never
// passes through a wall.
TEST(Wall, ASphereFarFromTheWallsBouncesBetweenThemEachTime) {
  const auto steel = material("steel");
  const double r = 1e-3, skin = 2e-4, gap = 20 * skin, v = 1.0, dt = 1e-8;
  auto p = refsim::uniform_parameters({steel, steel}, 1.0, 0.0, dt, skin);
  p.walls = {{2, 0.0, 2}, {2, 2 * r + gap, 2}};
  System s({sphere(1, steel, r, {0, 0, r + gap / 2}, {0, 0, -v})}, p);
  s.setup();
  int bottom = 0, top = 0;
  bool on_bottom = false, on_top = false;
  const long steps = std::lround(3 * gap / v / dt);  // down, up, down, and half way up again
  for (long k = 0; k < steps; ++k) {
    s.step();
    const double z = s.x(0)[2];
    bottom += z < r && !on_bottom;
    top += z > r + gap && !on_top;
    on_bottom = z < r;
    on_top = z > r + gap;
    ASSERT_GT(z, 0.0) << "through the bottom wall at step " << k;
    ASSERT_LT(z, 2 * r + gap) << "through the top wall at step " << k;
  }
  EXPECT_EQ(bottom, 2);
  EXPECT_EQ(top, 1);
  EXPECT_NEAR(s.v(0)[2] / v, 1.0, 1e-4);
  EXPECT_GT(s.neighbor_builds(), 10);
}

// physics.md section 5: a large sphere on two free small ones at theta (cos theta = 2 sqrt(2)/3)
// leaves with v_f / v_i = (1 - 2 kappa cos^2 theta) / (1 + 2 kappa cos^2 theta).
class Interface : public ::testing::TestWithParam<std::string> {};

TEST_P(Interface, LargeSphereOnTwoSmallOnesFollowsTheHardSphereLaw) {
  const auto steel = material("steel");
  const auto small_material = material(GetParam());
  const double r = 1e-3, big = 2 * r, v = 1.0;
  const double cos2 = 8.0 / 9.0;
  const double kappa = small_material.density / steel.density / 8.0;
  const double expected = (1 - 2 * kappa * cos2) / (1 + 2 * kappa * cos2);
  auto p = refsim::uniform_parameters({steel, small_material}, 1.0, 0.0, 2e-9, 2e-4);
  System s({sphere(1, steel, big, {0, 0, 2 * std::sqrt(2.0) * r}, {0, 0, -v}), sphere(2, small_material, r, {-r, 0, 0}, {0, 0, 0}),
            sphere(2, small_material, r, {r, 0, 0}, {0, 0, 0})},
           p);
  s.setup();
  collide(s, 1000000);
  EXPECT_NEAR(-s.v(0)[2] / v / expected, 1.0, 0.005) << "kappa " << kappa << " expected " << expected;
  EXPECT_NEAR(kinetic(s) / (0.5 * s.mass(0) * v * v), 1.0, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(SmallSpheres, Interface, ::testing::Values("steel", "teflon"),
                         [](const auto& param_info) { return param_info.param; });

// Kinetic + Hertz elastic energy of a whole stack (e = 1, mu = 0) stays at E_in, with an error
// of velocity Verlet's order dt^2.
double stack_energy_drift(double dt_factor) {
  model::StackSpec spec;  // the study's 4-block steel stack
  const auto stack = model::Stack::build(spec);
  auto params = refsim::case_parameters(stack);
  params.dt *= dt_factor;
  System s(refsim::particles_from(generator::data_file(stack, "energy")), params);
  s.setup();
  const double e_in = stack.incident_energy();
  const double y_star = model::effective_youngs_modulus(material("steel"), material("steel"));
  const long steps = std::lround(static_cast<double>(model::resolve(stack).steps) / dt_factor);
  double drift = 0.0;
  for (long k = 1; k <= steps; ++k) {
    s.step();
    if (k % static_cast<long>(50 / dt_factor) != 0) continue;
    double elastic = 0.0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      for (std::size_t j = i + 1; j < s.size(); ++j) {
        const double d = overlap(s, i, j);
        if (d > 0) elastic += model::hertz_elastic_energy(y_star, s.radius(i) * s.radius(j) / (s.radius(i) + s.radius(j)), d);
      }
    }
    drift = std::max(drift, std::fabs(kinetic(s) + elastic - e_in) / e_in);
  }
  return drift;
}

TEST(Energy, FourBlockStackConservesEnergyToSecondOrder) {
  const double coarse = stack_energy_drift(2.0);
  const double fine = stack_energy_drift(1.0);
  // 3e-4 at the automatic dt, as for LIGGGHTS (tests/liggghts); halving dt divides it by ~4.
  EXPECT_LT(fine, 3e-4);
  EXPECT_GT(coarse / fine, 3.0) << coarse << " " << fine;
  EXPECT_LT(coarse / fine, 5.0) << coarse << " " << fine;
}

// A chain of 60 touching spheres struck at one end: the pulse becomes a solitary wave whose
// speed follows Nesterenko's law for its peak force (physics.md section 5, 3 %) and whose
// width is about five diameters.
TEST(Chain, SolitaryWaveSpeedAndWidthFollowNesterenko) {
  const auto steel = material("steel");
  const double r = 1e-3, d = 2 * r, v = 1.0;
  const int n = 60;
  std::vector<Particle> chain;
  for (int k = 0; k < n; ++k) chain.push_back(sphere(1, steel, r, {0, 0, -d * k}, {0, 0, k == 0 ? -v : 0.0}));
  const auto pair = model::sphere_sphere(steel, r, steel, r);
  const double dt = model::hertz_contact_time(pair, v) / 200;
  System s(chain, refsim::uniform_parameters({steel}, 1.0, 0.0, dt, 2e-4));
  s.setup();
  std::vector<double> peak_speed(n, 0.0), peak_time(n, 0.0);
  double peak_overlap = 0.0;
  // Width: the support L of the cos^4 profile with the same RMS width as the overlaps of the
  // chain when the wave's maximum is on sphere 30 (for cos^4 over L, sigma = 0.1414482 L).
  double width = 0.0;
  long steps = 0;
  while (s.x(n - 1)[2] > -d * (n - 1) - 1e-9 * d && steps < 10000000) {  // until the wave reaches the end
    s.step();
    ++steps;
    for (int k = 20; k <= 40; ++k) {
      const double speed = -s.v(static_cast<std::size_t>(k))[2];
      if (speed > peak_speed[k]) {
        peak_speed[k] = speed;
        peak_time[k] = static_cast<double>(steps) * dt;
        if (k == 30) {
          double w0 = 0.0, w1 = 0.0, w2 = 0.0;
          for (int j = 0; j + 1 < n; ++j) {
            const double o = std::max(0.0, overlap(s, static_cast<std::size_t>(j), static_cast<std::size_t>(j + 1)));
            w0 += o;
            w1 += o * j;
            w2 += o * j * j;
          }
          width = std::sqrt(w2 / w0 - (w1 / w0) * (w1 / w0)) / 0.1414482;
        }
      }
    }
    for (int k = 20; k < 40; ++k) peak_overlap = std::max(peak_overlap, overlap(s, static_cast<std::size_t>(k), static_cast<std::size_t>(k + 1)));
  }
  // Least-squares speed from the arrival times of the velocity maximum at spheres 20..40.
  double st = 0, sx = 0, stt = 0, stx = 0;
  const int m = 21;
  for (int k = 20; k <= 40; ++k) {
    st += peak_time[k];
    sx += d * k;
    stt += peak_time[k] * peak_time[k];
    stx += peak_time[k] * d * k;
  }
  const double speed = (m * stx - st * sx) / (m * stt - st * st);
  const double peak_force = 4.0 / 3.0 * pair.y_star * std::sqrt(pair.r_star) * std::pow(peak_overlap, 1.5);
  const double nesterenko =
      0.6802 *
      std::cbrt(2 * steel.youngs_modulus / (d * std::pow(steel.density, 1.5) * (1 - std::pow(steel.poisson_ratio, 2)))) *
      std::pow(peak_force, 1.0 / 6.0);
  EXPECT_NEAR(speed / nesterenko, 1.0, 0.03) << speed << " m/s against " << nesterenko << " m/s";
  EXPECT_NEAR(width, 5.0, 0.5);
  std::printf("solitary wave: %.2f m/s (Nesterenko %.2f m/s for F_m = %.4g N), width %.2f diameters\n", speed, nesterenko,
              peak_force, width);
}

}  // namespace

namespace {

// Threads change who computes what, never the order of any sum: two and five threads give one
// thread's result to the bit (damped, frictional stack with a wall, so every path is taken; five
// share the neighbour builds' tiles unevenly).
TEST(Threads, TwoThreadsGiveExactlyTheOneThreadResult) {
  model::StackSpec spec;
  spec.blocks = 3;
  spec.top_columns = 4;
  spec.restitution.value = 0.9;
  spec.friction.value = 0.25;
  spec.bottom = model::Boundary::wall;
  const auto stack = model::Stack::build(spec);
  const auto particles = refsim::particles_from(generator::data_file(stack, "threads"));
  auto run = [&](int threads) {
    auto params = refsim::case_parameters(stack);
    params.threads = threads;
    auto s = std::make_unique<System>(particles, params);
    s->setup();
    for (int k = 0; k < 3000; ++k) s->step();
    return s;
  };
  const auto one = run(1);
  EXPECT_GT(one->neighbor_builds(), 0);
  for (const int threads : {2, 5}) {
    const auto other = run(threads);
    for (std::size_t i = 0; i < one->size(); ++i) {
      EXPECT_EQ(one->x(i), other->x(i)) << i << " on " << threads;
      EXPECT_EQ(one->v(i), other->v(i)) << i << " on " << threads;
      EXPECT_EQ(one->omega(i), other->omega(i)) << i << " on " << threads;
      EXPECT_EQ(one->force(i), other->force(i)) << i << " on " << threads;
    }
  }
  EXPECT_NE(one->v(stack.output_sphere_id() - 1), (refsim::Vec3{0, 0, 0}));  // the pulse got there
}

using test_support::kernel_cases;
using test_support::KernelCase;

std::unique_ptr<System> run_kernel(const KernelCase& c, const std::string& kernel, int threads, bool advance = false) {
  auto params = refsim::case_parameters(c.stack);
  params.kernel = kernel;
  params.threads = threads;
  return test_support::run_3000_steps(c.particles, params, advance);
}

void expect_same(const System& a, const System& reference) { EXPECT_EQ(test_support::first_difference(a, reference), ""); }

// The series' kinetic energies: one sphere's is its 0.5 m |v|^2 to the bit, and a block's the
// plain sum of its spheres' to round-off (the eight partial sums change only the rounding).
TEST(Kernels, KineticEnergiesAreTheSpheresSums) {
  const auto c = kernel_cases().front();
  const auto s = run_kernel(c, "auto", 1);
  const std::size_t n = s->size();
  double ke = 0.0, rot = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto v = s->v(i), w = s->omega(i);
    const double m = s->mass(i), r = s->radius(i);
    const auto one = s->kinetic_energy(i, i + 1);
    EXPECT_EQ(one[0], m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.5) << i;
    EXPECT_EQ(one[1], (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) * r * r * m * 0.2) << i;
    ke += one[0];
    rot += one[1];
  }
  const auto all = s->kinetic_energy(0, n);
  EXPECT_GT(rot, 0.0);  // the frictional case spins its spheres
  EXPECT_NEAR(all[0], ke, 1e-14 * ke);
  EXPECT_NEAR(all[1], rot, 1e-14 * rot);
}

// The reference kernel gives the same bits on one or two threads, stepping or advancing.
TEST(Kernels, TheReferenceKernelGivesTheSameBitsOnAnyThreadsAndStepping) {
  for (const auto& c : kernel_cases()) {
    const auto reference = run_kernel(c, "reference", 1);
    EXPECT_EQ(reference->kernel(), "reference");
    EXPECT_GT(reference->neighbor_builds(), 1);  // histories carried across a rebuild too
    EXPECT_NE(reference->v(c.output), (refsim::Vec3{0, 0, 0}));  // the pulse got there
    expect_same(*run_kernel(c, "reference", 1, true), *reference);
    expect_same(*run_kernel(c, "reference", 2, true), *reference);
  }
}

// A kernel case written to a file (for the emulated check of the ARM kernels) reads back to the
// same run, to the bit: every double in hexadecimal.
TEST(Kernels, AKernelCaseFileReadsBackToTheSameRun) {
  const auto dir = granstack::test::scratch(std::filesystem::path(GRANSTACK_TEST_WORKDIR) / "Kernels.AKernelCaseFileReadsBackToTheSameRun");
  std::filesystem::create_directories(dir);
  for (const auto& c : kernel_cases()) {
    const auto path = (dir / (c.name + ".case")).string();
    test_support::write_kernel_case(path, {refsim::case_parameters(c.stack), c.particles, c.output});
    const auto back = test_support::read_kernel_case(path);
    EXPECT_EQ(back.output, c.output);
    auto params = back.params;
    params.kernel = "reference";
    expect_same(*test_support::run_3000_steps(back.particles, params, false), *run_kernel(c, "reference", 1));
  }
}

// The vector kernels do the reference's operations lane by lane: the same bits, on every
// instruction set this CPU runs (each forced in turn), on one or two threads, stepping or
// advancing. "auto" takes the best of them.
TEST(Kernels, EveryVectorInstructionSetGivesExactlyTheReferenceResult) {
  const auto targets = refsim::vector_kernels();
  ASSERT_FALSE(targets.empty());
  EXPECT_EQ(targets.back(), "scalar");  // Highway's fallback, there on every CPU
  for (const auto& c : kernel_cases()) {
    const auto reference = run_kernel(c, "reference", 1);
    const auto automatic = run_kernel(c, "auto", 1);
    EXPECT_EQ(automatic->kernel(), targets.front());
    expect_same(*automatic, *reference);
    for (const auto& target : targets) {
      for (const int threads : {1, 2}) {
        for (const bool advance : {false, true}) expect_same(*run_kernel(c, target, threads, advance), *reference);
      }
    }
  }
}

// The laws the vector pair kernels do not run, on a torque_free table (no friction, no damping):
// Thornton's in lanes (VectorKernels::thornton) and Hooke's on the reference kernel with still
// blocks kept (::still_reference), the particles on the vector kernels. Every instruction set
// gives the reference's bits for Thornton (on one thread stepping, on two advancing), with the
// same contact energies (the work banked as contacts open), and the best and the portable scalar
// set for Hooke: at 20 m/s on a free bottom and on a wall, in both sphere orders, the contacts
// yield, unload, open and survive rebuilds.
TEST(Kernels, ThorntonAndHookeGiveTheReferenceBitsOnEveryInstructionSet) {
  const auto targets = refsim::vector_kernels();
  for (const auto normal : {model::NormalModel::thornton, model::NormalModel::hooke}) {
    for (const auto& [wall, reversed] : {std::pair{false, false}, {true, false}, {false, true}}) {
      model::StackSpec spec;
      spec.blocks = 3;
      spec.top_columns = 4;
      spec.normal_model = normal;
      spec.bottom = wall ? model::Boundary::wall : model::Boundary::free_surface;
      spec.striker_speed = 20.0;
      const auto stack = model::Stack::build(spec);
      auto particles = refsim::particles_from(generator::data_file(stack, "kernels"));
      if (reversed) std::reverse(particles.begin(), particles.end());
      const KernelCase c{"positional", stack, particles, 0};
      const auto what = fmt::format("{}{}{}", model::to_string(normal), wall ? " on a wall" : "", reversed ? " reversed" : "");
      const auto reference = run_kernel(c, "reference", 1);
      EXPECT_GT(reference->neighbor_builds(), 1) << what;
      const auto energies = reference->contact_energies();
      if (normal == model::NormalModel::thornton) {
        double banked = 0.0;
        for (const double w : energies.dissipated) banked += w;
        EXPECT_GT(banked, 0.0) << what;  // contacts yielded
      }
      const bool thornton = normal == model::NormalModel::thornton;
      for (const auto& target : targets) {
        if (!thornton && target != targets.front() && target != targets.back()) continue;
        for (const auto& [threads, advance] : {std::pair{1, false}, {2, true}}) {
          const auto run = run_kernel(c, target, threads, advance);
          EXPECT_EQ(run->kernel(), thornton ? target : target + System::kReferencePairs) << what;
          expect_same(*run, *reference);
          const auto e = run->contact_energies();
          EXPECT_TRUE(e.elastic == energies.elastic && e.dissipated == energies.dissipated) << what << ", " << target;
        }
      }
    }
  }
}

// On x86-64 the build offers every vector instruction set the CPU has, so that a laptop's AVX2
// runs its own kernels, not the scalar fallback.
TEST(Kernels, TheInstructionSetsThisCpuHasAreOffered) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  const auto targets = refsim::vector_kernels();
  const auto offered = [&](const char* name) { return std::find(targets.begin(), targets.end(), name) != targets.end(); };
  __builtin_cpu_init();
  EXPECT_EQ(offered("avx2"), __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") != 0);
  EXPECT_EQ(offered("avx512"), __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                                   __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw"));
  EXPECT_EQ(offered("sse4"), __builtin_cpu_supports("sse4.2") != 0);
#else
  GTEST_SKIP() << "the CPU's instruction sets are checked on x86-64 only";
#endif
}

// A kernel this CPU cannot run is refused, naming those it can.
TEST(Kernels, AnInstructionSetThisCpuLacksIsRefused) {
  const auto targets = refsim::vector_kernels();
  std::string missing;
  for (const char* name : {"neon", "avx512", "avx2", "sse4"}) {
    if (std::find(targets.begin(), targets.end(), name) == targets.end()) {
      missing = name;
      break;
    }
  }
  ASSERT_FALSE(missing.empty());
  const auto c = kernel_cases().front();
  auto params = refsim::case_parameters(c.stack);
  params.kernel = missing;
  try {
    System refused(c.particles, params);
    ADD_FAILURE() << "--kernel " << missing << " accepted on a CPU that runs only " << targets.size() << " others";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("use --kernel auto, reference or one of those"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(targets.front()), std::string::npos) << e.what();
  }
}

}  // namespace
