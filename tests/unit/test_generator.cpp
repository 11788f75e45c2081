// Template rendering and case writing: every placeholder filled, unknown ones refused, and a
// case directory is written whole or not at all.
#include <granstack/formats/case.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/generator/template.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

using namespace granstack;
namespace fs = std::filesystem;

namespace {

TEST(Template, FillsPlaceholdersAndRefusesUnknownOnes) {
  generator::TemplateVars vars{{"dt", "1e-07"}, {"steps", "520"}};
  EXPECT_EQ(generator::render_template("timestep {{dt}}\nrun {{ steps }}\n", vars, "t"), "timestep 1e-07\nrun 520\n");
  try {
    generator::render_template("a\nb {{dump_every}}\n", vars, "my.tmpl");
    FAIL();
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("my.tmpl:2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'{{dump_every}}'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("dt, steps"), std::string::npos) << msg;
  }
  EXPECT_THROW(generator::render_template("run {{steps", vars, "t"), std::runtime_error);
}

TEST(Template, DefaultDeckHasTheRequiredCommandsAndAvoidsThePitfalls) {
  for (auto bottom : {model::Boundary::free_surface, model::Boundary::wall}) {
    model::StackSpec s;
    s.blocks = 2;
    s.materials = {"steel", "teflon"};
    s.bottom = bottom;
    s.sides = bottom;
    s.gravity = bottom == model::Boundary::wall ? 9.81 : 0.0;
    const auto stack = model::Stack::build(s);
    const auto files = generator::case_files(stack);
    const auto deck = generator::render_template(generator::default_deck_template(),
                                                 generator::deck_variables(stack, model::resolve(stack), files, "t"),
                                                 "default");
    EXPECT_EQ(deck.find("{{"), std::string::npos);
    // docs/liggghts.md sections 0 and 11.
    for (const char* required :
         {"atom_style      granular", "newton          off", "communicate     single vel yes", "units           si",
          "hard_particles  yes", "neigh_modify    delay 0", "pair_style      gran model hertz tangential history",
          "fix             integr all nve/sphere", "thermo_modify   lost error", "sort id", "%.17g",
          "group           block2 type 2", "ke_trans_block2 ke_rot_block2"}) {
      EXPECT_NE(deck.find(required), std::string::npos) << required;
    }
    // Types: two blocks, the striker, and the wall when there is one.
    EXPECT_NE(deck.find(bottom == model::Boundary::wall ? "peratomtypepair 4 " : "peratomtypepair 3 "), std::string::npos);
    EXPECT_EQ(deck.find(" multi"), std::string::npos);
    EXPECT_EQ(deck.find("comm_modify"), std::string::npos);
    if (bottom == model::Boundary::wall) {
      EXPECT_NE(deck.find("wall/gran model hertz tangential history primitive type 4 zplane 0"), std::string::npos);
      EXPECT_NE(deck.find("xplane -0.004"), std::string::npos);  // C R_1 = 2 x 2 mm
      EXPECT_NE(deck.find("fix             gravity all gravity 9.81 vector 0 0 -1"), std::string::npos);
    }
  }
}

class CaseWriter : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("granstack_writer_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

std::vector<generator::CaseSpec> one_case(int blocks) {
  generator::CaseSpec c;
  c.spec.blocks = blocks;
  return {c};
}

// A case opened once (formats/case.hpp): the derived values typed as the deck runs them (the same
// as its spec gives), and one rule for its run record: none, a status, or damaged (unreadable,
// or without a status) with the reason, never taken for done.
TEST_F(CaseWriter, ACaseOpensWithItsDerivedValuesAndOneRuleForItsRunRecord) {
  generator::GenerateOptions o;
  o.output = root_ / "case";
  generator::generate(one_case(2), o);
  const auto c = formats::Case::open(o.output.string());
  const auto res = c.resolution();
  EXPECT_EQ(c.derived().dt, res.dt);
  EXPECT_EQ(c.derived().steps, res.steps);
  EXPECT_EQ(c.derived().dump_every, res.dump_every);
  EXPECT_EQ(c.derived().frames(), res.steps / res.dump_every + 1);
  EXPECT_EQ(c.derived().duration, res.duration);
  EXPECT_NO_THROW(c.check_derived());
  EXPECT_EQ(c.stack().spheres().size(), static_cast<std::size_t>(model::sphere_count(c.spec())));

  EXPECT_FALSE(c.run_record().exists());
  const auto record = o.output / "run.json";
  for (const char* damaged : {"{\"status\": \"do", "{\"engine\": \"liggghts\"}", "[1, 2]", "{\"status\": 3}"}) {
    std::ofstream(record) << damaged;
    const auto r = c.run_record();
    EXPECT_EQ(r.status, "damaged") << damaged;
    EXPECT_FALSE(r.done());
    EXPECT_NE(r.error.find("run.json cannot be read"), std::string::npos) << r.error;
  }
  c.write_run_record({{"status", "failed"}, {"error", "LIGGGHTS stopped\nat step 7"}});
  EXPECT_EQ(c.run_record().status, "failed");
  EXPECT_EQ(c.run_record().error_line(), "LIGGGHTS stopped");
  c.write_run_record({{"status", "done"}});
  EXPECT_TRUE(c.run_record().done());
}

TEST_F(CaseWriter, WritesACaseAndRefusesToOverwriteWithoutForce) {
  generator::GenerateOptions o;
  o.output = root_ / "case";
  o.command_line = {"granstack", "generate"};
  const auto r = generator::generate(one_case(1), o);
  ASSERT_EQ(r.case_dirs.size(), 1u);
  for (const char* f : {"manifest.json", "data.stack", "in.stack"}) EXPECT_TRUE(fs::exists(o.output / f)) << f;
  const auto m = formats::read_manifest(o.output.string());
  EXPECT_EQ(m.case_name, "case");
  EXPECT_EQ(m.spec.blocks, 1);
  EXPECT_EQ(m.derived->at("sphere_count"), 17);
  EXPECT_EQ(m.layout->at("output_sphere_id"), 17);
  EXPECT_EQ(m.command_line, o.command_line);

  std::ofstream(o.output / "precious.txt") << "a result";
  EXPECT_THROW(generator::generate(one_case(2), o), generator::ExistsError);
  EXPECT_TRUE(fs::exists(o.output / "precious.txt"));
  EXPECT_EQ(formats::read_manifest(o.output.string()).spec.blocks, 1);
  o.force = true;
  // Not even with force: the user's file is named and kept.
  EXPECT_THROW(generator::generate(one_case(2), o), generator::RefusedError);
  EXPECT_TRUE(fs::exists(o.output / "precious.txt"));
  fs::remove(o.output / "precious.txt");
  generator::generate(one_case(2), o);
  EXPECT_EQ(formats::read_manifest(o.output.string()).spec.blocks, 2);
  // Nothing temporary is left beside it.
  for (const auto& e : fs::directory_iterator(root_)) EXPECT_EQ(e.path().filename(), "case");
}

TEST_F(CaseWriter, ABadTemplateWritesNothing) {
  const auto tmpl = fs::temp_directory_path() / ("granstack_bad_" + std::to_string(::getpid()) + ".tmpl");
  std::ofstream(tmpl) << "run {{no_such_value}}\n";
  generator::GenerateOptions o;
  o.output = root_ / "case";
  o.deck_template_path = tmpl.string();
  EXPECT_THROW(generator::generate(one_case(1), o), std::runtime_error);
  EXPECT_FALSE(fs::exists(root_ / "case"));
  fs::remove(tmpl);
}

// A template of the user's without the plate's placeholders would hold a protected plate still (no
// {{plate}}: its motion) or dump its body with the spheres (no {{particles}}): refused, naming
// both, with nothing written; granstack's own template has both.
TEST_F(CaseWriter, APlateNeedsATemplateThatMovesItAndLeavesItsBodyOutOfTheDump) {
  auto own = std::string(generator::default_deck_template());
  ASSERT_NE(own.find("{{plate}}"), std::string::npos);
  const auto at = own.find("{{particles}}");
  ASSERT_NE(at, std::string::npos);
  own.replace(at, 13, "all");
  const auto tmpl = fs::temp_directory_path() / ("granstack_plate_" + std::to_string(::getpid()) + ".tmpl");
  std::ofstream(tmpl) << own;
  model::StackSpec spec;
  spec.blocks = 1;
  spec.bottom = model::Boundary::wall;
  spec.plate_mass = 0.01;
  generator::GenerateOptions o;
  o.output = root_ / "case";
  o.deck_template_path = tmpl.string();
  try {
    generator::generate({{"case", spec}}, o);
    ADD_FAILURE() << "a template that dumps the plate's body was taken";
  } catch (const model::SpecError& e) {
    EXPECT_NE(std::string(e.what()).find("lacks {{plate}} (after fix nve/sphere: the plate's motion) or {{particles}}"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(root_ / "case"));
  fs::remove(tmpl);
  o.deck_template_path.reset();
  generator::generate({{"case", spec}}, o);
  EXPECT_TRUE(fs::exists(root_ / "case" / "in.stack"));
}

TEST_F(CaseWriter, ASweepWritesOneDirectoryPerCaseAndAnIndex) {
  generator::Sweep sweep;
  sweep.axes = {{"blocks", {1, 2}}, {"restitution", {1.0, 0.95}}};
  generator::GenerateOptions o;
  o.output = root_ / "sweep";
  const auto r = generator::generate(generator::expand(sweep), o);
  EXPECT_TRUE(r.sweep);
  const auto dirs = formats::expand_case_dirs({o.output.string()});
  ASSERT_EQ(dirs.size(), 4u);
  EXPECT_EQ(fs::path(dirs[3]).filename(), "nb2_e0.95");
  EXPECT_EQ(formats::read_manifest(dirs[3]).spec.restitution.value, 0.95);
  EXPECT_THROW(formats::expand_case_dirs({root_.string()}), formats::FormatError);
}

// The deck refsim checks against is rebuilt from the manifest as written to disk and read back:
// for every kind of case it must be the deck generate wrote, byte for byte, so that nothing the
// deck depends on is missing from the manifest (and refsim runs what LIGGGHTS runs).
TEST_F(CaseWriter, TheManifestAloneGivesTheDeckBackByteForByte) {
  std::vector<model::StackSpec> specs(4);
  specs[1].materials = {"steel", "teflon", "steel", "teflon"};
  specs[1].restitution.set("steel", "teflon", 0.8);
  specs[2].bottom = specs[2].sides = model::Boundary::wall;
  specs[2].gravity = 9.80665;
  specs[2].friction.value = 0.3;
  specs[2].dump_format = model::DumpFormat::binary;
  specs[3].custom_materials.push_back({"glass", 2500, 6.3e10, 0.22, {}});
  specs[3].materials = {"glass"};
  specs[3].dump_files = model::DumpFiles::per_step;
  specs[3].dt = 2e-8;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    generator::GenerateOptions o;
    o.output = root_ / ("case" + std::to_string(i));
    generator::generate({{"c", specs[i]}}, o);
    const auto m = formats::read_manifest(o.output.string());
    std::ifstream deck(o.output / "in.stack", std::ios::binary);
    const std::string written((std::istreambuf_iterator<char>(deck)), std::istreambuf_iterator<char>());
    EXPECT_EQ(generator::default_deck(m), written) << i;
  }
}

}  // namespace
