#include <granstack/formats/input_script.hpp>
#include <granstack/formats/line_reader.hpp>

namespace granstack::formats {

namespace {
// The blanks Input::nextword() skips (strspn with " \t\n\v\f\r"): the C locale's isspace, tested
// inline (the log of a blow-end run repeats its loop's lines once per dump interval).
bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; }

// The runs of non-blanks in `line`: the words it has when no quote holds a blank.
std::size_t blank_separated(std::string_view line) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < line.size(); ++i) n += !blank(line[i]) && (i == 0 || blank(line[i - 1]));
  return n;
}
}  // namespace

// As Input::file() reads: a physical line ending in '&' (after its trailing blanks) continues
// where the '&' stood; the last line of a file without a final newline is taken as it is.
std::vector<ScriptLine> script_lines(std::string_view file_text) {
  std::vector<ScriptLine> lines;
  std::string buffer;
  long physical = 0, first = 0;
  for (std::size_t at = 0; at < file_text.size();) {
    const auto nl = file_text.find('\n', at);
    const bool ended = nl != std::string_view::npos;
    const auto piece = file_text.substr(at, ended ? nl - at : std::string_view::npos);
    at = ended ? nl + 1 : file_text.size();
    if (buffer.empty() && first == 0) first = physical + 1;
    ++physical;
    buffer += piece;
    if (!ended) break;
    auto end = buffer.size();
    while (end > 0 && blank(buffer[end - 1])) --end;
    if (end > 0 && buffer[end - 1] == '&') {
      buffer.resize(end - 1);
      continue;
    }
    buffer.resize(end);
    lines.push_back({std::move(buffer), first});
    buffer.clear();
    first = 0;
  }
  if (first != 0) lines.push_back({std::move(buffer), first});
  return lines;
}

// Input::parse(): one quote character remembered at a time, the last one seen.
std::string_view without_comment(std::string_view line) {
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '#' && quote == 0) return line.substr(0, i);
    if (c == quote) {
      quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    }
  }
  return line;
}

// Input::substitute(): double and single quotes each toggle a flag of their own, and a '$' is
// substituted only outside both.
std::optional<std::vector<std::size_t>> substitution_ends(std::string_view line) {
  std::vector<std::size_t> ends;
  bool in_double = false, in_single = false;
  for (std::size_t i = 0; i < line.size();) {
    const char c = line[i];
    if (c == '$' && !in_double && !in_single) {
      if (i + 1 >= line.size()) return std::nullopt;
      const char open = line[i + 1];
      std::size_t end = 0;
      if (open == '{') {
        const auto close = line.find('}', i + 2);
        if (close == std::string_view::npos) return std::nullopt;
        end = close + 1;
      } else if (open == '(') {
        int depth = 0;
        std::size_t k = i + 2;
        for (; k < line.size() && !(line[k] == ')' && depth == 0); ++k) depth += line[k] == '(' ? 1 : line[k] == ')' ? -1 : 0;
        if (k >= line.size()) return std::nullopt;
        end = k + 1;
      } else {
        end = i + 2;
      }
      ends.push_back(end);
      i = end;
      continue;
    }
    if (c == '"') in_double = !in_double;
    if (c == '\'') in_single = !in_single;
    ++i;
  }
  return ends;
}

// Input::nextword().
std::optional<std::vector<std::string>> script_words(std::string_view line) {
  std::vector<std::string> words;
  words.reserve(blank_separated(line));  // one allocation of the size kept (a run's commands are all kept)
  std::size_t at = 0;
  for (;;) {
    while (at < line.size() && blank(line[at])) ++at;
    if (at >= line.size()) return words;
    const char q = line[at];
    if (q == '"' || q == '\'') {
      const auto close = line.find(q, at + 1);
      if (close == std::string_view::npos) return std::nullopt;
      if (close + 1 < line.size() && !blank(line[close + 1])) return std::nullopt;
      words.emplace_back(line.substr(at + 1, close - at - 1));
      at = close + 1;
    } else {
      auto end = at;
      while (end < line.size() && !blank(line[end])) ++end;
      words.emplace_back(line.substr(at, end - at));
      at = end;
    }
  }
}

bool same_word(std::string_view a, std::string_view b) {
  if (a == b) return true;
  double x = 0.0, y = 0.0;
  return parse_double(a, x) && parse_double(b, y) && x == y;
}

std::string joined(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) {
    if (!out.empty()) out += ' ';
    out += w;
  }
  return out;
}

}  // namespace granstack::formats
