#pragma once
// The input language LIGGGHTS 3.8 and LAMMPS read (their src/input.cpp): how a file becomes
// lines, a line a command's words, and what the program echoes to its log as it reads them.
// The echo is how granstack learns what a run executed (formats/executed.hpp).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

// A line as the program reads it: physical lines ending in '&' joined to the next (the '&'
// dropped), trailing blanks removed. The program echoes exactly `text` before it runs it.
struct ScriptLine {
  std::string text;
  long line = 0;  // its first physical line, from 1
};
std::vector<ScriptLine> script_lines(std::string_view file_text);

// The line without its comment: from the first '#' outside quotes on.
std::string_view without_comment(std::string_view line);

// Where each `$` substitution of a comment-free line ends (${name}, $(expression), $x), in
// order: after each one the program echoes the line again, the substituted part followed by the
// rest from that offset on. nullopt when a substitution is not closed (the program stops there).
std::optional<std::vector<std::size_t>> substitution_ends(std::string_view line);

// The words of a command as the program splits them: blanks between words, a word that starts
// with a quote ("..." or '...') runs to the same quote and loses both. nullopt when a quote is not
// closed, or not followed by a blank.
std::optional<std::vector<std::string>> script_words(std::string_view line);

// Whether two words say the same: equal text, or numbers of equal value ("1e-7", "1.0e-07").
bool same_word(std::string_view a, std::string_view b);
// The words joined by single blanks (a command as messages quote it).
std::string joined(const std::vector<std::string>& words);

}  // namespace granstack::formats
