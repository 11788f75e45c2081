// Contact parameters and analytic formulas against the numbers of physics.md and
// docs/liggghts.md section 10.1 (steel, d = 2 mm, relative speed 1 m/s).
#include <cstdio>
#include <granstack/model/contact.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>

using namespace granstack::model;

namespace {

Material steel() { return *MaterialLibrary::builtin().find("steel"); }

TEST(Contact, SteelHeadOnMatchesTheLiggghtsFactsSheet) {
  const auto c = sphere_sphere(steel(), 1e-3, steel(), 1e-3);
  EXPECT_NEAR(c.m_star, 1.675516e-5, 1e-11);
  EXPECT_DOUBLE_EQ(c.r_star, 5e-4);
  EXPECT_NEAR(c.y_star / 1.060440e11, 1.0, 1e-6);
  EXPECT_DOUBLE_EQ(c.y_star, 193e9 / (2.0 * (1.0 - 0.09)));  // equal materials: Y / (2 (1 - nu^2))
  EXPECT_DOUBLE_EQ(c.g_star, 193e9 / (4.0 * 1.7 * 1.3));     // equal materials: Y / (4 (2 - nu)(1 + nu))
  EXPECT_NEAR(hertz_max_overlap(c, 1.0) / 2.130392289e-6, 1.0, 1e-9);
  // 2.9432752 d_max / v = 6.2703e-6 s (docs/liggghts.md 10.1; LIGGGHTS measured 6.270e-6 s)
  EXPECT_NEAR(hertz_contact_time(c, 1.0) / 6.2703e-6, 1.0, 1e-5);
  EXPECT_NEAR(rayleigh_time(steel(), 1e-3) / 1.1143e-6, 1.0, 1e-4);
}

TEST(Contact, ElasticEnergyIsTheIntegralOfTheHertzForce) {
  // F = 4/3 Y* sqrt(R*) d^(3/2); integrate numerically (Simpson) and compare with 8/15 Y* sqrt(R*) d^(5/2).
  const double y = 1e11, r = 5e-4, dmax = 2e-6;
  const int n = 2000;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double d = dmax * i / n;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * 4.0 / 3.0 * y * std::sqrt(r) * std::pow(d, 1.5);
  }
  EXPECT_NEAR(sum * dmax / n / 3.0 / hertz_elastic_energy(y, r, dmax), 1.0, 1e-6);
}

// The contact-time coefficient 2 int_0^1 (1 - x^(5/2))^(-1/2) dx, integrated here on its own:
// with x = 1 - w^2 the integrand 2w (1 - (1 - w^2)^(5/2))^(-1/2) is smooth on [0, 1], and
// 1 - (1 - w^2)^(5/2) = -expm1(5/2 log1p(-w^2)) keeps its digits near w = 0 (Simpson).
TEST(Contact, HertzTimeCoefficientIsTheCollisionIntegral) {
  const int n = 20000;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double w = static_cast<double>(i) / n;
    const double gap = -std::expm1(2.5 * std::log1p(-w * w));
    const double f = i == 0 ? 2.0 / std::sqrt(2.5) : 2.0 * w / std::sqrt(gap);
    sum += ((i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0)) * f;
  }
  const double integral = 2.0 * sum / n / 3.0;
  EXPECT_NEAR(hertz_time_coefficient(), integral, 1e-12);
  EXPECT_NEAR(hertz_time_coefficient(), 2.9432752, 1e-7);  // the value to 8 digits
  EXPECT_NE(hertz_time_coefficient(), 2.9432);             // not the truncated constant
}

// Every normal law's largest overlap and contact time (what the automatic time step is built on)
// are those of a head-on impact integrated here with its own elastic force: m* x'' = -F(x) from
// x = 0 at speed v, velocity Verlet at 2e5 steps per contact, the return through x = 0 found by
// linear interpolation. Measured: 3.1e-11 at most (the integration's own error, second order in its
// step); bound 1e-9. A new row is checked with no new test.
TEST(ContactModels, EveryNormalLawsOverlapAndContactTimeAreItsOwnForceIntegrated) {
  const auto pair = sphere_sphere(steel(), 1e-3, steel(), 1e-3);
  for (std::size_t row = 0; row < kNormalModelCount; ++row) {
    ContactModel m;
    m.normal = static_cast<NormalModel>(row);
    m.characteristic_velocity = 1.0;
    const auto& law = normal_law(m.normal);
    for (const double v : {0.1, 1.0, 5.0}) {
      SCOPED_TRACE(std::string(to_string(m.normal)) + " at " + std::to_string(v) + " m/s");
      const double expected_time = law.contact_time(m, pair, v), expected_overlap = law.max_overlap(m, pair, v);
      ASSERT_TRUE(expected_time > 0.0 && expected_overlap > 0.0);
      const double dt = expected_time / 2e5;
      double x = 0.0, u = v, t = 0.0, deepest = 0.0;
      double a = 0.0;  // F(0) = 0
      while (x >= 0.0 && t < 2.0 * expected_time) {
        const double x_before = x;
        u += 0.5 * dt * a;
        x += dt * u;
        a = -law.force(m, pair, std::max(x, 0.0)) / pair.m_star;
        u += 0.5 * dt * a;
        t += dt;
        deepest = std::max(deepest, x);
        if (x < 0.0) t -= dt * x / (x - x_before);  // back to where it crossed zero
      }
      EXPECT_NEAR(deepest / expected_overlap, 1.0, 1e-9);
      EXPECT_NEAR(t / expected_time, 1.0, 1e-9);
    }
  }
}

TEST(Contact, RestitutionBetaFollowsTheLiggghtsFormula) {
  EXPECT_EQ(restitution_beta(1.0), 0.0);
  EXPECT_NEAR(restitution_beta(0.9), std::log(0.9) / std::sqrt(std::log(0.9) * std::log(0.9) + M_PI * M_PI), 1e-16);
  EXPECT_LT(restitution_beta(0.5), 0.0);
}

// The sub-models' table: each model's keyword reads back to it (and no other), the first of each
// kind is the study's (both engines run it), the help names the keyword first, a refusal names
// the model it refuses, and a model LAMMPS runs has its word there (LIGGGHTS's is the keyword).
template <typename Model, typename Parse>
void expect_table_reads_back(Parse parse) {
  const auto models = all_models<Model>();
  ASSERT_GE(models.size(), 2u);
  EXPECT_TRUE(info(models.front()).lammps_refusal.empty());
  EXPECT_TRUE(info(models.front()).liggghts_refusal.empty());
  for (const auto m : models) {
    const auto& row = info(m);
    EXPECT_EQ(parse(row.keyword), m) << row.keyword;
    EXPECT_EQ(row.help.substr(0, row.keyword.size()), row.keyword);
    EXPECT_NE(keyword_list<Model>().find("'" + std::string(row.keyword) + "'"), std::string::npos);
    for (const auto refusal : {row.lammps_refusal, row.liggghts_refusal}) {
      if (!refusal.empty()) {
        EXPECT_NE(refusal.find(row.keyword), std::string::npos) << row.keyword;
      }
    }
    // Some engine runs every model: LIGGGHTS or LAMMPS, or refsim's own law in LIGGGHTS's frame
    // (thornton, a normal model: refsim has a kernel for every normal model).
    constexpr bool refsim_runs_it = std::is_same_v<Model, NormalModel>;
    EXPECT_TRUE(row.lammps_refusal.empty() || row.liggghts_refusal.empty() || refsim_runs_it)
        << row.keyword << ": neither engine runs it";
    if constexpr (std::is_same_v<Model, TangentialModel>) {
      EXPECT_EQ(row.lammps_word.empty(), !row.lammps_refusal.empty()) << row.keyword;
    }
  }
  EXPECT_FALSE(parse("none of them").has_value());
}

TEST(ContactModels, EveryKeywordReadsBackToItsModel) {
  expect_table_reads_back<NormalModel>(parse_normal_model);
  expect_table_reads_back<TangentialModel>(parse_tangential_model);
  expect_table_reads_back<RollingModel>(parse_rolling_model);
  EXPECT_EQ(keyword_list<NormalModel>(), "'hertz', 'hooke', 'thornton' or 'thornton_ning'");
  EXPECT_EQ(to_string(NormalModel::hertz), "hertz");
}

TEST(Resolution, AutomaticTimeStepIsAFixedFractionOfTheShortestContact) {
  StackSpec s;
  const auto stack = Stack::build(s);
  const auto r = resolve(stack);
  // The shortest contact is between two bottom spheres (the smallest, lightest pair).
  EXPECT_EQ(r.min_contact_pair, "block 4 - block 4");
  EXPECT_DOUBLE_EQ(r.min_contact_time, hertz_contact_time(sphere_sphere(steel(), 1e-3, steel(), 1e-3), 1.0));
  EXPECT_DOUBLE_EQ(r.dt, r.min_contact_time / kStepsPerContact);
  EXPECT_EQ(r.steps % r.dump_every, 0);  // the final state is dumped
  EXPECT_GE(r.duration, kDurationPerArrival * r.arrival_estimate * (1 - 1e-12));  // steps round to 1e-9 of a step
  // physics.md section 6: the output sphere of the 4-block stack has its final energy by ~390 us.
  EXPECT_GT(r.duration, 390e-6);
}

// A soft block with stiffer ones above and below it holds the pulse and lets it out in bursts;
// only such stacks get the longer automatic duration.
// Over a bottom wall the series samples the wall's force at least 20 times per contact of a
// bottom sphere on the wall (#47 item 8), whatever the run's length: three nylon blocks over a
// steel one (ratios 3, 8 rows each; a 0.3 mm steel bottom on the steel wall, the shortest contact,
// and a long run of soft blocks) had every 6th step sampled, 19.1 samples per wall contact (now
// every 5th, 23.0; printed).
TEST(Resolution, TheSeriesResolvesTheWallsContact) {
  StackSpec s;
  s.blocks = 4;
  s.radius_ratios = {3, 3, 3};
  s.block_rows = {8, 8, 8, 8};
  s.materials = {"nylon", "nylon", "nylon", "steel"};
  s.bottom_radius = 8e-3 / 27;
  s.bottom = Boundary::wall;
  s.wall_material = "steel";
  s.striker_speed = 2.0;
  const auto r = resolve(Stack::build(s));
  ASSERT_GT(r.wall_contact_time, 0.0);
  const double per_contact = r.wall_contact_time / (r.series_every * r.dt);
  EXPECT_GE(per_contact, kSeriesPerWallContact);
  // The old cadence, by the run's length alone: ceil(steps / kAutoSeriesSamples).
  const double by_length = std::ceil(std::ceil(r.steps_asked - 1e-9) / static_cast<double>(kAutoSeriesSamples));
  std::printf("samples per wall contact: %.4g (every %d steps), %.4g by the run's length alone (every %.0f)\n", per_contact,
              r.series_every, r.wall_contact_time / (by_length * r.dt), by_length);
  EXPECT_LT(r.wall_contact_time / (by_length * r.dt), kSeriesPerWallContact);  // the rule bites here
  s.bottom = Boundary::free_surface;
  EXPECT_EQ(resolve(Stack::build(s)).wall_contact_time, 0.0);
}

TEST(Resolution, OnlyASoftBlockBetweenStifferOnesMakesACavityAndALongerRun) {
  const std::pair<std::vector<std::string>, bool> stacks[] = {
      {{"steel"}, false},
      {{"steel", "teflon"}, false},
      {{"teflon", "steel"}, false},  // the striker is Teflon too: nothing stiffer above
      {{"teflon", "steel", "teflon"}, false},
      {{"steel", "steel", "teflon", "teflon"}, false},
      {{"steel", "teflon", "steel"}, true},
      {{"steel", "teflon", "teflon", "steel"}, true},
      {{"teflon", "steel", "teflon", "steel"}, true},
  };
  for (const auto& [materials, cavity] : stacks) {
    StackSpec s;
    s.materials = materials;
    s.blocks = materials.size() == 1 ? 4 : static_cast<int>(materials.size());
    const auto r = resolve(Stack::build(s));
    EXPECT_EQ(has_soft_cavity(Stack::build(s)), cavity) << materials.size() << " " << materials.back();
    EXPECT_EQ(r.soft_cavity, cavity);
    const double per_arrival = cavity ? kCavityDurationPerArrival : kDurationPerArrival;
    EXPECT_NEAR(r.duration / r.arrival_estimate, per_arrival, 1e-2);
  }
  // A steel striker on a Teflon block resting on steel: the striker is the stiffer thing above.
  StackSpec s;
  s.blocks = 2;
  s.materials = {"teflon", "steel"};
  s.striker_material = "steel";
  EXPECT_TRUE(has_soft_cavity(Stack::build(s)));
}

TEST(Resolution, TimeStepScalesAsSpeedToTheMinusOneFifth) {
  StackSpec slow, fast;
  slow.striker_speed = 0.1;
  const double ratio = resolve(Stack::build(slow)).dt / resolve(Stack::build(fast)).dt;
  EXPECT_NEAR(ratio, std::pow(10.0, 0.2), 1e-12);
}

TEST(Resolution, ExplicitValuesAreHonoured) {
  StackSpec s;
  s.blocks = 1;
  s.dt = 1e-8;
  s.duration = 1e-5;
  s.dump_every = 100;
  s.series_every = 7;
  const auto r = resolve(Stack::build(s));
  EXPECT_EQ(r.dt, 1e-8);
  EXPECT_EQ(r.steps, 1000);
  EXPECT_EQ(r.dump_every, 100);
  EXPECT_EQ(r.series_every, 7);
  EXPECT_FALSE(r.dt_auto);
  s.dump_every = 300;  // not a divisor: the run is lengthened to the next dump
  EXPECT_EQ(resolve(Stack::build(s)).steps, 1200);
}

}  // namespace

// Hooke's spring is calibrated so that its largest overlap at the characteristic velocity is
// Hertz's; left automatic, that velocity is the striker's speed. At 3 m/s (not the 1 m/s default
// speed, where a constant 1 m/s would pass unseen) the striker's Hooke overlap on a top sphere is
// Hertz's at 3 m/s, and a spring calibrated at 1 m/s gives another one (v sqrt(m*/k), k fixed).
TEST(Contact, HookesAutomaticCalibrationIsAtTheStrikersSpeed) {
  StackSpec spec;
  spec.blocks = 1;
  spec.normal_model = NormalModel::hooke;
  spec.striker_speed = 3.0;
  const auto stack = Stack::build(spec);
  const auto pair = striker_contact(stack);
  const double hertz = hertz_max_overlap(pair, 3.0);
  EXPECT_NEAR(max_overlap(spec.contact_model(), pair, 3.0), hertz, 1e-12 * hertz);
  spec.characteristic_velocity = 1.0;
  const double at_one = max_overlap(spec.contact_model(), pair, 3.0);
  // Calibrated at 1 m/s: Hertz's overlap at 1 m/s, times 3 (linear in v).
  EXPECT_NEAR(at_one, 3.0 * hertz_max_overlap(pair, 1.0), 1e-12 * at_one);
  EXPECT_GT(std::abs(at_one - hertz), 0.1 * hertz);
}
