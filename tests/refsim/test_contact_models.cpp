// refsim's contact models beyond the study's (model/contact.hpp) against analytic physics, as
// test_physics.cpp holds the Hertz model: Hooke's linear spring-dashpot (restitution exactly e,
// contact time pi / omega_d whatever the speed), tangential no_history (viscous, capped at
// Coulomb's mu |F_n|), epsd2 rolling friction (a torque capped at mu_r R* |F_n|), cdt (a
// torque mu_r R* k_n delta against the spin) and LAMMPS's mindlin_rescale (mindlin's spring
// while a contact loads). Their
// agreement with LIGGGHTS, bit for bit, is test_agreement.cpp's (tests/data/twobody);
// mindlin_rescale's with LAMMPS, to round-off, tests/lammps's.
#include <granstack/model/contact.hpp>
#include <granstack/refsim/case_run.hpp>

#include "contact_models/sub_models.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

using namespace granstack;
using refsim::Particle;
using refsim::System;

namespace {

const model::Material kSteel = model::MaterialLibrary::builtin().at("steel");
constexpr double kR = 1e-3, kDt = 1e-9;

Particle steel_sphere(int type, refsim::Vec3 x, refsim::Vec3 v, refsim::Vec3 w = {0.0, 0.0, 0.0}) {
  return {type, kR, model::sphere_mass(kR, kSteel.density), x, v, w};
}

refsim::Parameters parameters(const model::ContactModel& contact, double e, double mu, double mu_r, int types) {
  std::vector<model::Material> materials(static_cast<std::size_t>(types), kSteel);
  auto p = refsim::uniform_parameters(materials, e, mu, kDt, 2e-4);
  p.contact = contact;
  p.rolling_friction.assign(p.restitution.size(), mu_r);
  return p;
}

double gap(const System& s) {
  const auto a = s.x(0), b = s.x(1);
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) - 2.0 * kR;
}

struct HeadOnResult {
  double restitution, contact_time, max_overlap;
};

// Two equal steel spheres head on at relative speed v, until they part.
HeadOnResult head_on(const model::ContactModel& contact, double e, double v) {
  System s({steel_sphere(1, {0, 0, 0}, {0, 0, 0.5 * v}), steel_sphere(1, {0, 0, 2 * kR}, {0, 0, -0.5 * v})},
           parameters(contact, e, 0.0, 0.0, 1));
  s.setup();
  long steps = 0;
  double deepest = 0.0;
  for (long k = 0; k < 200000 && (steps == 0 || gap(s) < 0.0); ++k) {
    s.step();
    if (gap(s) < 0.0) ++steps;
    deepest = std::max(deepest, -gap(s));
  }
  return {(s.v(1)[2] - s.v(0)[2]) / v, static_cast<double>(steps) * kDt, deepest};
}

model::ContactModel hooke(double characteristic_velocity) {
  model::ContactModel m;
  m.normal = model::NormalModel::hooke;
  m.characteristic_velocity = characteristic_velocity;
  return m;
}

}  // namespace

class HookeHeadOn : public ::testing::TestWithParam<double> {};

// A linear spring k_n with the dashpot gamma_n = sqrt(4 m* k_n ln(e)^2 / (ln(e)^2 + pi^2)) gives
// restitution e exactly and lasts pi / omega_d, omega_d = sqrt(k_n / m* - (gamma_n / 2 m*)^2)
// (zeta = -ln e / sqrt(ln^2 e + pi^2)); at the characteristic velocity an undamped contact
// reaches Hertz's largest overlap. Tolerances: velocity Verlet with half-step velocities in the
// dashpot errs by O(dt / t_c), 1.5e-4 here (6700 steps per contact): restitution measured within
// 2.9e-5, allowed 1.3e-4; the contact time is counted in whole steps: measured within 0.8 of a
// step, allowed 2.
TEST_P(HookeHeadOn, RestitutionIsEAndTheContactLastsPiOverOmegaD) {
  const double e = GetParam(), v = 1.0;
  const auto r = head_on(hooke(v), e, v);
  const auto c = model::sphere_sphere(kSteel, kR, kSteel, kR);
  const double kn = model::hooke_stiffness(c, v);
  const double l = std::log(e);
  const double gamma = std::sqrt(4.0 * c.m_star * kn * l * l / (l * l + model::kPi * model::kPi));
  const double omega_d = std::sqrt(kn / c.m_star - std::pow(gamma / (2.0 * c.m_star), 2));
  std::printf("e %.2f: restitution %.8f, contact time %.6g s (pi / omega_d %.6g s)\n", e, r.restitution, r.contact_time,
              model::kPi / omega_d);
  EXPECT_NEAR(r.restitution, e, 1.3e-4);
  EXPECT_NEAR(r.contact_time, model::kPi / omega_d, 2 * kDt);
  if (e == 1.0) {
    EXPECT_NEAR(r.max_overlap / model::hertz_max_overlap(c, v), 1.0, 1e-4);
    EXPECT_NEAR(r.contact_time, model::contact_time(hooke(v), c, v), 2 * kDt);
  }
}

INSTANTIATE_TEST_SUITE_P(Restitution, HookeHeadOn, ::testing::Values(0.5, 0.9, 1.0),
                         [](const auto& param_info) { return fmt::format("e{:02}", std::lround(param_info.param * 10)); });

// A linear spring's period does not depend on the amplitude: at 0.25 and 4 m/s the contact
// lasts as long (Hertz's would differ by 4^(1/5) each way).
TEST(Hooke, TheContactTimeDoesNotDependOnTheSpeed) {
  const double slow = head_on(hooke(1.0), 1.0, 0.25).contact_time, fast = head_on(hooke(1.0), 1.0, 4.0).contact_time;
  std::printf("contact time at 0.25 m/s %.6g s, at 4 m/s %.6g s\n", slow, fast);
  EXPECT_NEAR(slow, fast, 2 * kDt);
}

namespace {
// A steel sphere thrown at a steel wall at (vt, 0, -vn) with spin w about y, until it leaves;
// per step, the wall's force on it (the sphere's total force: nothing else acts) and torque.
struct WallBounce {
  refsim::Vec3 v, w;
  double normal_impulse = 0.0, worst_ratio = 0.0, torque_impulse = 0.0, worst_torque_ratio = 0.0;
};

WallBounce bounce(const model::ContactModel& contact, double e, double mu, double mu_r, refsim::Vec3 v, refsim::Vec3 w) {
  auto p = parameters(contact, e, mu, mu_r, 2);
  p.walls = {{2, 0.0, 2}};
  System s({steel_sphere(1, {0, 0, kR}, v, w)}, p);
  s.setup();
  WallBounce b;
  for (int k = 0; k < 20000; ++k) {
    s.step();
    const auto f = s.force(0), t = s.torque(0);
    const double fn = std::fabs(f[2]), ft = std::hypot(f[0], f[1]);
    b.normal_impulse += fn * kDt;
    b.torque_impulse += t[1] * kDt;
    if (fn > 0.0) {
      b.worst_ratio = std::max(b.worst_ratio, ft / fn);
      b.worst_torque_ratio = std::max(b.worst_torque_ratio, std::hypot(t[0], t[1], t[2]) / (kR * fn));
    }
  }
  b.v = s.v(0);
  b.w = s.omega(0);
  return b;
}
}  // namespace

// no_history's tangential force is viscous, -gamma_t v_t, capped at mu |F_n|: fast sliding
// (5 m/s against a 1 m/s impact) stays on the cap throughout, so the tangential impulse is mu
// times the integral of |F_n| (to the step's round-off), and it never exceeds the cap.
TEST(NoHistory, FastSlidingTakesMuTimesTheNormalImpulse) {
  model::ContactModel m;
  m.tangential = model::TangentialModel::no_history;
  const double mu = 0.05, vt = 5.0;
  const auto b = bounce(m, 0.7, mu, 0.0, {vt, 0, -1.0}, {0, 0, 0});
  const double mass = model::sphere_mass(kR, kSteel.density);
  const double tangential_impulse = mass * (vt - b.v[0]);
  std::printf("tangential impulse %.8g, mu x normal impulse %.8g; largest |F_t| / |F_n| %.8g\n", tangential_impulse,
              mu * b.normal_impulse, b.worst_ratio);
  EXPECT_NEAR(tangential_impulse / (mu * b.normal_impulse), 1.0, 1e-9);
  EXPECT_LE(b.worst_ratio, mu * (1.0 + 1e-12));
}

// Its damping is gamma_t = gamma_n, zero at e = 1: an elastic contact has no tangential force at
// all, whatever mu (history's spring would grip).
TEST(NoHistory, AnElasticContactHasNoTangentialForce) {
  model::ContactModel m;
  m.tangential = model::TangentialModel::no_history;
  const auto b = bounce(m, 1.0, 10.0, 0.0, {0.3, 0, -1.0}, {0, 0, 0});
  EXPECT_EQ(b.v[0], 0.3);
  EXPECT_EQ(b.w[1], 0.0);
  EXPECT_NEAR(b.v[2], 1.0, 1e-4);
}

// epsd2 on a frictionless contact: turned at 2000 rad/s, the torque spring (k_t R^2, k_t ~
// sqrt(delta)) and the cap mu_r R |F_n| both grow as t^1.5 while the contact loads, the spring
// 4 G* R omega / (mu_r Y* v) = 8 times faster, and the cap then falls: the torque sits on the
// cap from the first step to the last, so the angular impulse is mu_r R times the normal
// impulse, against the spin: measured equal to 1.2e-15, allowed 1e-9. The cap is never
// exceeded and the bounce stays elastic (no sliding friction).
TEST(Epsd2, ASpinningSphereLosesMuRTimesRTimesTheNormalImpulse) {
  model::ContactModel m;
  m.rolling = model::RollingModel::epsd2;
  const double mu_r = 0.2;
  const auto b = bounce(m, 1.0, 0.0, mu_r, {0, 0, -1.0}, {0, 2000.0, 0});
  std::printf("angular impulse / (-mu_r R x normal impulse) - 1 = %.3g; largest |torque| / (R |F_n|) %.8g\n",
              b.torque_impulse / (-mu_r * kR * b.normal_impulse) - 1.0, b.worst_torque_ratio);
  EXPECT_NEAR(b.torque_impulse / (-mu_r * kR * b.normal_impulse), 1.0, 1e-9);
  EXPECT_LE(b.worst_torque_ratio, mu_r * (1.0 + 1e-12));
  EXPECT_NEAR(b.v[2], 1.0, 1e-4);
  EXPECT_EQ(b.v[0], 0.0);
  EXPECT_LT(b.w[1], 2000.0);
}

namespace {
// Between two spheres a rolling model's torques are equal and opposite: with no sliding friction
// the total angular momentum is kept (to round-off) while each sphere's spin changes.
void expect_rolling_keeps_the_angular_momentum(model::RollingModel rolling) {
  model::ContactModel m;
  m.rolling = rolling;
  System s({steel_sphere(1, {0, 0, 0}, {0, 0, 0.5}, {0, 3000.0, 0}), steel_sphere(1, {0, 0, 2 * kR}, {0, 0, -0.5})},
           parameters(m, 1.0, 0.0, 0.1, 1));
  s.setup();
  for (int k = 0; k < 20000; ++k) s.step();
  const double spin0 = s.omega(0)[1], spin1 = s.omega(1)[1];
  std::printf("%s: spins after: %.8g and %.8g rad/s (3000 before)\n", std::string(model::to_string(rolling)).c_str(),
              spin0, spin1);
  EXPECT_LT(spin0, 2990.0);  // the torque acted
  EXPECT_NEAR((spin0 + spin1) / 3000.0, 1.0, 1e-12);
}
}  // namespace

TEST(Epsd2, RollingTorquesBetweenSpheresKeepTheAngularMomentum) {
  expect_rolling_keeps_the_angular_momentum(model::RollingModel::epsd2);
}

// cdt on an elastic frictionless wall contact: the torque is mu_r R k_n delta = mu_r R |F_n| at
// every step (e = 1: no damping part in F_n) against the spin, whatever its speed: the angular
// impulse is mu_r R times the normal impulse at 3000 rad/s and at 1500 rad/s alike (measured equal
// to round-off, allowed 1e-9), each step's torque on that value, and the bounce elastic. (That
// impulse, 2 mu_r m v R, takes 5 mu_r v / R = 1000 rad/s off the spin: a slower one would stop
// within the contact.)
TEST(Cdt, ASpinningSphereLosesMuRTimesRTimesTheNormalImpulseWhateverItsSpin) {
  model::ContactModel m;
  m.rolling = model::RollingModel::cdt;
  const double mu_r = 0.2;
  for (const double spin : {3000.0, 1500.0}) {
    const auto b = bounce(m, 1.0, 0.0, mu_r, {0, 0, -1.0}, {0, spin, 0});
    std::printf("%g rad/s: angular impulse / (-mu_r R x normal impulse) - 1 = %.3g; largest |torque| / (R |F_n|) %.8g\n",
                spin, b.torque_impulse / (-mu_r * kR * b.normal_impulse) - 1.0, b.worst_torque_ratio);
    EXPECT_NEAR(b.torque_impulse / (-mu_r * kR * b.normal_impulse), 1.0, 1e-9) << spin;
    EXPECT_NEAR(b.worst_torque_ratio, mu_r, mu_r * 1e-12) << spin;
    EXPECT_NEAR(b.v[2], 1.0, 1e-4) << spin;
    EXPECT_EQ(b.v[0], 0.0) << spin;
    EXPECT_GT(b.w[1], 0.0) << spin;  // slowed, not turned back
    EXPECT_LT(b.w[1], spin) << spin;
  }
}

TEST(Cdt, RollingTorquesBetweenSpheresKeepTheAngularMomentum) {
  expect_rolling_keeps_the_angular_momentum(model::RollingModel::cdt);
}

// The vector kernels run the study's model only: asked for by name with another, refsim says so.
namespace {
// A steel sphere thrown at a steel wall at (vt, 0, -vn) by LAMMPS's rules with `tangential`, mu =
// 1 (it sticks), undamped: per step, the sphere's height and the wall's force on it.
struct Trace {
  std::vector<double> z;
  std::vector<refsim::Vec3> f;
};
Trace wall_trace(model::TangentialModel tangential) {
  model::ContactModel m;
  m.tangential = tangential;
  auto p = parameters(m, 1.0, 1.0, 0.0, 2);
  p.lammps_rules = true;
  p.walls = {{2, 0.0, 2}};
  System s({steel_sphere(1, {0, 0, kR}, {0.2, 0, -1.0})}, p);
  s.setup();
  Trace t;
  for (int k = 0; k < 20000 && s.x(0)[2] <= kR; ++k) {
    s.step();
    t.z.push_back(s.x(0)[2]);
    t.f.push_back(s.force(0));
  }
  return t;
}
}  // namespace

// mindlin_rescale is mindlin's spring, its displacement scaled by a / a_last only when the contact
// radius a = sqrt(R* d) shrinks: while the sphere goes into the wall (the overlap, and so a, grows
// at every step), the two give the same force to the bit; once it comes out, the rescaled spring
// departs from mindlin's (measured: by 0.17 of the largest tangential force; more than 1e-3 is
// asked, far above the last bits and far below what either spring gives).
TEST(MindlinRescale, IsMindlinWhileTheContactLoadsAndDepartsAsItUnloads) {
  const auto mindlin = wall_trace(model::TangentialModel::history);
  const auto rescale = wall_trace(model::TangentialModel::mindlin_rescale);
  ASSERT_GT(mindlin.z.size(), 100u);
  std::size_t deepest = 0;
  while (deepest + 1 < mindlin.z.size() && mindlin.z[deepest + 1] < mindlin.z[deepest]) ++deepest;
  ASSERT_GT(deepest, 10u);
  for (std::size_t k = 0; k <= deepest; ++k) {
    ASSERT_EQ(rescale.z[k], mindlin.z[k]) << k;
    for (int d = 0; d < 3; ++d) ASSERT_EQ(rescale.f[k][d], mindlin.f[k][d]) << "step " << k << ", axis " << d;
  }
  double largest = 0.0, departure = 0.0;
  for (std::size_t k = 0; k < std::min(mindlin.f.size(), rescale.f.size()); ++k) {
    largest = std::max(largest, std::fabs(mindlin.f[k][0]));
    departure = std::max(departure, std::fabs(rescale.f[k][0] - mindlin.f[k][0]));
  }
  std::printf("loading steps %zu of %zu; tangential force: largest %.6g N, rescale's largest departure %.6g N\n",
              deepest + 1, mindlin.z.size(), largest, departure);
  EXPECT_GT(departure, 1e-3 * largest);
}

// The kernel alone (refsim's private contact_models/): a spring of displacement s0 on a contact
// that unloads with no tangential motion, its radius a falling to half in ten steps. mindlin's
// stiffness 8 G* a falls with a, so its force does; mindlin_rescale also scales the displacement
// by a / a_last at each step, so its force falls as a^2: at every step F / F_0 = (a / a_0)^2, to
// the last bits (a product of ten ratios: allowed 1e-14), and the last radius is kept.
TEST(MindlinRescale, AnUnloadingSpringWithNoTangentialMotionFallsAsTheContactRadiusSquared) {
  namespace detail = refsim::detail;
  const double a0 = 1e-4, k = 8.0 * 70e9, s0 = 1e-8, mu = 1e3, fn = 1e3;
  detail::ContactPoint c{};
  c.en[2] = 1.0;
  double rescaled[detail::kMindlinRescaleHistory] = {s0, 0.0, 0.0, 0.0}, plain[detail::kMindlinRescaleHistory] = {s0, 0.0, 0.0, 0.0};
  double f0 = 0.0;
  for (int step = 0; step <= 10; ++step) {
    const double a = a0 * (1.0 - 0.05 * step);
    const detail::Normal n{fn, k * a, 0.0, 0.0, a};
    double ft[3], fm[3];
    detail::tangential_mindlin_rescale(rescaled, c, n, mu, true, 1e-9, ft);
    detail::tangential_mindlin(plain, c, n, mu, true, 1e-9, fm);
    if (step == 0) f0 = ft[0];
    EXPECT_EQ(fm[0], -k * a * s0) << step;
    EXPECT_NEAR(ft[0] / f0, (a / a0) * (a / a0), 1e-14) << step;
    EXPECT_EQ(rescaled[3], a) << step;
  }
  EXPECT_LT(f0, 0.0);
}

// Every sub-model an engine has (its row gives no refusal for it) has its kernel in that engine's
// rules, and every one it lacks is refused with the row's own words: the tables of
// contact_models/composition.cpp and model/src/contact_models.cpp say the same.
TEST(ContactModels, EveryModelAnEngineRunsHasItsKernelThere) {
  for (const bool lammps : {false, true}) {
    for (const auto tangential : model::all_models<model::TangentialModel>()) {
      for (const auto rolling : model::all_models<model::RollingModel>()) {
        model::ContactModel m;
        m.tangential = tangential;
        m.rolling = rolling;
        auto p = parameters(m, 0.9, 0.3, 0.1, 1);
        p.lammps_rules = lammps;
        p.kernel = "reference";
        const auto refusal = lammps ? model::lammps_refusal(m) : model::liggghts_refusal(m);
        const auto what = fmt::format("{}, {} by {}'s rules", model::to_string(tangential), model::to_string(rolling),
                                      lammps ? "LAMMPS" : "LIGGGHTS");
        try {
          System s({steel_sphere(1, {0, 0, 0}, {0, 0, 0})}, p);
          EXPECT_TRUE(refusal.empty()) << what << " ran";
        } catch (const std::invalid_argument& e) {
          EXPECT_FALSE(refusal.empty()) << what << ": " << e.what();
          EXPECT_NE(std::string(e.what()).find(refusal), std::string::npos) << what << ": " << e.what();
        }
      }
    }
  }
}

// A model the vector pair kernels do not run has its pairs on the reference kernel and its
// particles on the vector kernels, and says so (the same bits: Kernels.ThorntonAndHooke...).
TEST(ContactModels, AVectorKernelWithAnotherModelRunsItsPairsOnTheReference) {
  auto p = parameters(hooke(1.0), 1.0, 0.0, 0.0, 1);
  const auto best = refsim::vector_kernels().front();
  for (const std::string& kernel : {best, std::string("auto")}) {
    p.kernel = kernel;
    EXPECT_EQ(System({steel_sphere(1, {0, 0, 0}, {0, 0, 0})}, p).kernel(), best + System::kReferencePairs);
  }
  p.kernel = "reference";
  EXPECT_EQ(System({steel_sphere(1, {0, 0, 0}, {0, 0, 0})}, p).kernel(), "reference");
}
