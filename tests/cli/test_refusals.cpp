// Every contact sub-model an engine cannot run is refused by every command that would run it on
// that engine (run, submit, validate, and design where its search engine is the one), in the
// row's own words and before anything is written. The refusals are read from the tables
// (runner::model_refusal over every row of model/src/contact_models.cpp and the normal laws), so a
// new row, or a new engine, is checked with no new test.
#include "../support/granstack_test.hpp"

#include <granstack/model/contact.hpp>
#include <granstack/runner/engines.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <set>

using namespace granstack;
using namespace granstack::test;

namespace {

// One sub-model row (on the study's defaults otherwise) that one engine refuses.
struct Refused {
  std::string field;    // the spec's field: normal_model, tangential_model or rolling_model
  std::string keyword;  // the row's
  runner::Engine engine;
  bool lammps_rules;    // refsim by LAMMPS's contact rules
  std::string why;      // the row's refusal
  std::vector<std::string> generate_flags;  // a valid case with it
  std::string fixed;    // the design space's [fixed] lines giving it
};

// A case's flags and a space's [fixed] lines for one row: friction (and e < 1, which a viscous
// tangential force needs) where the row is tangential, rolling friction where it is rolling.
void describe(Refused& r) {
  const auto flag = "--" + r.field.substr(0, r.field.find('_')) + "-model";
  r.generate_flags = {flag, r.keyword};
  r.fixed = fmt::format("{} = \"{}\"\n", r.field, r.keyword);
  if (r.field == "tangential_model") {
    r.generate_flags.insert(r.generate_flags.end(), {"--friction", "0.3", "--restitution", "0.9"});
    r.fixed += "friction = 0.3\nrestitution = 0.9\n";
  } else if (r.field == "rolling_model") {
    r.generate_flags.insert(r.generate_flags.end(), {"--friction", "0.3", "--rolling-friction", "0.1"});
    r.fixed += "friction = 0.3\nrolling_friction = 0.1\n";
  }
}

template <typename Model>
void add_refusals(const std::string& field, Model model::ContactModel::*member, std::vector<Refused>& out) {
  for (const auto m : model::all_models<Model>()) {
    model::ContactModel c;
    c.*member = m;
    for (const auto& row : runner::engine_table()) {
      for (const bool lammps_rules : {false, true}) {
        if (lammps_rules && row.engine != runner::Engine::refsim) continue;
        const auto why = runner::model_refusal(row.engine, c, lammps_rules);
        if (why.empty()) continue;
        Refused r{field, std::string(model::to_string(m)), row.engine, lammps_rules, std::string(why), {}, {}};
        describe(r);
        out.push_back(r);
      }
    }
  }
}

std::vector<Refused> every_refusal() {
  std::vector<Refused> out;
  add_refusals("normal_model", &model::ContactModel::normal, out);
  add_refusals("tangential_model", &model::ContactModel::tangential, out);
  add_refusals("rolling_model", &model::ContactModel::rolling, out);
  return out;
}

// A parameter as gtest prints it.
void PrintTo(const Refused& r, std::ostream* os) {
  *os << r.field << " = " << r.keyword << " on " << runner::to_string(r.engine) << (r.lammps_rules ? " by LAMMPS's rules" : "");
}

std::string name_of(const ::testing::TestParamInfo<Refused>& p) {
  return fmt::format("{}_{}{}", p.param.keyword, runner::to_string(p.param.engine), p.param.lammps_rules ? "_lammps_rules" : "");
}

// Every file and folder beneath `dir`, with each file's bytes; not the test's logs of each
// command, nor a case's lock file (which names its last holder: a command takes the case's lock
// before it reads the spec it refuses).
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const auto name = fs::relative(e.path(), dir).string();
    if (name.rfind(".granstack-", 0) == 0 || e.path().filename() == ".granstack.lock") continue;
    out[name] = e.is_regular_file() ? read_bytes(e.path()) : std::string("(folder)");
  }
  return out;
}

class Refusal : public GranstackTest, public ::testing::WithParamInterface<Refused> {
 protected:
  // The command refused with `code`, naming the row's refusal, and the test's folder as it was.
  void expect_refused(const std::vector<std::string>& args, int code) {
    const auto before = contents(dir_);
    const auto r = granstack(args);
    EXPECT_EQ(r.code, code) << fmt::format("{}", fmt::join(args, " ")) << "\n" << r.output;
    expect_contains(r, GetParam().why);
    EXPECT_EQ(contents(dir_), before) << fmt::format("{}", fmt::join(args, " ")) << " wrote or changed files";
  }
};

TEST_P(Refusal, EveryCommandThatWouldRunItRefusesItBeforeWritingAnything) {
  const auto& p = GetParam();
  std::vector<std::string> generate{"generate", "-o", "case", "--blocks", "2", "--rows", "3"};
  generate.insert(generate.end(), p.generate_flags.begin(), p.generate_flags.end());
  ASSERT_EQ(granstack(generate).code, 0);
  const auto engine = runner::to_string(p.engine);
  std::vector<std::string> run{"run", "--engine", engine};
  if (p.lammps_rules) run.insert(run.end(), {"--contact-rules", "lammps"});
  run.push_back("case");
  expect_refused(run, 1);
  // SLURM's tasks run an engine by its own rules (submit has no --contact-rules).
  if (!p.lammps_rules) expect_refused({"submit", "--engine", engine, "case"}, 1);
  // Validate compares it with another engine: LAMMPS's rules are refsim's beside LAMMPS.
  const std::string other = p.engine == runner::Engine::refsim ? (p.lammps_rules ? "lammps" : "liggghts") : "refsim";
  expect_refused({"validate", "--engines", engine + "," + other, "case"}, 1);
  // A design searches on refsim by LIGGGHTS's rules.
  if (p.engine == runner::Engine::refsim && !p.lammps_rules) {
    auto space = small_space("space.toml");
    space.replace(space.find("[fixed]\n"), 8, "[fixed]\n" + p.fixed);
    std::ofstream(path("space.toml")) << space;
    expect_refused({"design", "run", "space.toml", "-o", "out"}, 2);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryRow, Refusal, ::testing::ValuesIn(every_refusal()), name_of);

// The rows' refusals are not an empty set: each engine refuses at least one row (were the tables
// to lose their refusal columns, the test above would check nothing).
TEST(Refusals, EveryEngineRefusesSomeRow) {
  std::set<std::string> engines;
  for (const auto& r : every_refusal()) engines.insert(runner::to_string(r.engine) + (r.lammps_rules ? " (LAMMPS's rules)" : ""));
  EXPECT_EQ(engines, (std::set<std::string>{"liggghts", "lammps", "refsim", "refsim (LAMMPS's rules)"}));
}

}  // namespace
