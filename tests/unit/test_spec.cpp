// Spec validation (every field's error names the field and its range), spec files, flags and
// sweep expansion.
#include <granstack/generator/spec_input.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/model/spec_fields.hpp>

#include <granstack/model/yield.hpp>
#include <granstack/model/stack.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <tuple>
#include <vector>

using namespace granstack;
using model::StackSpec;

namespace {

struct BadCase {
  const char* name;
  std::function<void(StackSpec&)> spoil;
  const char* field;
  const char* words;  // a fragment of the message: the allowed range or the fix
};

class SpecValidation : public ::testing::TestWithParam<BadCase> {};

TEST_P(SpecValidation, NamesTheFieldAndTheAllowedRange) {
  StackSpec s;
  GetParam().spoil(s);
  const auto issues = model::validate(s);
  ASSERT_FALSE(issues.empty());
  bool found = false;
  for (const auto& i : issues) {
    if (i.field == GetParam().field && i.message.find(GetParam().words) != std::string::npos) found = true;
  }
  EXPECT_TRUE(found) << "first issue: " << issues.front().field << ": " << issues.front().message;
  EXPECT_THROW(model::require_valid(s), model::SpecError);
}

const BadCase kBadCases[] = {
    {"blocks_zero", [](StackSpec& s) { s.blocks = 0; }, "blocks", "from 1 to 16"},
    {"rows_zero", [](StackSpec& s) { s.rows = 0; }, "rows", "from 1 to 4096"},
    {"odd_columns", [](StackSpec& s) { s.top_columns = 3; }, "top_columns", "even"},
    {"negative_radius", [](StackSpec& s) { s.bottom_radius = -1e-3; }, "bottom_radius", "in [1e-07, 1] m"},
    {"nan_radius", [](StackSpec& s) { s.bottom_radius = std::nan(""); }, "bottom_radius", "in [1e-07, 1] m"},
    {"huge_radius", [](StackSpec& s) { s.bottom_radius = 1e308; }, "bottom_radius", "in [1e-07, 1] m"},
    {"tiny_radius", [](StackSpec& s) { s.bottom_radius = 1e-300; }, "bottom_radius", "in [1e-07, 1] m"},
    {"top_radius", [](StackSpec& s) { s.blocks = 12; }, "bottom_radius", "the top spheres would be 2.048 m"},
    {"ratio_zero", [](StackSpec& s) { s.radius_ratio = 0; }, "radius_ratio", "whole number"},
    {"too_many_spheres", [](StackSpec& s) { s.blocks = 16; s.top_columns = 64; s.bottom_radius = 1e-6; }, "blocks", "more than"},
    {"unknown_material", [](StackSpec& s) { s.materials = {"unobtainium"}; }, "materials", "unknown material 'unobtainium' (known: aluminium, aluminium_7075, brass"},
    {"material_count", [](StackSpec& s) { s.materials = {"steel", "teflon"}; }, "materials", "one per block"},
    {"restitution_zero", [](StackSpec& s) { s.restitution.value = 0.0; }, "restitution", "(0.05, 1]"},
    {"restitution_above_one", [](StackSpec& s) { s.restitution.value = 1.2; }, "restitution", "(0.05, 1]"},
    {"restitution_pair", [](StackSpec& s) { s.restitution.set("steel", "teflon", 0.01); },
     "restitution_pairs.\"steel:teflon\"", "(0.05, 1]"},
    {"restitution_pair_material", [](StackSpec& s) { s.restitution.set("steel", "granite", 0.5); },
     "restitution_pairs.\"granite:steel\"", "unknown material"},
    {"friction_negative", [](StackSpec& s) { s.friction.value = -0.1; }, "friction", "in [0, 10]"},
    {"friction_huge", [](StackSpec& s) { s.friction.value = 1e300; }, "friction", "in [0, 10]"},
    {"speed_zero", [](StackSpec& s) { s.striker_speed = 0.0; }, "striker_speed", "> 0"},
    {"gravity_negative", [](StackSpec& s) { s.gravity = -9.8; }, "gravity", "in [0, 1000]"},
    {"gravity_huge", [](StackSpec& s) { s.gravity = 1e30; }, "gravity", "in [0, 1000]"},
    {"dt_negative", [](StackSpec& s) { s.dt = -1.0; }, "dt", "> 0"},
    {"dt_longer_than_run", [](StackSpec& s) { s.dt = 1e-3; s.duration = 1e-4; }, "dt", "smaller than the duration"},
    {"duration_zero", [](StackSpec& s) { s.duration = 0.0; }, "duration", "> 0"},
    {"dump_every_zero", [](StackSpec& s) { s.dump_every = 0; }, "dump_every", ">= 1"},
    {"series_every_zero", [](StackSpec& s) { s.series_every = 0; }, "series_every", ">= 1"},
    {"wall_material", [](StackSpec& s) { s.wall_material = "wood"; }, "wall_material", "unknown material"},
    {"striker_material", [](StackSpec& s) { s.striker_material = "wood"; }, "striker_material", "unknown material"},
    {"striker_small", [](StackSpec& s) { s.striker_radius_ratio = 0.5; }, "striker_radius_ratio", "in [1, 16]"},
    {"striker_nan", [](StackSpec& s) { s.striker_radius_ratio = std::nan(""); }, "striker_radius_ratio", "in [1, 16]"},
    {"striker_at_walls", [](StackSpec& s) { s.sides = granstack::model::Boundary::wall; s.striker_radius_ratio = 2.0; },
     "striker_radius_ratio", "touch the side walls"},
    {"material_density", [](StackSpec& s) { s.custom_materials.push_back({"foam", 0.0, 1e6, 0.3, {}}); },
     "custom_materials.foam.density", "in [1, 100000] kg/m^3"},
    {"material_builtin", [](StackSpec& s) { s.custom_materials.push_back({"steel", 1.0, 1e3, 0.3, {}}); },
     "custom_materials.steel", "built-in material and cannot be redefined"},
    {"pair_absent_material", [](StackSpec& s) { s.restitution.set("steel", "teflon", 0.8); },
     "restitution_pairs.\"steel:teflon\"", "names a material this stack does not use (it uses: steel)"},
    {"friction_pair_absent_material", [](StackSpec& s) { s.friction.set("teflon", "teflon", 0.3); },
     "friction_pairs.\"teflon:teflon\"", "does not use"},
    {"material_modulus", [](StackSpec& s) { s.custom_materials.push_back({"foam", 100.0, -1.0, 0.3, {}}); },
     "custom_materials.foam.youngs_modulus", "in [1000, 1e+13] Pa"},
    {"material_poisson", [](StackSpec& s) { s.custom_materials.push_back({"foam", 100.0, 1e6, 0.5, {}}); },
     "custom_materials.foam.poisson_ratio", "[0, 0.5)"},
    {"material_yield", [](StackSpec& s) { s.custom_materials.push_back({"foam", 100.0, 1e6, 0.3, 2e6}); },
     "custom_materials.foam.yield_strength", "positive and below its Young's modulus"},
    {"material_name", [](StackSpec& s) { s.custom_materials.push_back({"Foam!", 100.0, 1e6, 0.3, {}}); },
     "custom_materials.Foam!", "lower-case"},
    {"rolling_friction_without_model", [](StackSpec& s) { s.rolling_friction.value = 0.1; }, "rolling_friction",
     "rolling_model = epsd2 or cdt only"},
    {"rolling_friction_range", [](StackSpec& s) { s.rolling_model = model::RollingModel::epsd2; s.rolling_friction.value = 2.0; },
     "rolling_friction", "in [0, 1]"},
    {"rolling_friction_pair", [](StackSpec& s) { s.rolling_model = model::RollingModel::epsd2; s.rolling_friction.set("steel", "steel", -1.0); },
     "rolling_friction_pairs.\"steel:steel\"", "in [0, 1]"},
    {"characteristic_velocity_with_hertz", [](StackSpec& s) { s.characteristic_velocity = 1.0; }, "characteristic_velocity",
     "normal_model = hooke only"},
    {"characteristic_velocity_slow", [](StackSpec& s) { s.normal_model = model::NormalModel::hooke; s.characteristic_velocity = 1e-3; },
     "characteristic_velocity", "at least 0.01 m/s"},
    {"plate_without_wall", [](StackSpec& s) { s.plate_mass = 0.01; }, "plate_mass", "give it with bottom = 'wall'"},
    {"plate_negative", [](StackSpec& s) { s.bottom = model::Boundary::wall; s.plate_mass = -1.0; }, "plate_mass",
     "in [0, 1e+12] (kg; 0 is the rigid wall)"},
    {"plate_nan", [](StackSpec& s) { s.bottom = model::Boundary::wall; s.plate_mass = std::nan(""); }, "plate_mass", "in [0, 1e+12]"},
    {"mount_without_plate", [](StackSpec& s) { s.bottom = model::Boundary::wall; s.mount_stiffness = 1e6; }, "mount_stiffness",
     "give it with plate_mass > 0"},
    {"mount_damping_negative", [](StackSpec& s) { s.bottom = model::Boundary::wall; s.plate_mass = 1.0; s.mount_damping = -1.0; },
     "mount_damping", "in [0, 1e+12] (N s/m)"},
    {"plate_with_gravity", [](StackSpec& s) { s.bottom = model::Boundary::wall; s.plate_mass = 1.0; s.gravity = 9.8; }, "plate_mass",
     "use gravity 0 with a plate"},
};

INSTANTIATE_TEST_SUITE_P(Fields, SpecValidation, ::testing::ValuesIn(kBadCases),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(SpecValidation, TheDefaultIsTheStudysStackAndValid) {
  StackSpec s;
  EXPECT_TRUE(model::validate(s).empty());
  EXPECT_EQ(s.blocks, 4);
  EXPECT_EQ(s.rows, 8);
  EXPECT_EQ(s.top_columns, 2);
  EXPECT_EQ(s.bottom_radius, 1e-3);
  EXPECT_EQ(s.striker_speed, 1.0);
  EXPECT_EQ(s.restitution.value, 1.0);
  EXPECT_EQ(s.friction.value, 0.0);
  EXPECT_EQ(model::sphere_count(s), 241);
}

TEST(SpecInput, TomlFileWithSweepsPairsAndCustomMaterials) {
  const auto raw = generator::parse_spec_toml(R"(
blocks = [1, 2, 3]
restitution = [1.0, 0.9]
materials = ["steel", "rubbery"]
friction = 0.25
striker_speed = 2
bottom = "wall"
dt = "auto"
duration = 1e-4
[restitution_pairs]
"steel:rubbery" = 0.8
[custom_materials.rubbery]
density = 1100
youngs_modulus = 1e7
poisson_ratio = 0.45
)",
                                              "test.toml");
  auto sweep = generator::build_sweep(raw);
  ASSERT_EQ(sweep.axes.size(), 2u);
  EXPECT_EQ(sweep.base.friction.value, 0.25);
  EXPECT_EQ(sweep.base.striker_speed, 2.0);
  EXPECT_EQ(sweep.base.bottom, model::Boundary::wall);
  EXPECT_FALSE(sweep.base.dt.has_value());
  EXPECT_EQ(sweep.base.duration.value(), 1e-4);
  EXPECT_EQ(sweep.base.restitution.get("rubbery", "steel"), 0.8);
  ASSERT_EQ(sweep.base.custom_materials.size(), 1u);
  EXPECT_EQ(sweep.base.custom_materials[0].youngs_modulus, 1e7);
  // Two materials for one block is invalid, so the expansion names the failing case.
  try {
    generator::expand(sweep);
    FAIL() << "expected a SpecError";
  } catch (const model::SpecError& e) {
    EXPECT_NE(std::string(e.what()).find("nb1_e1"), std::string::npos) << e.what();
  }
  sweep.base.materials = {"steel"};
  sweep.base.wall_material = "rubbery";  // the pair must name materials the stack uses
  const auto cases = generator::expand(sweep);
  ASSERT_EQ(cases.size(), 6u);
  EXPECT_EQ(cases[0].name, "nb1_e1");
  EXPECT_EQ(cases[1].name, "nb1_e0.9");
  EXPECT_EQ(cases[5].name, "nb3_e0.9");
  EXPECT_EQ(cases[5].spec.blocks, 3);
  EXPECT_EQ(cases[5].spec.restitution.value, 0.9);
  EXPECT_EQ(cases[5].spec.restitution.get("steel", "rubbery"), 0.8);  // pairs survive the sweep
}

// The contact model's fields, from a spec file: the choices, hooke's characteristic velocity
// ('auto': the striker speed), rolling friction swept (case names 'mur...') and per pair.
TEST(SpecInput, ContactModelFields) {
  const auto raw = generator::parse_spec_toml(R"(
normal_model = "hooke"
tangential_model = "no_history"
rolling_model = "epsd2"
rolling_friction = [0.05, 0.1]
characteristic_velocity = "auto"
materials = ["steel", "teflon", "steel", "steel"]
[rolling_friction_pairs]
"steel:teflon" = 0.2
)", "models.toml");
  const auto cases = generator::expand(generator::build_sweep(raw));
  ASSERT_EQ(cases.size(), 2u);
  EXPECT_EQ(cases[0].name, "mur0.05");
  EXPECT_EQ(cases[1].name, "mur0.1");
  const auto& s = cases[1].spec;
  EXPECT_EQ(s.normal_model, model::NormalModel::hooke);
  EXPECT_EQ(s.tangential_model, model::TangentialModel::no_history);
  EXPECT_EQ(s.rolling_model, model::RollingModel::epsd2);
  EXPECT_EQ(s.rolling_friction.get("steel", "steel"), 0.1);
  EXPECT_EQ(s.rolling_friction.get("teflon", "steel"), 0.2);
  EXPECT_FALSE(s.characteristic_velocity.has_value());
  EXPECT_EQ(s.contact_model().characteristic_velocity, s.striker_speed);
  EXPECT_EQ(model::liggghts_model_words(s.contact_model()), "model hooke tangential no_history rolling_friction epsd2");
  for (const auto& [field, value, words] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"normal_model", "hertzian", "'hertzian' is not 'hertz', 'hooke', 'thornton' or 'thornton_ning'"},
           {"tangential_model", "none", "'none' is not 'history', 'no_history' or 'mindlin_rescale'"},
           {"rolling_model", "epsd", "'epsd' is not 'off', 'epsd2' or 'cdt'"}}) {
    try {
      generator::build_sweep({{field, {value}}});
      ADD_FAILURE() << field << " = " << value << " was taken";
    } catch (const model::SpecError& e) {
      EXPECT_EQ(e.issues().front().field, field);
      EXPECT_NE(e.issues().front().message.find(words), std::string::npos) << e.issues().front().message;
    }
  }
}

TEST(SpecInput, NumbersSurviveTheTextRoundTripExactly) {
  const auto raw = generator::parse_spec_toml("bottom_radius = 0.1\nstriker_speed = 0.30000000000000004\n", "t");
  const auto sweep = generator::build_sweep(raw);
  EXPECT_EQ(sweep.base.bottom_radius, 0.1);
  EXPECT_EQ(sweep.base.striker_speed, 0.30000000000000004);
}

// The issues a spec's text is refused with, read and built as `generate` does (none where it is taken).
std::vector<model::SpecIssue> refusal(const std::string& toml) {
  try {
    generator::build_sweep(generator::parse_spec_toml(toml, "spec.toml"));
  } catch (const model::SpecError& e) {
    return e.issues();
  }
  return {};
}

TEST(SpecInput, UnknownKeysAndWrongTypesAreNamed) {
  auto issues = refusal("blokcs = 3\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].field, "blokcs");
  EXPECT_NE(issues[0].message.find("did you mean 'blocks'? known fields: geometry, "), std::string::npos)
      << issues[0].message;
  issues = refusal("blocks = 2.5\nbottom = \"floor\"\n");
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].field, "blocks");
  EXPECT_NE(issues[0].message.find("whole number"), std::string::npos);
  EXPECT_EQ(issues[1].field, "bottom");
  EXPECT_THROW(generator::parse_spec_toml("blocks = [1, \n", "spec.toml"), std::runtime_error);
  // A deck addition is a command, or a fix, compute or dump with its style.
  issues = refusal("deck_additions = [\"fix\", \"viscous 0.1\", \"Run\"]\n");
  ASSERT_EQ(issues.size(), 3u);
  EXPECT_EQ(issues[0].field, "deck_additions");
  EXPECT_NE(issues[0].message.find("'fix' is not a command ('displace_atoms') or a fix, compute or dump with its "
                                   "style ('fix viscous')"),
            std::string::npos)
      << issues[0].message;
}

// The elastic-plastic laws: a material without a yield strength, a dashpot, and the yield
// pressure factor out of range or on an elastic law are each refused, naming the field and the fix.
TEST(SpecInput, ElasticPlasticLawsRefuseWhatTheyCannotModel) {
  auto issues = refusal("normal_model = \"thornton\"\nmaterials = [\"glass\"]\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].field, "normal_model");
  EXPECT_NE(issues[0].message.find("'glass' has none"), std::string::npos) << issues[0].message;
  issues = refusal("normal_model = \"thornton_ning\"\nrestitution = 0.9\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].field, "restitution");
  EXPECT_NE(issues[0].message.find("set restitution = 1"), std::string::npos) << issues[0].message;
  issues = refusal("normal_model = \"thornton\"\nyield_pressure_factor = 4\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("outside 1.5..3"), std::string::npos) << issues[0].message;
  issues = refusal("yield_pressure_factor = 2\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("applies to the elastic-plastic laws only"), std::string::npos) << issues[0].message;
  EXPECT_TRUE(refusal("normal_model = \"thornton\"\nyield_pressure_factor = 3\n").empty());
  issues = refusal("normal_model = \"thornton_ning\"\nrolling_model = \"cdt\"\nrolling_friction = 0.1\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].field, "rolling_model");
  // The engines that lack a law refuse it by name (the rows the engines, submit and the decks read).
  model::ContactModel m;
  m.normal = model::NormalModel::thornton;
  EXPECT_NE(model::liggghts_refusal(m).find("nearest law is thornton_ning"), std::string::npos);
  EXPECT_NE(model::lammps_refusal(m).find("no elastic-plastic normal model"), std::string::npos);
  m.normal = model::NormalModel::thornton_ning;
  EXPECT_TRUE(model::liggghts_refusal(m).empty());
  EXPECT_NE(model::lammps_refusal(m).find("no elastic-plastic normal model"), std::string::npos);
}

// thornton_ning's yield ratios give every sphere type the same r * ratio to the bit (so which
// sphere LIGGGHTS calls i does not matter), block 1's pairs their intended p_y, and a stack
// whose small bottom spheres would need a ratio above 1 is refused.
TEST(SpecInput, ThorntonNingYieldRatiosAreOneYieldRadius) {
  model::StackSpec spec;
  spec.normal_model = model::NormalModel::thornton_ning;
  spec.blocks = 4;
  spec.rows = 3;
  spec.bottom = model::Boundary::wall;
  const auto stack = model::Stack::build(spec);
  const auto plan = model::thornton_ning_plan(stack);
  ASSERT_TRUE(plan.refusal.empty()) << plan.refusal;
  for (const auto& s : stack.spheres()) {
    EXPECT_EQ(s.radius * plan.ratio[static_cast<std::size_t>(s.atom_type - 1)], plan.yield_radius) << s.id;
  }
  ASSERT_FALSE(plan.kinds.empty());
  const auto& own = *std::find_if(plan.kinds.begin(), plan.kinds.end(), [](const auto& k) { return k.what == "block 1 - block 1"; });
  EXPECT_NEAR(own.effective / own.intended, 1.0, 1e-12);
  const auto& wall = *std::find_if(plan.kinds.begin(), plan.kinds.end(), [](const auto& k) { return k.what == "block 4 - wall"; });
  EXPECT_GT(wall.effective, 0.0);
  spec.materials = {"teflon"};
  spec.blocks = 8;
  spec.rows = 1;
  const auto deep = model::thornton_ning_plan(model::Stack::build(spec));
  EXPECT_NE(deep.refusal.find("LIGGGHTS takes 0..1"), std::string::npos) << deep.refusal;
}

TEST(SpecInput, FlagListsSplitOnCommasAndDuplicatesAreRejected) {
  EXPECT_EQ(generator::split_list("1, 2,3"), (std::vector<std::string>{"1", "2", "3"}));
  generator::RawSpec raw{{"blocks", {"1", "2", "1"}}};
  EXPECT_THROW(generator::build_sweep(raw), model::SpecError);
  raw = {{"gravity", {"true"}}, {"custom_materials", {"foam:30:1e6:0.1"}}, {"materials", {"foam"}}};
  const auto sweep = generator::build_sweep(raw);
  EXPECT_EQ(sweep.base.gravity, 9.80665);
  EXPECT_EQ(sweep.base.custom_materials.at(0).density, 30.0);
}

}  // namespace

// The field table (model/spec_fields.hpp) is the one list: every field has a unique name and
// flag, a parser, a manifest writer and reader; sweepable ones a setter and a unique case-name
// key; and a spec file naming every field once with a non-default value reads back, through a
// manifest, to the same spec.
TEST(SpecFields, EveryFieldIsReadWrittenAndDocumented) {
  std::set<std::string> names, flags, keys;
  for (const auto& f : model::spec_fields()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_TRUE(flags.insert(f.flag).second) << f.flag;
    EXPECT_TRUE(f.parse && f.save && f.load) << f.name;
    EXPECT_FALSE(f.help.empty() || f.type.empty() || f.default_text.empty()) << f.name;
    if (f.sweepable()) {
      EXPECT_TRUE(f.set_number) << f.name;
      EXPECT_TRUE(keys.insert(f.short_key).second) << f.short_key;
    }
    EXPECT_NE(model::spec_fields_markdown().find("| `" + f.name + "` |"), std::string::npos) << f.name;
  }
  auto every = generator::parse_spec_toml(R"(
geometry = "panels"
panels = 3
impact_panel = 1
separator = "matrix"
matrix_material = "soft"
blocks = 2
block_rows = [3, 5]
top_columns = 4
bottom_radius = 2e-3
radius_ratio = 3
materials = ["steel", "soft"]
restitution = 0.9
friction = 0.2
restitution_pairs = { "steel:soft" = 0.8 }
friction_pairs = { "soft:steel" = 0.3 }
striker_speed = 0.5
striker_radius_ratio = 1.5
striker_material = "teflon"
impact_offset = -1
bottom = "wall"
sides = "free"
wall_material = "steel"
plate_mass = 0.5
mount_stiffness = 1e4
mount_damping = 2
gravity = 0
dt = 1e-8
duration = 1e-4
stop = "duration"
cap_durations = 20
dump_every = 50
series_every = 5
dump_files = "per_step"
dump_format = "binary"
custom_materials = { soft = { density = 1000, youngs_modulus = 1e7, poisson_ratio = 0.4 } }
normal_model = "hooke"
tangential_model = "no_history"
rolling_model = "epsd2"
rolling_friction = 0.1
rolling_friction_pairs = { "steel:steel" = 0.05 }
characteristic_velocity = 2
yield_pressure_factor = 2.5
order_dependent_yield = "accept"
deck_additions = ["fix viscous", "displace_atoms"]
)", "every.toml");
  // Every field but rows, which block_rows replaces (the two are refused together), and stacking,
  // which the container refuses (strip only; read and written below).
  EXPECT_EQ(every.size() + 2, model::spec_fields().size()) << "a field of the table is missing from this test's file";
  EXPECT_EQ(every.count("rows"), 0u);
  // yield_pressure_factor belongs to the elastic-plastic laws, not to this file's hooke: read on its own.
  auto plastic = generator::parse_spec_toml("normal_model = \"thornton\"\nyield_pressure_factor = 2.5\n", "p.toml");
  EXPECT_EQ(generator::build_sweep(plastic).base.yield_pressure_factor, 2.5);
  every.erase("yield_pressure_factor");
  // ... and order_dependent_yield to thornton_ning: read on its own, and refused on another law.
  const auto ning = generator::build_sweep(
      generator::parse_spec_toml("normal_model = \"thornton_ning\"\norder_dependent_yield = \"accept\"\n", "n.toml"));
  EXPECT_EQ(ning.base.order_dependent_yield, model::OrderDependentYield::accept);
  EXPECT_EQ(model::spec_from_json_fields(nlohmann::json::parse(model::spec_json(ning.base).dump())), ning.base);
  EXPECT_THROW(generator::build_sweep(every), model::SpecError);
  every.erase("order_dependent_yield");
  const auto spec = generator::build_sweep(every).base;
  EXPECT_EQ(model::spec_from_json_fields(nlohmann::json::parse(model::spec_json(spec).dump())), spec);
  EXPECT_EQ(spec.impact_panel, 1);
  EXPECT_EQ(spec.separator, model::Separator::matrix);
  EXPECT_EQ(spec.dump_files, model::DumpFiles::per_step);
  EXPECT_EQ(*spec.characteristic_velocity, 2.0);
  EXPECT_EQ(spec.rolling_friction.get("steel", "steel"), 0.05);
  EXPECT_EQ(spec.impact_offset, -1);
  EXPECT_EQ(spec.plate_mass, 0.5);
  EXPECT_EQ(spec.mount_stiffness, 1e4);
  EXPECT_EQ(spec.mount_damping, 2.0);
  EXPECT_EQ(spec.deck_additions, (std::vector<std::string>{"fix viscous", "displace_atoms"}));
  auto nested = generator::build_sweep(generator::parse_spec_toml("radius_ratio = 3\nstacking = \"nested\"\n", "t")).base;
  EXPECT_EQ(nested.stacking, model::Stacking::nested);
  EXPECT_EQ(model::spec_from_json_fields(nlohmann::json::parse(model::spec_json(nested).dump())), nested);
  // A run that stops at the blow's end, with its cap, reads back from the manifest as it was.
  auto stopping = spec;
  stopping.duration.reset();
  stopping.stop = model::StopRule::blow_end;
  stopping.cap_durations = 7.5;
  EXPECT_EQ(model::spec_from_json_fields(nlohmann::json::parse(model::spec_json(stopping).dump())), stopping);
  EXPECT_EQ(spec.block_rows, (std::vector<int>{3, 5}));
}

// Per-block rows and per-interface ratios (the design search's variables): a list of one per
// block and one per interface, each checked, the stack built from them, and refused with rows
// or with the wrong count.
TEST(SpecInput, RowsPerBlockAndRatiosPerInterface) {
  const auto spec = generator::build_sweep(generator::parse_spec_toml(
      "blocks = 3\nblock_rows = [4, 2, 6]\nradius_ratio = [3, 2]\n", "t")).base;
  EXPECT_EQ(spec.radius_ratios, (std::vector<int>{3, 2}));
  EXPECT_EQ(spec.rows_of(3), 6);
  EXPECT_EQ(spec.ratio_below(1), 3);
  EXPECT_EQ(spec.radius_factor(1), 6.0);
  EXPECT_EQ(model::spec_from_json_fields(nlohmann::json::parse(model::spec_json(spec).dump())), spec);
  EXPECT_TRUE(model::spec_json(spec).at("radius_ratio").is_array());
  const auto issue = [](const generator::RawSpec& raw) {
    try {
      generator::expand(generator::build_sweep(raw));
    } catch (const model::SpecError& e) {
      return e.issues().front().field + ": " + e.issues().front().message;
    }
    return std::string("taken");
  };
  EXPECT_EQ(issue({{"rows", {"4"}}, {"block_rows", {"4", "4", "4", "4"}}}), "block_rows: give rows or block_rows, not both");
  EXPECT_NE(issue({{"block_rows", {"4", "4"}}}).find("block_rows: 2 rows listed for 4 blocks"), std::string::npos);
  EXPECT_NE(issue({{"radius_ratio", {"2", "2"}}}).find("radius_ratio: 2 ratios listed for 4 blocks: list one per "
                                                        "interface (3)"),
            std::string::npos);
  EXPECT_NE(issue({{"blocks", {"3"}}, {"radius_ratio", {"2", "17"}}}).find("radius_ratio: 17 must be a whole number"),
            std::string::npos);
  EXPECT_NE(issue({{"blocks", {"2"}}, {"block_rows", {"0", "3"}}}).find("block_rows: 0 must be a whole number from 1"),
            std::string::npos);
  // A sweep of blocks with one list of ratios: the cases it does not fit are named.
  EXPECT_NE(issue({{"blocks", {"3", "4"}}, {"radius_ratio", {"2", "2"}}}).find("(in the sweep case nb4)"),
            std::string::npos);
}
