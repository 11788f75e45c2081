// What a run executed, read from its log (formats/executed.hpp), and the rules it is held to
// (formats/deck_rules.hpp): the input language's reading, a log followed through substitutions,
// ifs, jumps and includes, and each rule against a case generated here. The real LIGGGHTS and
// LAMMPS logs are followed in tests/liggghts/test_executed.cpp.
#include <granstack/formats/case.hpp>
#include <granstack/formats/deck_rules.hpp>
#include <granstack/formats/executed.hpp>
#include <granstack/formats/input_script.hpp>
#include <granstack/generator/case_writer.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <fstream>
#include <unistd.h>

using namespace granstack;
namespace fs = std::filesystem;

namespace {

TEST(InputScript, LinesJoinAtAmpersandsAndLoseTrailingBlanks) {
  const auto lines = formats::script_lines("a b  \nvariable long string &\n   joined\n\nlast &  \n  one\nend");
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0].text, "a b");
  EXPECT_EQ(lines[1].text, "variable long string    joined");  // as LIGGGHTS and LAMMPS echo it
  EXPECT_EQ(lines[1].line, 2);
  EXPECT_EQ(lines[2].text, "");
  EXPECT_EQ(lines[3].text, "last   one");
  EXPECT_EQ(lines[3].line, 5);
  EXPECT_EQ(lines[4].text, "end");  // no final newline: as it is
}

TEST(InputScript, CommentsSubstitutionsAndWordsAreTheProgramsOwn) {
  EXPECT_EQ(formats::without_comment("print \"a # b\" # c"), "print \"a # b\" ");
  EXPECT_EQ(formats::without_comment("x 'it' # y"), "x 'it' ");
  const std::string line = "variable c equal ${a}+$(1+(2)) $b \"$q\"";
  const auto ends = formats::substitution_ends(line);
  ASSERT_TRUE(ends);
  ASSERT_EQ(ends->size(), 3u);
  EXPECT_EQ(line.substr((*ends)[0]), "+$(1+(2)) $b \"$q\"");
  EXPECT_EQ(line.substr((*ends)[1]), " $b \"$q\"");
  EXPECT_EQ(line.substr((*ends)[2]), " \"$q\"");
  EXPECT_FALSE(formats::substitution_ends("timestep ${dt"));
  EXPECT_FALSE(formats::substitution_ends("x $(1+2"));
  const auto words = formats::script_words("if \"${a} > 1\" then 'print \"x\"' else   \"run 5\"");
  ASSERT_TRUE(words);
  EXPECT_EQ(*words, (std::vector<std::string>{"if", "${a} > 1", "then", "print \"x\"", "else", "run 5"}));
  EXPECT_FALSE(formats::script_words("print \"unclosed"));
  EXPECT_FALSE(formats::script_words("print 'it''s'"));  // LIGGGHTS: "quote not followed by whitespace"
  EXPECT_TRUE(formats::same_word("1e-7", "1.0e-07"));
  EXPECT_FALSE(formats::same_word("1e-7", "1.0000001e-07"));
}

// The running test's own folder under the system's temporary one, not there yet.
fs::path own_dir(const std::string& kind) {
  const auto dir = fs::temp_directory_path() / ("granstack_" + kind + "_" + std::to_string(::getpid()) + "_" +
                                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  return dir;
}

// A deck and its log, written into a folder of their own.
class Follow : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = own_dir("follow");
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void file(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  formats::ExecutedScript follow(const std::string& log) { return formats::follow_log(dir_, "in.deck", log); }
  static std::vector<std::string> texts(const formats::ExecutedScript& s) {
    std::vector<std::string> out;
    for (const auto& c : s.commands) out.push_back(c.text);
    return out;
  }
  fs::path dir_;
};

// The log of LIGGGHTS 3.8 for this deck, as it wrote it (outputs between the echoes included).
TEST_F(Follow, SubstitutionsIfsIncludesAndJumpsAreFollowed) {
  file("inc.txt", "variable inc equal 3\n");
  file("in.deck",
       "# comment\n"
       "variable a equal 2   # trailing\n"
       "variable c equal ${a}+$(1+1)\n"
       "if \"${a} > 1\" then \"variable d equal 5\" \"print 'in if'\" else \"variable d equal 6\"\n"
       "include inc.txt\n"
       "label again\n"
       "run 10\n"
       "if \"1 > 0\" then \"jump SELF done\"\n"
       "run 99\n"
       "label done\n"
       "print \"end\"\n");
  const auto s = follow(
      "LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)\n# comment\nvariable a equal 2   # trailing\n"
      "variable c equal ${a}+$(1+1)\nvariable c equal 2+$(1+1)\nvariable c equal 2+2\n"
      "if \"${a} > 1\" then \"variable d equal 5\" \"print 'in if'\" else \"variable d equal 6\"\n"
      "variable d equal 5\nprint 'in if'\nin if\ninclude inc.txt\nvariable inc equal 3\nlabel again\nrun 10\n"
      "Setting up run ...\nLoop time of 0.1 on 1 procs for 10 steps with 3 atoms\n"
      "if \"1 > 0\" then \"jump SELF done\"\njump SELF done\nprint \"end\"\nend\n");
  EXPECT_TRUE(s.complete) << s.stopped;
  EXPECT_EQ(texts(s), (std::vector<std::string>{"variable a equal 2   ", "variable c equal 2+2",
                                                "if \"${a} > 1\" then \"variable d equal 5\" \"print 'in if'\" else \"variable d equal 6\"",
                                                "variable d equal 5", "print 'in if'", "include inc.txt",
                                                "variable inc equal 3", "label again", "run 10",
                                                "if \"1 > 0\" then \"jump SELF done\"", "jump SELF done", "print \"end\""}));
  EXPECT_EQ(s.commands[6].where(), "inc.txt:1");
  EXPECT_EQ(s.commands[3].where(), "in.deck:4, from an if");
  EXPECT_EQ(s.files, (std::vector<std::string>{"in.deck", "inc.txt"}));
  EXPECT_EQ(s.commands[1].log_line, 4);
}

// A loop back to a label, as a blow-end deck makes one per dump interval: every search begins at
// the top of the file, so the first of two labels of one name is the one found, each time.
TEST_F(Follow, ALoopBackToALabelFindsTheFirstSuchLabelEachTime) {
  file("in.deck",
       "variable i equal 0\n"
       "label again\n"
       "variable i equal $(v_i+1)\n"
       "if \"${i} < 3\" then \"jump SELF again\"\n"
       "jump SELF later\n"
       "label again\n"
       "label later\n"
       "print \"end\"\n");
  std::string log = "variable i equal 0\nlabel again\n";
  for (int i = 1; i <= 3; ++i) {
    log += fmt::format("variable i equal $(v_i+1)\nvariable i equal {}\nif \"${{i}} < 3\" then \"jump SELF again\"\n", i);
    log += i < 3 ? "jump SELF again\n" : "jump SELF later\nprint \"end\"\nend\n";
  }
  const auto s = follow(log);
  EXPECT_TRUE(s.complete) << s.stopped;
  ASSERT_EQ(s.commands.size(), 12U);
  EXPECT_EQ(s.commands[8].text, "variable i equal 3");
  EXPECT_EQ(s.commands[8].where(), "in.deck:3");
  EXPECT_EQ(s.commands[8].log_line, 11);
  EXPECT_EQ(s.commands[11].text, "print \"end\"");
  EXPECT_EQ(s.commands[11].where(), "in.deck:8");
}

TEST_F(Follow, WhatCannotBeFollowedOrWasNotRunIsSaid) {
  file("in.deck", "variable n loop 2\nlabel l\nnext n\njump SELF l\nrun 1\n");
  auto s = follow("variable n loop 2\nlabel l\nnext n\n");
  EXPECT_FALSE(s.complete);
  EXPECT_TRUE(s.unfollowable);
  EXPECT_NE(s.stopped.find("in.deck:3: 'next n' cannot be followed"), std::string::npos) << s.stopped;
  file("in.deck", "echo none\ntimestep 1e-7\n");
  s = follow("echo none\n");
  EXPECT_NE(s.stopped.find("stops the log's echo"), std::string::npos) << s.stopped;
  file("in.deck", "timestep 1e-7\nrun 5\nprint done\n");
  s = follow("LIGGGHTS\ntimestep 1e-7\nrun 5\nERROR: lost atoms\n");
  EXPECT_FALSE(s.complete);
  EXPECT_FALSE(s.unfollowable);
  EXPECT_NE(s.stopped.find("the log ends before in.deck:3 ('print done')"), std::string::npos) << s.stopped;
  s = follow("LIGGGHTS\nSetting up run\n");
  EXPECT_NE(s.stopped.find("echoes no line of in.deck"), std::string::npos) << s.stopped;
  // An if whose command reads as the line after it: which ran cannot be told.
  file("in.deck", "if \"${x} > 0\" then \"run 5\"\nrun 5\n");
  s = follow("if \"${x} > 0\" then \"run 5\"\nrun 5\n");
  EXPECT_TRUE(s.unfollowable);
  EXPECT_NE(s.stopped.find("cannot tell which commands of the if ran"), std::string::npos) << s.stopped;
  // A substitution the log does not echo as the program makes it.
  file("in.deck", "timestep ${dt}\n");
  s = follow("timestep ${dt}\ntimestep\n");
  EXPECT_TRUE(s.unfollowable);
}

// A generated case, its reference deck (granstack's own), and commands "executed" from deck text
// line by line (what the log of a deck without control flow gives).
class Rules : public ::testing::Test {
 protected:
  void make(model::StackSpec spec) {
    dir_ = own_dir("rules");
    generator::GenerateOptions o;
    o.output = dir_;
    generator::generate({{"case", spec}}, o);
    case_.emplace(formats::Case::open(dir_.string()));
    reference_ = generator::default_deck(case_->manifest());
  }
  void TearDown() override { fs::remove_all(dir_); }
  static formats::ExecutedScript ran(const std::string& deck) {
    formats::ExecutedScript s;
    s.files = {"in.stack"};
    s.complete = true;
    for (const auto& line : formats::script_lines(deck)) {
      const std::string text(formats::without_comment(line.text));
      const auto words = formats::script_words(text);
      if (words && !words->empty()) s.commands.push_back({"in.stack", line.line, text, *words, line.line, false});
    }
    return s;
  }
  formats::DeckVerdict executed(const std::string& deck) { return formats::hold_executed(*case_, ran(deck), reference_); }
  // The reference with `from` replaced by `to`.
  std::string edited(const std::string& from, const std::string& to) const {
    auto text = reference_;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  }
  static std::string problems(const formats::DeckVerdict& v) { return v.summary(100); }
  fs::path dir_;
  std::optional<formats::Case> case_;
  std::string reference_;
};

TEST_F(Rules, GranstacksOwnDeckPassesAndEveryChangeOfItsPhysicsIsNamed) {
  model::StackSpec spec;
  spec.blocks = 2;
  make(spec);
  EXPECT_TRUE(executed(reference_).ok()) << problems(executed(reference_));
  EXPECT_TRUE(formats::hold_literal(*case_, reference_, "in.stack", reference_).ok());
  const auto dt = fmt::format("timestep        {}", case_->derived().dt);
  // N1: a second time step (an include's, an if's: the log shows them all as commands).
  auto v = executed(edited(dt, dt + "\ntimestep 1e-7"));
  EXPECT_NE(problems(v).find("'timestep 1e-7' is not what granstack's deck runs for this case"), std::string::npos)
      << problems(v);
  // The same value written otherwise is the same time step.
  EXPECT_TRUE(executed(edited(dt, fmt::format("timestep {:.20e}", case_->derived().dt))).ok());
  // N2: the output sphere's group, redefined.
  v = executed(reference_ + "\ngroup output_sphere clear\n");
  EXPECT_NE(problems(v).find("'group output_sphere clear' redefines group output_sphere"), std::string::npos)
      << problems(v);
  // N5: physics the spec does not have.
  for (const auto* added : {"fix g all gravity 9.81 vector 0 0 -1", "fix visc all viscous 0.01", "displace_atoms all move 0 0 1e-9",
                            "fix f all freeze", "fix dtr all dt/reset 1 NULL NULL 1e-6"}) {
    v = executed(edited(dt, dt + "\n" + added));
    EXPECT_NE(problems(v).find(fmt::format("'{}' is a command granstack's deck does not run", added)), std::string::npos)
        << problems(v);
    EXPECT_NE(problems(v).find("deck_additions = ["), std::string::npos);
  }
  v = executed(edited("fix             integr all nve/sphere", "# no integrator"));
  EXPECT_NE(problems(v).find("the deck never ran 'fix integr all nve/sphere'"), std::string::npos) << problems(v);
  v = executed(edited("fix             integr all nve/sphere", "fix 1 all nve/sphere\nfix integr all nve/sphere\nunfix integr"));
  EXPECT_NE(problems(v).find("'unfix integr' removes fix integr"), std::string::npos) << problems(v);
  EXPECT_NE(problems(v).find("'fix 1 all nve/sphere' is a command granstack's deck does not run"), std::string::npos);
  // Settings run after the run did not hold for it.
  v = executed(edited(dt, "") + "\n" + dt + "\n");
  EXPECT_NE(problems(v).find("comes after the first run"), std::string::npos) << problems(v);
  v = executed(edited("thermo_modify   lost error", "thermo_modify   lost ignore"));
  EXPECT_NE(problems(v).find("lose spheres without stopping"), std::string::npos) << problems(v);
}

TEST_F(Rules, RunsAndWritesAreTheCasesAndAdditionsAreNamed) {
  model::StackSpec spec;
  spec.blocks = 1;
  spec.deck_additions = {"fix viscous", "dump custom/vtk"};
  make(spec);
  const auto run = fmt::format("run             {}", case_->derived().steps);
  auto v = executed(edited(run, run + "\n" + run));
  EXPECT_NE(problems(v).find(fmt::format("ran '{}' 2 times", formats::joined({"run", std::to_string(case_->derived().steps)}))),
            std::string::npos)
      << problems(v);
  v = executed(edited(run, "run 100"));
  EXPECT_NE(problems(v).find("'run 100' is not the case's run"), std::string::npos) << problems(v);
  // N4: a write outside the case, over the user's file; a write over the case's own files.
  v = executed(edited(run, "print \"x\" file /home/user/notes.txt\nwrite_dump all custom ../USERFILE.txt id\n" + run));
  EXPECT_NE(problems(v).find("writes /home/user/notes.txt, outside the case"), std::string::npos) << problems(v);
  EXPECT_NE(problems(v).find("writes ../USERFILE.txt, outside the case"), std::string::npos) << problems(v);
  v = executed(edited(run, "fix v all viscous 0.01\ndump vtk all custom/vtk 10 dumps/x.vtk id\n" + run));
  EXPECT_NE(problems(v).find("writes dumps/x.vtk, a file of the case that granstack's own commands write"),
            std::string::npos)
      << problems(v);
  // Additions the spec lists run, and are named.
  v = executed(edited(run, "fix v all viscous 0.01\ndump vtk all custom/vtk 10 vtk/x_*.vtk id\n" + run));
  EXPECT_TRUE(v.ok()) << problems(v);
  ASSERT_EQ(v.additions.size(), 2u);
  EXPECT_NE(v.additions[0].find("fix v all viscous 0.01 (in.stack:"), std::string::npos) << v.additions[0];
  // A reading that stopped is a problem of its own.
  auto stopped = ran(reference_);
  stopped.complete = false;
  stopped.stopped = "the log ends before in.stack:9";
  EXPECT_NE(problems(formats::hold_executed(*case_, stopped, reference_)).find("the log ends before"), std::string::npos);
}

// Before a run, the deck's own lines: what can be judged without running it.
TEST_F(Rules, ADecksLiteralLinesAreHeldBeforeItRuns) {
  model::StackSpec spec;
  spec.blocks = 1;
  make(spec);
  const auto literal = [&](const std::string& deck) { return problems(formats::hold_literal(*case_, deck, "in.stack", reference_)); };
  EXPECT_NE(literal(reference_ + "\nif \"1 > 0\" then \"timestep 1e-7\"\n").find("'timestep 1e-7' is not"),
            std::string::npos);
  EXPECT_NE(literal(reference_ + "\npartition yes 1 timestep 1e-7\n").find("cannot be followed"), std::string::npos);
  EXPECT_NE(literal(reference_ + "\nshell touch x\n").find("it runs a program"), std::string::npos);
  // What only its run can tell is left to the run: a substituted value, a missing command.
  EXPECT_EQ(literal(reference_ + "\ntimestep ${dt}\n"), "");
  EXPECT_EQ(literal("units si\n"), "");
}

// A protected plate's deck writes its mesh with print lines and reads it back: those lines are the
// plate, held like a fix. Another vertex (the plate tilted by 0.1 mm) or a print of the user's over
// the mesh is named; a mesh never written is missing; prints to other files stay the user's.
TEST_F(Rules, APlatesMeshIsHeldLikeItsFixes) {
  model::StackSpec spec;
  spec.blocks = 1;
  spec.bottom = model::Boundary::wall;
  spec.plate_mass = 0.01;
  spec.mount_stiffness = 1e5;
  make(spec);
  EXPECT_TRUE(executed(reference_).ok()) << problems(executed(reference_));
  const auto at = reference_.find("\"vertex 0 ");
  ASSERT_NE(at, std::string::npos) << reference_;
  const auto end = reference_.find(" 0\"", at + 9);
  const auto vertex = reference_.substr(at, end + 3 - at);
  auto tilted = vertex;
  tilted.replace(tilted.size() - 3, 3, " 0.0001\"");
  auto v = executed(edited(vertex, tilted));
  EXPECT_NE(problems(v).find("writes plate.stl, which granstack's deck writes itself (and reads back) with other lines"),
            std::string::npos)
      << problems(v);
  EXPECT_NE(problems(v).find(fmt::format("the deck never ran 'print {}", vertex.substr(1, vertex.size() - 2))), std::string::npos)
      << problems(v);
  const auto integr = std::string("fix             integr all nve/sphere");
  v = executed(edited(integr, integr + "\nprint \"solid x\" append plate.stl"));
  EXPECT_NE(problems(v).find("'print solid x append plate.stl' writes plate.stl"), std::string::npos) << problems(v);
  EXPECT_TRUE(executed(edited(integr, integr + "\nprint \"a note\" file notes.txt")).ok());
}

}  // namespace
