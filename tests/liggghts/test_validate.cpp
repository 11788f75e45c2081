// postproc::compare_runs, what `granstack validate` certifies with, on a real LIGGGHTS run and a
// refsim run of one case: it agrees to round-off, and every way a run can be incomplete or
// different is a disagreement, named, never skipped.
#include <granstack/formats/case.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/generator/spec_input.hpp>
#include <granstack/postproc/compare.hpp>
#include <granstack/postproc/reduce.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/runner/runner.hpp>

#include "../support/scratch.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace granstack;
namespace fs = std::filesystem;

namespace {

std::string read_bytes(const fs::path& f) { return formats::read_file(f); }
void write_bytes(const fs::path& f, const std::string& text) { std::ofstream(f, std::ios::binary) << text; }

// Generates `spec` into ROOT/liggghts and ROOT/refsim and runs each on its engine.
void run_both_engines(const fs::path& root, const model::StackSpec& spec) {
  for (const auto* engine : {"liggghts", "refsim"}) {
    generator::GenerateOptions o;
    o.output = root / engine;
    generator::generate({{engine, spec}}, o);
    runner::RunOptions r;
    r.engine = std::string(engine) == "refsim" ? runner::Engine::refsim : runner::Engine::liggghts;
    const auto outcome = runner::run_cases({o.output.string()}, r);
    ASSERT_EQ(outcome.front().status, runner::RunStatus::done) << outcome.front().message;
  }
}

class Validate : public ::testing::Test {
 protected:
  // Each test in a directory of its own (ctest runs them as parallel processes): a LIGGGHTS
  // run and a refsim run of one damped, frictional case, and b_, the refsim run to spoil.
  void SetUp() override {
    root_ = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) /
                          ("validate_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())));
    fs::remove_all(root_);
    model::StackSpec spec;
    spec.blocks = 2;
    spec.rows = 4;
    spec.restitution.value = 0.9;
    spec.friction.value = 0.25;
    run_both_engines(root_, spec);
    b_ = root_ / "refsim";
  }
  postproc::RunComparison compare() const { return postproc::compare_runs((root_ / "liggghts").string(), b_.string()); }
  static bool mentions(const postproc::RunComparison& c, const std::string& words) {
    for (const auto& m : c.mismatches) {
      if (m.find(words) != std::string::npos) return true;
    }
    return false;
  }
  fs::path root_, b_;
};

TEST_F(Validate, RealRunsAgreeToRoundOffInEveryColumnFrameAndRow) {
  const auto c = compare();
  EXPECT_TRUE(c.mismatches.empty()) << c.mismatches.front();
  EXPECT_LE(c.worst(), postproc::kDefaultTolerance) << c.largest().quantity;
  EXPECT_EQ(c.disagreement(postproc::kDefaultTolerance), "");  // validate's verdict, and design confirm's
  // Every column the deck dumps, including those LIGGGHTS leaves at zero in this plane (y, vy,
  // omegax, omegaz, fy, tqx, tqz), is compared for every sphere of every frame.
  EXPECT_EQ(c.dump.size(), 18u);  // the 19 dump columns but the id, which keys the spheres
  EXPECT_GT(c.frames, 100);
  constexpr long kSpheres = 1 + 4 * 2 + 4 * 4;  // the striker, 4 rows of 2 and of 4 columns
  for (const auto& d : c.dump) EXPECT_EQ(d.values, c.frames * kSpheres) << d.quantity;
  // Translational and rotational KE of 2 blocks, striker, output sphere, bottom row and each
  // block's middle-row sphere of the impact path.
  EXPECT_EQ(c.series.size(), 14u);
  for (const auto& d : c.series) EXPECT_EQ(d.values, c.series_rows) << d.quantity;
  EXPECT_EQ(c.output_fraction.values, 1);
}

TEST_F(Validate, AColumnThatShouldBeZeroIsComparedToo) {
  auto dump = read_bytes(b_ / "dumps/dump.txt");
  // The second frame's first atom line: its vy (the 9th value) becomes 1e-6 m/s.
  auto at = dump.find("ITEM: ATOMS", dump.find("ITEM: ATOMS") + 1);
  at = dump.find('\n', at) + 1;
  for (int k = 1; k < 9; ++k) at = dump.find(' ', at) + 1;
  dump.replace(at, dump.find(' ', at) - at, "1e-06");
  write_bytes(b_ / "dumps/dump.txt", dump);
  const auto c = compare();
  EXPECT_GT(c.worst(), postproc::kDefaultTolerance);
  EXPECT_EQ(c.largest().quantity, "vy");
  EXPECT_EQ(c.largest().atom, 1);
  // One verdict (#47 item 7): design confirm, whose objectives (peak force, crush) this leaves
  // alone, calls it a disagreement as validate does.
  EXPECT_NE(c.disagreement(postproc::kDefaultTolerance).find("whole runs differ by"), std::string::npos);
  EXPECT_NE(c.disagreement(postproc::kDefaultTolerance).find("(vy, step"), std::string::npos);
}

TEST_F(Validate, MissingFramesRowsAndColumnsAndNonFiniteValuesAreMismatches) {
  const auto dump = read_bytes(b_ / "dumps/dump.txt");
  const auto series = read_bytes(b_ / "ke_series.txt");
  // The last dump frame gone.
  write_bytes(b_ / "dumps/dump.txt", dump.substr(0, dump.rfind("ITEM: TIMESTEP")));
  auto c = compare();
  EXPECT_TRUE(mentions(c, "has more dump frames than")) << (c.mismatches.empty() ? "" : c.mismatches.front());
  EXPECT_FALSE(c.worst() <= 1.0);
  EXPECT_EQ(c.disagreement(1.0), c.mismatches.front());  // a run that stopped at another frame disagrees
  write_bytes(b_ / "dumps/dump.txt", dump);
  // A series row gone from the middle.
  const auto middle = series.find('\n', series.size() / 2) + 1;
  write_bytes(b_ / "ke_series.txt", series.substr(0, middle) + series.substr(series.find('\n', middle) + 1));
  c = compare();
  EXPECT_TRUE(mentions(c, "series rows")) << (c.mismatches.empty() ? "" : c.mismatches.front());
  // A series column gone.
  std::istringstream in(series);
  std::string line, cut;
  while (std::getline(in, line)) cut += line.substr(0, line.rfind(' ')) + "\n";
  write_bytes(b_ / "ke_series.txt", cut);
  c = compare();
  EXPECT_TRUE(mentions(c, "the series have other columns"));
  write_bytes(b_ / "ke_series.txt", series);
  // NaN in a dump column.
  auto nan = dump;
  auto at = nan.find('\n', nan.find("ITEM: ATOMS", nan.size() / 2)) + 1;
  for (int k = 1; k < 14; ++k) at = nan.find(' ', at) + 1;
  nan.replace(at, nan.find(' ', at) - at, "nan");
  write_bytes(b_ / "dumps/dump.txt", nan);
  c = compare();
  EXPECT_TRUE(mentions(c, "nan in column 'fx'")) << (c.mismatches.empty() ? "" : c.mismatches.front());
  EXPECT_FALSE(c.worst() <= 1.0);
}

// Every contact model granstack offers (model/contact.hpp), on a stack: LIGGGHTS and refsim agree
// to round-off in every column, frame and row (refsim's reference kernels; the two-body cases of
// tests/data/twobody agree bit for bit). Walls, friction and damping on, so each model's every
// term acts.
struct ModelCase {
  const char* name;
  model::NormalModel normal;
  model::TangentialModel tangential;
  model::RollingModel rolling;
};

class ValidateModel : public ::testing::TestWithParam<ModelCase> {};

TEST_P(ValidateModel, LiggghtsAndRefsimAgreeToRoundOff) {
  const auto& mc = GetParam();
  const auto root = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / (std::string("validate_model_") + mc.name));
  fs::remove_all(root);
  model::StackSpec spec;
  spec.blocks = 2;
  spec.rows = 4;
  // The elastic-plastic laws dissipate by yielding and take restitution 1 (no dashpot).
  spec.restitution.value = model::normal_law(mc.normal).dissipative ? 1.0 : 0.8;
  spec.friction.value = 0.3;
  spec.bottom = model::Boundary::wall;
  spec.sides = model::Boundary::wall;
  spec.normal_model = mc.normal;
  spec.tangential_model = mc.tangential;
  spec.rolling_model = mc.rolling;
  if (mc.rolling != model::RollingModel::off) spec.rolling_friction.value = 0.1;
  if (mc.normal == model::NormalModel::hooke) spec.characteristic_velocity = 0.5;
  run_both_engines(root, spec);
  if (HasFatalFailure()) return;
  const auto c = postproc::compare_runs((root / "liggghts").string(), (root / "refsim").string());
  EXPECT_TRUE(c.mismatches.empty()) << c.mismatches.front();
  EXPECT_LE(c.worst(), postproc::kDefaultTolerance) << c.largest().quantity;
  EXPECT_GT(c.frames, 100);
  std::printf("%s: largest difference %.3g (%s)\n", mc.name, c.worst(), c.largest().quantity.c_str());
}

// A design's stack (each interface its own ratio, odd and even; each block its rows) on both
// engines: they agree to round-off, and reduce finds kinetic plus elastic energy kept (e = 1)
// within 3e-4 of E_in (velocity Verlet at the automatic dt, tests/liggghts/test_pipeline.cpp).
TEST(ValidateDesign, PerInterfaceRatiosAndPerBlockRowsRunAlikeOnBothEngines) {
  const auto root = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / "validate_design");
  fs::remove_all(root);
  model::StackSpec spec;
  spec.blocks = 3;
  spec.radius_ratios = {3, 2};
  spec.block_rows = {4, 2, 3};
  run_both_engines(root, spec);
  if (HasFatalFailure()) return;
  const auto c = postproc::compare_runs((root / "liggghts").string(), (root / "refsim").string());
  EXPECT_TRUE(c.mismatches.empty()) << c.mismatches.front();
  EXPECT_LE(c.worst(), postproc::kDefaultTolerance) << c.largest().quantity;
  postproc::ReduceOptions quiet;
  quiet.write_files = false;
  const auto r = postproc::reduce_case((root / "liggghts").string(), quiet);
  ASSERT_TRUE(r.energy_drift.has_value());
  std::printf("design stack: largest difference %.3g, energy drift %.3g, output fraction %.4g\n", c.worst(),
              *r.energy_drift, r.output_fraction);
  EXPECT_LT(*r.energy_drift, 3e-4);
  EXPECT_GT(r.output_fraction, 0.0);
}

INSTANTIATE_TEST_SUITE_P(
    Models, ValidateModel,
    ::testing::Values(ModelCase{"hooke", model::NormalModel::hooke, model::TangentialModel::history, model::RollingModel::off},
                      ModelCase{"no_history", model::NormalModel::hertz, model::TangentialModel::no_history,
                                model::RollingModel::off},
                      ModelCase{"epsd2", model::NormalModel::hertz, model::TangentialModel::history, model::RollingModel::epsd2},
                      ModelCase{"hooke_no_history_epsd2", model::NormalModel::hooke, model::TangentialModel::no_history,
                                model::RollingModel::epsd2},
                      ModelCase{"cdt", model::NormalModel::hertz, model::TangentialModel::history, model::RollingModel::cdt},
                      ModelCase{"hooke_cdt", model::NormalModel::hooke, model::TangentialModel::history,
                                model::RollingModel::cdt},
                      ModelCase{"thornton_ning", model::NormalModel::thornton_ning, model::TangentialModel::history,
                                model::RollingModel::off}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace

// A test's own empty folder under the work directory.
fs::path fresh_root(const std::string& name) {
  const auto root = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / name);
  fs::remove_all(root);
  return root;
}

// Two steel blocks of 4 rows over a bottom wall.
model::StackSpec two_blocks_on_a_wall() {
  model::StackSpec s;
  s.blocks = 2;
  s.rows = 4;
  s.bottom = model::Boundary::wall;
  return s;
}

// The protected plate on LIGGGHTS (a mesh moved with an atom of its mass, model::plate_body) and
// on refsim: a damped, frictional stack between side walls on a plate 3.7 times its mass, on a
// spring and dashpot, runs alike to round-off, the plate's columns too (their gaps printed), and
// the plate moves (more than a micrometre, against the spheres' overlaps of about 0.1 um).
TEST(ValidatePlate, APlateOnItsMountRunsAlikeOnLiggghtsAndRefsim) {
  const auto root = fresh_root("validate_plate");
  auto spec = two_blocks_on_a_wall();
  spec.restitution.value = 0.9;
  spec.friction.value = 0.25;
  spec.sides = model::Boundary::wall;
  spec.plate_mass = 0.01;
  spec.mount_stiffness = 2e5;
  spec.mount_damping = 5.0;
  run_both_engines(root, spec);
  if (HasFatalFailure()) return;
  const auto c = postproc::compare_runs((root / "liggghts").string(), (root / "refsim").string());
  EXPECT_TRUE(c.mismatches.empty()) << c.mismatches.front();
  EXPECT_LE(c.worst(), postproc::kDefaultTolerance) << c.largest().quantity;
  int plate_columns = 0;
  for (const auto& q : c.series) {
    if (q.quantity.rfind("plate_", 0) != 0) continue;
    ++plate_columns;
    std::printf("%s: largest difference %.3g over %ld values\n", q.quantity.c_str(), q.relative, q.values);
  }
  EXPECT_EQ(plate_columns, 3);
  const auto dir = root / "liggghts";
  const auto series = formats::read_series((dir / formats::Case::open(dir.string()).files().series).string());
  const int z = series.column("plate_z");
  ASSERT_GE(z, 0);
  double lowest = 0.0;
  for (const auto& row : series.rows) lowest = std::min(lowest, row[static_cast<std::size_t>(z)]);
  EXPECT_LT(lowest, -1e-6);
}

// A plate a billion times the stack's mass is the rigid wall on LIGGGHTS too: its mesh, moved by
// the body's nanometres, gives the primitive wall's answers to 1e-9.
TEST(ValidatePlate, OnLiggghtsAPlateFarHeavierThanTheStackIsTheRigidWall) {
  const auto root = fresh_root("validate_heavy_plate");
  const auto wall = two_blocks_on_a_wall();
  auto plate = wall;
  plate.plate_mass = 1e9;
  postproc::ReduceOptions quiet;
  quiet.write_files = false;
  std::vector<postproc::CaseReduction> r;
  for (const auto& [name, spec] : {std::pair{"wall", wall}, std::pair{"plate", plate}}) {
    generator::GenerateOptions o;
    o.output = root / name;
    generator::generate({{name, spec}}, o);
    ASSERT_EQ(runner::run_cases({o.output.string()}, runner::RunOptions{}).front().status, runner::RunStatus::done);
    r.push_back(postproc::reduce_case(o.output.string(), quiet));
  }
  const auto gap = [](double a, double b) { return std::abs(a - b) / std::max(std::abs(a), std::abs(b)); };
  std::printf("heavy plate against the rigid wall on LIGGGHTS: output fraction %.3g, peak force %.3g, crush %.3g apart\n",
              gap(r[0].output_fraction, r[1].output_fraction), gap(*r[0].peak_wall_force, *r[1].peak_wall_force),
              gap(r[0].crush, r[1].crush));
  EXPECT_LT(gap(r[0].output_fraction, r[1].output_fraction), 1e-9);
  EXPECT_LT(gap(*r[0].peak_wall_force, *r[1].peak_wall_force), 1e-9);
  EXPECT_LT(gap(r[0].crush, r[1].crush), 1e-9);
}

// Per-pair restitution and friction reach LIGGGHTS's deck: steel over brass with the steel-brass
// pair's coefficients far from the diagonal's (e 0.5 against 0.95, mu 0.6 against 0.1), so a
// deck that wrote the diagonal for every pair would part from refsim (which reads the spec's
// table) at the interface's first contact. The pair changes the physics (the output fraction
// moves), and the two engines still agree to round-off on it.
TEST(ValidatePairs, PerPairRestitutionAndFrictionReachLiggghts) {
  const auto root = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / "validate_pairs");
  fs::remove_all(root);
  model::StackSpec spec;
  spec.blocks = 2;
  spec.rows = 4;
  spec.materials = {"steel", "brass"};
  spec.restitution.value = 0.95;
  spec.friction.value = 0.1;
  model::StackSpec paired = spec;
  paired.restitution.set("steel", "brass", 0.5);
  paired.friction.set("steel", "brass", 0.6);
  run_both_engines(root / "diagonal", spec);
  run_both_engines(root / "paired", paired);
  const auto c = postproc::compare_runs((root / "paired" / "liggghts").string(), (root / "paired" / "refsim").string());
  EXPECT_TRUE(c.mismatches.empty()) << c.mismatches.front();
  EXPECT_LE(c.worst(), postproc::kDefaultTolerance) << c.largest().quantity;
  const double diagonal = postproc::reduce_case((root / "diagonal" / "liggghts").string()).output_fraction;
  const double pairs = postproc::reduce_case((root / "paired" / "liggghts").string()).output_fraction;
  EXPECT_GT(std::abs(pairs - diagonal), 0.05 * diagonal) << "the pair's coefficients changed nothing";
}

// Runs that stop at the blow's end (#32, stop = blow_end). LIGGGHTS's deck judges each dump frame
// as refsim does, and both stop at the same frame. Reduce judges the dumps itself: it finds the blow
// ended at the last frame, or the cap reached with the blow not ended (censored). The deck's stop
// runs one dump interval at a time, and that changes no bit of LIGGGHTS's trajectory: its dump and
// series equal, byte for byte, those of a plain run (stop = duration) of the same length and
// cadences.
namespace {

struct BlowEndCase {
  const char* name;
  model::StackSpec spec;
  bool ends;  // before the cap
  // The blow ends before the run stops: a course to the striker through other spheres (which the
  // blow's end leaves out, the run's stop not) outlasts it (model::BlowEnd).
  bool ends_before_stop = false;
};

model::StackSpec blow_end_spec(int blocks, std::vector<int> rows, std::vector<std::string> materials, model::Boundary bottom,
                               double cap = model::kBlowEndCapDurations, model::Geometry g = model::Geometry::strip) {
  model::StackSpec s;
  s.geometry = g;
  s.blocks = blocks;
  s.block_rows = std::move(rows);
  s.materials = std::move(materials);
  s.bottom = bottom;
  s.stop = model::StopRule::blow_end;
  s.cap_durations = cap;
  return s;
}

// `s` with `change` made to it.
template <class Change>
model::StackSpec changed(model::StackSpec s, Change change) {
  change(s);
  return s;
}

long steps_run(const fs::path& dir) {
  const auto c = formats::Case::open(dir.string());
  return formats::read_run_record(dir, c.files()).record->at("steps").get<long>();
}

void PrintTo(const BlowEndCase& c, std::ostream* os) { *os << c.name; }

class StopAtBlowEnd : public ::testing::TestWithParam<BlowEndCase> {};

TEST_P(StopAtBlowEnd, BothEnginesStopAtTheFrameWhereTheBlowEndedAndTheDeckChangesNoBit) {
  const auto& param = GetParam();
  const auto root = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / (std::string("blow_end_") + param.name));
  fs::remove_all(root);
  run_both_engines(root, param.spec);
  if (HasFatalFailure()) return;
  const auto res = model::resolve(model::Stack::build(param.spec));
  const long steps = steps_run(root / "liggghts");
  EXPECT_EQ(steps_run(root / "refsim"), steps);
  postproc::ReduceOptions quiet;
  quiet.write_files = false;
  for (const auto* engine : {"liggghts", "refsim"}) {
    const auto r = postproc::reduce_case((root / engine).string(), quiet);
    for (const auto& w : r.warnings) EXPECT_EQ(w.find("otherwise than reduce does"), std::string::npos) << engine << ": " << w;
    if (param.ends) {
      ASSERT_TRUE(r.blow_end_time) << engine << ": " << r.blow_not_ended;
      if (param.ends_before_stop) {
        EXPECT_LT(*r.blow_end_time, static_cast<double>(steps) * res.dt) << engine;
        EXPECT_EQ(r.frames_after_blow_end, (steps - std::llround(*r.blow_end_time / res.dt)) / res.dump_every) << engine;
        std::printf("%s: the blow ended at step %ld\n", engine, std::lround(*r.blow_end_time / res.dt));
      } else {
        EXPECT_EQ(*r.blow_end_time, static_cast<double>(steps) * res.dt) << engine;
      }
      EXPECT_LT(steps, res.steps) << engine;
    } else {
      EXPECT_FALSE(r.blow_end_time) << engine;
      EXPECT_EQ(steps, res.steps) << engine << ": a censored run goes to its cap";
      EXPECT_FALSE(r.blow_not_ended.empty()) << engine;
    }
  }
  std::printf("%s: both engines stopped at step %ld of the cap's %ld (%.3g automatic durations), the blow %s\n",
              param.name, steps, res.steps, static_cast<double>(steps) / static_cast<double>(res.steps) * param.spec.cap_durations,
              param.ends ? "ended" : "not ended (censored)");
  const auto c = postproc::compare_runs((root / "liggghts").string(), (root / "refsim").string());
  EXPECT_TRUE(c.mismatches.empty()) << c.mismatches.front();
  EXPECT_LE(c.worst(), postproc::kDefaultTolerance) << c.largest().quantity;

  auto plain = param.spec;
  plain.stop = model::StopRule::duration;
  plain.cap_durations = model::kBlowEndCapDurations;
  plain.duration = static_cast<double>(steps) * res.dt;
  plain.dump_every = res.dump_every;
  plain.series_every = res.series_every;
  ASSERT_EQ(model::resolve(model::Stack::build(plain)).steps, steps);
  generator::GenerateOptions o;
  o.output = root / "plain";
  generator::generate({{"plain", plain}}, o);
  runner::RunOptions r;
  ASSERT_EQ(runner::run_cases({o.output.string()}, r).front().status, runner::RunStatus::done);
  const auto files = formats::Case::open((root / "plain").string()).files();
  for (const auto& file : {files.dump, files.series}) {
    const auto stopped = read_bytes(root / "liggghts" / file), whole = read_bytes(root / "plain" / file);
    const auto at = std::mismatch(stopped.begin(), stopped.end(), whole.begin(), whole.end()).first - stopped.begin();
    EXPECT_TRUE(stopped == whole) << file << ": " << stopped.size() << " and " << whole.size() << " bytes, first differing at byte "
                                  << at;
  }
}

// A run that stopped where reduce judges the blow had not ended (an engine judging a frame within
// round-off otherwise, as several MPI ranks may): reduce says so, and does not take the blow as
// ended; the measures are read as reduce judges them. The record of such a run is made here from a
// whole run, cut at its third frame, with its digests taken anew (what run.json would hold). A
// template of the user's that skips the judging loop is refused: its run executed too few of the
// case's commands.
TEST(StopAtBlowEndCheck, ARunThatStopsElsewhereIsSaidAndItsBlowIsNotTakenAsEnded) {
  const auto root = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / "blow_end_elsewhere");
  fs::remove_all(root);
  fs::create_directories(root);
  generator::GenerateOptions o;
  o.output = root / "case";
  generator::generate({{"case", blow_end_spec(2, {4, 4}, {"steel"}, model::Boundary::wall)}}, o);
  ASSERT_EQ(runner::run_cases({o.output.string()}, {}).front().status, runner::RunStatus::done);
  const auto c = formats::Case::open(o.output.string());
  const long every = c.derived().dump_every, stop = 2 * every;
  auto dump = formats::read_file(c.path(c.files().dump));
  dump.resize(dump.find(fmt::format("ITEM: TIMESTEP\n{}\n", stop + every)));
  formats::write_file_atomically(c.path(c.files().dump), dump);
  std::istringstream series(formats::read_file(c.path(c.files().series)));
  std::string kept, line;
  while (std::getline(series, line)) {
    if (line[0] == '#' || std::stol(line.substr(0, line.find(' '))) <= stop) kept += line + "\n";
  }
  formats::write_file_atomically(c.path(c.files().series), kept);
  auto record = nlohmann::json::parse(formats::read_file(c.path(c.files().run_record)));
  record["steps"] = stop;
  record["digests"] = formats::run_digests(c);
  c.write_run_record(record);
  postproc::ReduceOptions quiet;
  quiet.write_files = false;
  const auto r = postproc::reduce_case(o.output.string(), quiet);
  EXPECT_FALSE(r.blow_end_time);
  const bool said = std::any_of(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
    return w.find("before its cap") != std::string::npos && w.find("otherwise than reduce does") != std::string::npos;
  });
  EXPECT_TRUE(said) << (r.warnings.empty() ? std::string("no warning") : r.warnings.front());

  std::string text(generator::default_deck_template());
  text.replace(text.rfind("{{run}}"), 7,
               "run             {{dump_every}} pre no post no\njump            SELF skipped\n{{run}}\nlabel           skipped");
  std::ofstream(root / "deck.tmpl") << text;
  o.output = root / "skipping";
  o.deck_template_path = (root / "deck.tmpl").string();
  generator::generate({{"case", blow_end_spec(2, {4, 4}, {"steel"}, model::Boundary::wall)}}, o);
  const auto skipping = runner::run_cases({o.output.string()}, {}).front();
  EXPECT_EQ(skipping.status, runner::RunStatus::failed);
  EXPECT_NE(skipping.message.find("the deck never ran 'compute gs_pz"), std::string::npos) << skipping.message;
}

// Two steel blocks that yield (LIGGGHTS's thornton_ning) struck at 1 m/s, between side walls over a
// wall: the run ends its blow though spheres of the bottom row still overlap the wall at that frame
// (their dents: the wall carries no force on them), where an overlap kept every yielding stack's
// blow open to its cap (model::blow_end_reads_wall_force).
model::StackSpec yielding_on_wall_spec() {
  auto s = blow_end_spec(2, {4, 4}, {"steel"}, model::Boundary::wall);
  s.bottom_radius = 2e-3;
  s.sides = model::Boundary::wall;  // confined, as a design space's stacks are
  s.normal_model = model::NormalModel::thornton_ning;
  return s;
}

// How many spheres overlap the bottom wall (z < r) in a case's last dump frame.
int overlapping_wall_at_end(const fs::path& dir) {
  const auto c = formats::Case::open(dir.string());
  formats::TextDumpReader reader(c.path(c.files().dump).string());
  formats::DumpFrame f, last;
  while (reader.next(f)) last = f;
  const int z = last.column("z"), r = last.column("radius");
  int n = 0;
  for (long i = 0; i < last.atoms; ++i) n += last.at(i, z) < last.at(i, r) ? 1 : 0;
  return n;
}

TEST(StopAtBlowEndYield, AYieldedStackRestingDentedOnTheWallHasEndedItsBlow) {
  const auto root = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / "blow_end_dented");
  fs::remove_all(root);
  run_both_engines(root, yielding_on_wall_spec());
  if (HasFatalFailure()) return;
  const auto res = model::resolve(model::Stack::build(yielding_on_wall_spec()));
  EXPECT_EQ(steps_run(root / "liggghts"), steps_run(root / "refsim"));
  EXPECT_LT(steps_run(root / "liggghts"), res.steps);
  for (const auto* engine : {"liggghts", "refsim"}) {
    const int dented = overlapping_wall_at_end(root / engine);
    std::printf("%s: %d spheres overlap the wall at the blow's end (step %ld)\n", engine, dented, steps_run(root / engine));
    EXPECT_GT(dented, 0) << engine;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, StopAtBlowEnd,
    ::testing::Values(
        BlowEndCase{"wall", blow_end_spec(2, {4, 4}, {"steel"}, model::Boundary::wall), true},
        BlowEndCase{"yielding_wall", yielding_on_wall_spec(), true},
        BlowEndCase{"free", blow_end_spec(2, {4, 4}, {"steel"}, model::Boundary::free_surface), true},
        // A soft cavity over a wall (the hold is two arrivals). Its blow ends 1,680 steps (0.1 ms)
        // before the run stops: a course to the striker through other spheres holds the stop back.
        BlowEndCase{"sandwich_wall", blow_end_spec(3, {8, 8, 8}, {"steel", "teflon", "steel"}, model::Boundary::wall), true,
                    true},
        // An off-centre blow over a wall: the striker one top-sphere diameter right of the centre.
        BlowEndCase{"off_centre_wall", changed(blow_end_spec(2, {4, 4}, {"steel"}, model::Boundary::wall),
                                               [](auto& s) {
                                                 s.top_columns = 4;
                                                 s.impact_offset = 1;
                                               }),
                    true},
        // A 3D nest over a wall: the footprint in y as well as x.
        // One steel block at 2 m/s: its rebounding top spheres hit the striker again at 1.8 ms, after
        // the momentum over the footprint had turned (the blow ends for the striker too, #47).
        BlowEndCase{"striker_hit_again", changed(blow_end_spec(1, {8}, {"steel"}, model::Boundary::wall),
                                                 [](auto& s) {
                                                   s.bottom_radius = 8e-3;
                                                   s.striker_speed = 2.0;
                                                 }),
                    true},
        BlowEndCase{"nest_wall", blow_end_spec(2, {3, 3}, {"steel"}, model::Boundary::wall, model::kBlowEndCapDurations,
                                               model::Geometry::nested3d),
                    true},
        // On a sprung plate (twice the stack's mass, its mount at about 560 Hz): the decks' judge
        // takes the momentum relative to the plate and leaves the plate's body out.
        BlowEndCase{"sprung_plate", changed(blow_end_spec(2, {4, 4}, {"steel"}, model::Boundary::wall),
                                            [](auto& s) {
                                              s.plate_mass = 0.02;
                                              s.mount_stiffness = 1e5;
                                            }),
                    true},
        // Steel on Teflon with a free bottom, capped at 2 automatic durations: a sphere is still on
        // course to hit the output sphere at the cap (measured with refsim).
        BlowEndCase{"censored", blow_end_spec(2, {3, 3}, {"steel", "teflon"}, model::Boundary::free_surface, 2.0), false}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
