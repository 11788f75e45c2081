// The echo of the real LIGGGHTS and LAMMPS: a deck with substitutions, a continued line, an if,
// an include, a loop by jump and a print whose output reads as a command, run by each program,
// followed through its log (formats/executed.hpp) to the commands as they ran.
#include <granstack/formats/executed.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/os/mpi_session.hpp>
#include <granstack/os/process.hpp>

#include "../support/scratch.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace granstack;
namespace fs = std::filesystem;

namespace {

constexpr const char* kDeck = R"deck(# comment line
variable a equal 2   # trailing
variable b string hello
print "a is ${a} and $(v_a*2)"   # comment
variable c equal ${a}+$(1+1)
variable long string &
   joined
if "${a} > 1" then "variable d equal 5" &
  "print 'inside if $a'" else "variable d equal 6"
include inc.txt
variable k equal 0
label again
variable k equal $(v_k+1)
if "${k} < 3" then "jump SELF again"
print "variable k2 equal 7"
variable k2 equal 7
print "k is ${k}"
)deck";

const std::vector<std::string> kRan{
    "variable a equal 2   ",
    "variable b string hello",
    "print \"a is ${a} and $(v_a*2)\"   ",
    "variable c equal 2+2",
    "variable long string    joined",
    "if \"${a} > 1\" then \"variable d equal 5\"   \"print 'inside if $a'\" else \"variable d equal 6\"",
    "variable d equal 5",
    "print 'inside if $a'",
    "include inc.txt",
    "variable inc equal 3",
    "variable k equal 0",
    "label again",
    "variable k equal 1",
    "if \"${k} < 3\" then \"jump SELF again\"",
    "jump SELF again",
    "variable k equal 2",
    "if \"${k} < 3\" then \"jump SELF again\"",
    "jump SELF again",
    "variable k equal 3",
    "if \"${k} < 3\" then \"jump SELF again\"",
    "print \"variable k2 equal 7\"",
    "variable k2 equal 7",
    "print \"k is ${k}\""};

void follow_with(const std::string& program) {
  if (!os::find_program(program)) GTEST_SKIP() << program << " is not installed (scripts/setup.sh installs it)";
  const auto dir = test::scratch(fs::path(GRANSTACK_TEST_WORKDIR) / ("Executed." + program));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "in.deck") << kDeck;
  std::ofstream(dir / "inc.txt") << "variable inc equal 3\n";
  os::StartOptions o;
  o.cwd = dir;
  o.output = dir / "screen.txt";
  ASSERT_TRUE(os::run_open_mpi_program({program, "-in", "in.deck", "-log", "log.txt"}, o).ok()) << formats::read_file(dir / "screen.txt");
  const auto ran = formats::follow_log(dir, "in.deck", formats::read_file(dir / "log.txt"));
  EXPECT_TRUE(ran.complete) << ran.stopped;
  std::vector<std::string> texts;
  for (const auto& c : ran.commands) texts.push_back(c.text);
  EXPECT_EQ(texts, kRan);
  ASSERT_EQ(ran.commands.size(), kRan.size());
  EXPECT_EQ(ran.commands[6].where(), "in.deck:8, from an if");
  EXPECT_EQ(ran.commands[9].where(), "inc.txt:1");
  EXPECT_EQ(ran.commands[12].where(), "in.deck:13");
}

TEST(Executed, LiggghtsLogGivesTheCommandsAsTheyRan) { follow_with("liggghts"); }
TEST(Executed, LammpsLogGivesTheCommandsAsTheyRan) { follow_with("lmp"); }

}  // namespace
