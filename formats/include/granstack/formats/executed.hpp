#pragma once
// What a LIGGGHTS or LAMMPS run executed, read from its log. Both programs echo to the log every
// line of input they read before they run it, and the line again after each `$` substitution
// (formats/input_script.hpp). Following the deck through its includes, jumps and ifs against
// that echo gives the commands that ran, in order, with the values they ran with, each traced
// to its file and line. A command the log cannot show the effect of (a shell, a loop variable's
// `next`, `echo none`) stops the reading, and says so.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

struct ExecutedCommand {
  std::string file;   // the input file it came from, as named (the deck, an included file)
  long line = 0;      // its line there; for a command an `if` ran, the if's line
  std::string text;   // as it ran: comment removed, variables substituted
  std::vector<std::string> words;
  long log_line = 0;  // the log's line that echoes it, from 1
  bool in_if = false; // run by an `if`
  // "in.stack:57" (", from an if" added for an if's command).
  std::string where() const;
};

struct ExecutedScript {
  std::vector<ExecutedCommand> commands;
  std::vector<std::string> files;  // the input files read: the deck first, then each an include or jump opened
  bool complete = false;           // the input was read to its end, or to a `quit`
  // Why the reading stopped before the end ("" when complete): a command granstack cannot follow
  // (`unfollowable`), or a line whose echo the log does not hold (the run ended there).
  std::string stopped;
  bool unfollowable = false;
};

// Follows `deck` (a file in `dir`, where the program ran; includes and jumps are read from there
// too) through the text of the program's log.
ExecutedScript follow_log(const std::filesystem::path& dir, const std::string& deck, std::string_view log_text);

// Why a command is one granstack cannot follow through the log, or "".
std::string unfollowable_command(const std::vector<std::string>& words);

}  // namespace granstack::formats
