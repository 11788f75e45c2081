#include <granstack/formats/executed.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/input_script.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>

namespace granstack::formats {

namespace fs = std::filesystem;

std::string ExecutedCommand::where() const {
  return fmt::format("{}:{}{}", file, line, in_if ? ", from an if" : "");
}

std::string unfollowable_command(const std::vector<std::string>& words) {
  if (words.empty()) return "";
  const auto& c = words[0];
  if (c == "shell") return "it runs a program, which could do and write anything";
  if (c == "python") return "it runs Python code";
  if (c == "next") {
    return "it moves a loop variable, and whether the jump after it runs depends on a value the log does not show";
  }
  if (c == "partition") return "it runs a command on some partitions only";
  if (c == "log") return "it sends the rest of the log, and with it the echo of the commands, to another file";
  if (c == "clear") return "it starts the program anew";
  if (c == "echo" && !(words.size() == 2 && (words[1] == "log" || words[1] == "both"))) {
    return "it stops the log's echo of the commands";
  }
  if (c == "run" && std::find(words.begin(), words.end(), "every") != words.end()) {
    return "'run ... every' runs commands between the pieces of the run";
  }
  return "";
}

namespace {

std::vector<std::string_view> log_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  for (std::size_t at = 0; at < text.size();) {
    auto nl = text.find('\n', at);
    if (nl == std::string_view::npos) nl = text.size();
    lines.push_back(text.substr(at, nl - at));
    at = nl + 1;
  }
  return lines;
}

bool ends_with(std::string_view s, std::string_view tail) {
  return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

// The commands of an `if` line's branches (then, each elif, else), as the program takes them.
std::vector<std::vector<std::string>> if_branches(const std::vector<std::string>& words) {
  std::vector<std::vector<std::string>> branches;
  if (words.size() < 4 || words[2] != "then") return branches;
  branches.emplace_back();
  for (std::size_t i = 3; i < words.size(); ++i) {
    if (words[i] == "elif") {
      branches.emplace_back();
      ++i;  // its condition
    } else if (words[i] == "else") {
      branches.emplace_back();
    } else {
      branches.back().push_back(words[i]);
    }
  }
  return branches;
}

// A line of an input file, named in a message only when one is written.
struct Place {
  const std::string& file;
  long line;
  std::string where() const { return fmt::format("{}:{}", file, line); }
};

class Follower {
 public:
  Follower(fs::path dir, std::string_view log) : dir_(std::move(dir)), log_(log_lines(log)) {}

  ExecutedScript run(const std::string& deck) {
    if (!open(deck)) return std::move(out_);
    while (!files_.empty() && out_.stopped.empty()) {
      auto& f = files_.back();
      if (f.next >= f.lines.size()) {
        files_.pop_back();
        continue;
      }
      if (label_) {  // a jump's search: the program reads on, echoing nothing, to the label
        find_label(f);
        continue;
      }
      const auto& line = f.lines[f.next++];
      execute(line.text, f.name, line.line, false, false);
    }
    out_.complete = out_.stopped.empty();
    if (!out_.complete && out_.commands.empty() && !out_.unfollowable) {
      out_.stopped = fmt::format("the log echoes no line of {}: the program ran with '-echo none' or '-echo screen', "
                                 "or the log is another run's; run it with its default echo",
                                 deck);
    }
    return std::move(out_);
  }

 private:
  struct Open {
    std::string name;
    std::vector<ScriptLine> lines;
    std::size_t next = 0;
    // Where each label a search from the file's top found stands: a blow-end deck jumps back to
    // its label once per dump interval, and the search reads the same lines each time.
    std::map<std::string, std::size_t, std::less<>> labels;
  };

  // Reads on from f's next line to the line `label <label_>`, as the program's search does.
  // Every search begins at the top of the file jumped to (it may read on into the file that
  // included it, where what it finds is not remembered).
  void find_label(Open& f) {
    const bool in_jumped_file = label_file_ < files_.size() && &f == &files_[label_file_];
    if (const auto it = f.labels.find(*label_); f.next == 0 && in_jumped_file && it != f.labels.end()) {
      f.next = it->second + 1;
      label_.reset();
      return;
    }
    const auto& line = f.lines[f.next++];
    const auto words = script_words(without_comment(line.text));
    if (!words || words->size() < 2 || (*words)[0] != "label" || (*words)[1] != *label_) return;
    if (in_jumped_file) f.labels.emplace(*label_, f.next - 1);
    label_.reset();
  }

  bool open(const std::string& name) {
    try {
      files_.push_back({name, script_lines(read_file(dir_ / name)), 0, {}});
      out_.files.push_back(name);
      return true;
    } catch (const std::exception& e) {
      stop(fmt::format("{} cannot be read now ({})", name, e.what()), true);
      return false;
    }
  }
  void stop(std::string why, bool unfollowable) {
    if (!out_.stopped.empty()) return;
    out_.stopped = std::move(why);
    out_.unfollowable = unfollowable;
  }

  // Where the log echoes `raw` from at_ on (right at at_ when `strict`), or npos.
  std::size_t find_echo(std::string_view raw, bool strict) const {
    if (strict) return at_ < log_.size() && log_[at_] == raw ? at_ : std::string_view::npos;
    for (auto i = at_; i < log_.size(); ++i) {
      if (log_[i] == raw) return i;
    }
    return std::string_view::npos;
  }

  // The line as it ran, from its echo and the echoes of its substitutions; nullopt when the log
  // does not hold them (the reason is set).
  std::optional<std::string> read_echo(const std::string& raw, std::size_t echo, const Place& place) {
    if (echo == std::string_view::npos) {
      stop(fmt::format("the log ends before {} ('{}'): the run stopped there, or the log is another run's", place.where(),
                       raw),
           false);
      return std::nullopt;
    }
    at_ = echo + 1;
    const auto text = without_comment(raw);
    const auto ends = substitution_ends(text);
    if (!ends) {
      stop(fmt::format("{}: a substitution in '{}' is not closed", place.where(), raw), false);
      return std::nullopt;
    }
    std::string ran(text);
    const auto head = text.substr(0, text.find('$'));
    for (const auto end : *ends) {
      if (at_ >= log_.size() || !ends_with(log_[at_], text.substr(end)) || log_[at_].substr(0, head.size()) != head) {
        stop(fmt::format("{}: the log does not echo the substitutions of '{}' as the program makes them", place.where(),
                         raw),
             true);
        return std::nullopt;
      }
      ran = std::string(log_[at_++]);
    }
    return ran;
  }

  void execute(const std::string& raw, const std::string& file, long line, bool strict, bool in_if) {
    const Place place{file, line};
    const auto echo = find_echo(raw, strict);
    const auto log_line = static_cast<long>(echo) + 1;
    auto ran = read_echo(raw, echo, place);
    if (!ran) return;
    auto words = script_words(*ran);
    if (!words) {
      stop(fmt::format("{}: '{}' has a quote that is not closed, or not followed by a blank", place.where(), *ran), false);
      return;
    }
    if (words->empty()) return;
    out_.commands.push_back({file, line, std::move(*ran), std::move(*words), log_line, in_if});
    dispatch(out_.commands.back().words, file, line);
  }

  void dispatch(const std::vector<std::string>& words, const std::string& file, long line) {
    const auto& c = words[0];
    if (const auto why = unfollowable_command(words); !why.empty()) {
      stop(fmt::format("{}: '{}' cannot be followed: {}", Place{file, line}.where(), joined(words), why), true);
    } else if (c == "include" && words.size() == 2) {
      open(words[1]);
    } else if (c == "jump" && words.size() >= 2) {
      jump(words);
    } else if (c == "if") {
      follow_if(words, file, line);
    } else if (c == "quit") {
      files_.clear();
    }
  }

  void jump(const std::vector<std::string>& words) {
    if (words[1] == "SELF") {
      files_.back().next = 0;
    } else {
      files_.pop_back();
      open(words[1]);
    }
    if (words.size() >= 3) {
      label_ = words[2];
      label_file_ = files_.size() - 1;
    }
  }

  // The text of the line the program reads next when no command of an if runs.
  std::optional<std::string> next_line_text() const {
    for (auto f = files_.rbegin(); f != files_.rend(); ++f) {
      if (f->next < f->lines.size()) return f->lines[f->next].text;
    }
    return std::nullopt;
  }

  // An if's branch that ran is the one whose first command the log echoes next, right after the
  // if (nothing is printed between); none ran when it echoes the line after the if.
  // (`words` is the if's command in out_.commands: read before the branch's commands are added.)
  void follow_if(const std::vector<std::string>& words, const std::string& file, long line) {
    const auto branches = if_branches(words);
    const std::vector<std::string>* taken = nullptr;
    int matches = 0;
    for (const auto& b : branches) {
      if (b.empty() || find_echo(b[0], true) == std::string_view::npos) continue;
      if (taken != nullptr && *taken == b) continue;  // two branches that run the same commands
      taken = &b;
      ++matches;
    }
    const auto after = next_line_text();
    if (taken != nullptr && (matches > 1 || (after && *after == (*taken)[0]))) {
      stop(fmt::format("{}: the log cannot tell which commands of the if ran ('{}' begins more than one way on)",
                       Place{file, line}.where(), (*taken)[0]),
           true);
      return;
    }
    if (taken == nullptr) return;
    for (std::size_t k = 0; k < taken->size() && !label_ && out_.stopped.empty(); ++k) {
      execute((*taken)[k], file, line, k == 0, true);
    }
  }

  fs::path dir_;
  std::vector<std::string_view> log_;
  std::size_t at_ = 0;
  std::vector<Open> files_;
  std::optional<std::string> label_;
  std::size_t label_file_ = 0;  // files_'s index of the file the search began in
  ExecutedScript out_;
};

}  // namespace

ExecutedScript follow_log(const fs::path& dir, const std::string& deck, std::string_view log_text) {
  return Follower(dir, log_text).run(deck);
}

}  // namespace granstack::formats
