#include <granstack/formats/deck_rules.hpp>
#include <granstack/formats/input_script.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <string_view>
#include <unordered_set>
#include <utility>

namespace granstack::formats {

namespace fs = std::filesystem;
using Words = std::vector<std::string>;

std::string DeckVerdict::summary(std::size_t most) const {
  std::string out;
  std::vector<std::string> fixes;
  for (std::size_t i = 0; i < problems.size(); ++i) {
    if (i < most) out += fmt::format("\n    {}: {}", problems[i].where, problems[i].what);
    if (std::find(fixes.begin(), fixes.end(), problems[i].fix) == fixes.end()) fixes.push_back(problems[i].fix);
  }
  if (problems.size() > most) out += fmt::format("\n    ... and {} more", problems.size() - most);
  for (const auto& f : fixes) out += "\n  to mend: " + f;
  return out;
}

std::string command_kind(const Words& words) {
  if (words.empty()) return "";
  const auto& c = words[0];
  if ((c == "fix" || c == "compute" || c == "dump") && words.size() >= 4) return c + " " + words[3];
  return c;
}

namespace {

// Commands that change nothing a result is labelled with; they may appear anywhere, any number
// of times (a write of theirs is held as any other).
const std::set<std::string>& harmless() {
  static const std::set<std::string> s{"variable", "print",   "label",      "jump",   "if",   "include", "echo",
                                       "thermo",   "thermo_style", "thermo_modify", "processors", "region", "quit", "info"};
  return s;
}

// Commands that name a fix, compute, dump or group: what they define or act on.
const std::map<std::string, std::string>& acts_on() {
  static const std::map<std::string, std::string> m{
      {"fix", "fix"},         {"unfix", "fix"},         {"fix_modify", "fix"},     {"compute", "compute"},
      {"uncompute", "compute"}, {"compute_modify", "compute"}, {"dump", "dump"},   {"undump", "dump"},
      {"dump_modify", "dump"}, {"group", "group"}};
  return m;
}

const char* kPlaceholders =
    "leave it to the template's placeholders ({{dt}}, {{contact_model}}, {{walls}}, {{gravity}}, {{groups}}, "
    "{{energy_series}}, {{run}}, ...), which write the spec's values";

bool same_words(const Words& a, const Words& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!same_word(a[i], b[i])) return false;
  }
  return true;
}

// The deck granstack's template gives, read as written (its loop is not followed: each command once).
struct Reference {
  std::map<std::string, std::vector<Words>> held;                      // by command, those that name nothing
  std::map<std::pair<std::string, std::string>, std::vector<Words>> named;  // (fix|compute|dump|group, name)
  // The deck's own prints to a file (a protected plate's mesh), by the file: a file the run reads.
  std::map<std::string, std::vector<Words>> prints;
  Words run;
};

// The files a command writes (as it names them), for the commands that write files.
std::vector<std::string> written_files(const Words& w) {
  std::vector<std::string> files;
  const auto at = [&](std::size_t i) {
    if (i < w.size()) files.push_back(w[i]);
  };
  const auto& c = w[0];
  if (c == "dump") at(5);
  if (c == "write_dump") at(3);
  if (c == "write_data" || c == "write_restart" || c == "write_coeff" || c == "log") at(1);
  if (c == "restart" && w.size() > 1 && w[1] != "0") {
    at(2);
    if (w.size() > 3 && w[3].find('/') == std::string::npos && w[3] != "fileper" && w[3] != "nfile") at(3);
  }
  if (c == "pair_write") at(8);
  if (c == "print" || c == "fix") {
    for (std::size_t i = 1; i + 1 < w.size(); ++i) {
      if (w[i] == "file" || w[i] == "append" || w[i] == "universe") at(i + 1);
    }
  }
  return files;
}

Reference read_reference(std::string_view text) {
  Reference r;
  for (const auto& line : script_lines(text)) {
    const auto words = script_words(without_comment(line.text));
    if (!words || words->empty()) continue;
    const auto& c = (*words)[0];
    const auto acts = acts_on().find(c);
    if (acts != acts_on().end() && words->size() >= 2) {
      r.named[{acts->second, (*words)[1]}].push_back(*words);
    } else if (c == "run") {
      r.run = *words;
    } else if (c == "print") {
      for (const auto& file : written_files(*words)) r.prints[file].push_back(*words);
    } else if (harmless().count(c) == 0) {
      r.held[c].push_back(*words);
    }
  }
  return r;
}

class Judge {
 public:
  Judge(const Case& c, std::string_view reference) : c_(c), r_(read_reference(reference)) {
    const auto& f = c.files();
    const auto l = lammps_files(f);
    own_ = {"manifest.json", f.data, f.deck, f.series, f.log, f.screen, f.run_record, l.deck, l.log, l.screen};
    dumps_ = fs::path(f.dump).parent_path().string();
    additions_.insert(c.spec().deck_additions.begin(), c.spec().deck_additions.end());
  }

  // One command alone.
  void command(const Words& w, const std::string& text, const std::string& where) {
    if (const auto why = unfollowable_command(w); !why.empty()) {
      problem(where, fmt::format("'{}' cannot be followed: {}", text, why),
              "write out the commands it stands for, or take it out");
      return;
    }
    const auto& c = w[0];
    const auto acts = acts_on().find(c);
    if (acts != acts_on().end() && w.size() >= 2 && r_.named.count({acts->second, w[1]}) != 0) {
      reserved(w, text, where, acts->second);
      return;
    }
    writes(w, text, where);
    if (c == "print") printed(w, text, where);
    if (c == "run") {
      if (!same_words(w, r_.run)) {
        problem(where, fmt::format("'{}' is not the case's run ('{}')", text, joined(r_.run)), kPlaceholders);
      }
    } else if (c == "thermo_modify") {
      const auto lost = std::find(w.begin(), w.end(), "lost");
      if (lost != w.end() && (lost + 1 == w.end() || *(lost + 1) != "error")) {
        problem(where, fmt::format("'{}' lets the program lose spheres without stopping", text),
                "keep 'lost error', as granstack's deck has it");
      }
    } else if (harmless().count(c) != 0 || (acts != acts_on().end() && (c == "compute" || c == "group" || c[0] == 'u' ||
                                                                         c.find("_modify") != std::string::npos))) {
      // harmless, or a compute, group or change of the deck's own additions
    } else if (const auto held = r_.held.find(c); held != r_.held.end()) {
      const bool known = std::any_of(held->second.begin(), held->second.end(), [&](const Words& r) { return same_words(w, r); });
      if (!known) {
        problem(where, fmt::format("'{}' is not what granstack's deck runs for this case ('{}')", text,
                                   joined(held->second.front())),
                kPlaceholders);
      }
    } else {
      addition(w, text, where);
    }
  }

  // The whole run: what a complete deck must have run, and in which order.
  void whole_run(const ExecutedScript& ran) {
    const auto first_run = std::find_if(ran.commands.begin(), ran.commands.end(),
                                        [](const ExecutedCommand& e) { return e.words[0] == "run"; });
    for (auto e = ran.commands.begin(); e != ran.commands.end(); ++e) {
      if (e > first_run && is_reference_command(e->words)) {
        problem(e->where(), fmt::format("'{}' comes after the first run ({}), which ran without it", joined(e->words),
                                        first_run->where()),
                "leave the order to granstack's template: everything it sets comes before its run");
      }
    }
    missing(ran);
    runs(ran);
  }

  DeckVerdict take() { return std::move(verdict_); }
  // How many problems and additions it has found so far.
  std::size_t findings() const { return verdict_.problems.size() + verdict_.additions.size(); }

 private:
  void problem(const std::string& where, std::string what, std::string fix) {
    verdict_.problems.push_back({where, std::move(what), std::move(fix)});
  }

  // A fix, compute, dump or group of a name granstack's deck gives: exactly its command.
  void reserved(const Words& w, const std::string& text, const std::string& where, const std::string& what) {
    const auto& defined = r_.named.at({what, w[1]});
    if (std::any_of(defined.begin(), defined.end(), [&](const Words& r) { return same_words(w, r); })) return;
    writes(w, text, where);
    const auto action = w[0] == what ? "redefines" : w[0].rfind("un", 0) == 0 ? "removes" : "changes";
    problem(where, fmt::format("'{}' {} {} {}, which granstack's deck defines as '{}'", text, action, what, w[1],
                               joined(defined.front())),
            fmt::format("{}; give a {} of your own another name", kPlaceholders, what));
  }

  // A print to a file the deck's own prints write (the plate's mesh, which the run then reads):
  // one of those lines.
  void printed(const Words& w, const std::string& text, const std::string& where) {
    for (const auto& file : written_files(w)) {
      const auto own = r_.prints.find(file);
      if (own == r_.prints.end()) continue;
      if (std::none_of(own->second.begin(), own->second.end(), [&](const Words& r) { return same_words(w, r); })) {
        problem(where, fmt::format("'{}' writes {}, which granstack's deck writes itself (and reads back) with other lines",
                                   text, file),
                fmt::format("{}; write your own file under another name", kPlaceholders));
      }
    }
  }

  void addition(const Words& w, const std::string& text, const std::string& where) {
    const auto kind = command_kind(w);
    if (additions_.count(kind) != 0) {
      verdict_.additions.push_back(fmt::format("{} ({})", text, where));
      return;
    }
    problem(where, fmt::format("'{}' is a command granstack's deck does not run ({}): it would change or add to what "
                               "the run measures without the spec saying so",
                               text, kind),
            fmt::format("if you mean it, list it in the spec's deck_additions (deck_additions = [\"{}\"]) and the run "
                        "will name it; else take it out of the template",
                        kind));
  }

  void writes(const Words& w, const std::string& text, const std::string& where) {
    for (const auto& file : written_files(w)) {
      const fs::path p(file);
      bool outside = file.empty() || p.is_absolute() || file.find('$') != std::string::npos;
      for (const auto& part : p) outside = outside || part == "..";
      const auto name = p.lexically_normal().string();
      const bool clobbers = !outside && (own_.count(name) != 0 || (!dumps_.empty() && name.rfind(dumps_ + "/", 0) == 0));
      if (outside) {
        problem(where, fmt::format("'{}' writes {}, outside the case", text, file),
                "write inside the case: a relative path without '..' (the program runs in the case's folder)");
      } else if (clobbers) {
        problem(where, fmt::format("'{}' writes {}, a file of the case that granstack's own commands write", text, file),
                "write to a file name of your own");
      }
    }
  }

  bool is_reference_command(const Words& w) const {
    const auto acts = acts_on().find(w[0]);
    if (acts != acts_on().end()) return w.size() >= 2 && r_.named.count({acts->second, w[1]}) != 0;
    return r_.held.count(w[0]) != 0;
  }

  // Every command of granstack's deck ran at least once.
  void missing(const ExecutedScript& ran) {
    // Most commands ran as written: found by their text at once; a number written otherwise
    // (1e-7 for 1.0e-07) is looked for word by word.
    std::set<std::string> texts;
    for (const auto& e : ran.commands) texts.insert(joined(e.words));
    const auto ran_one = [&](const Words& r) {
      return texts.count(joined(r)) != 0 ||
             std::any_of(ran.commands.begin(), ran.commands.end(), [&](const ExecutedCommand& e) { return same_words(e.words, r); });
    };
    const auto say = [&](const Words& r) {
      problem(c_.files().deck, fmt::format("the deck never ran '{}', which granstack's deck runs for this case", joined(r)),
              kPlaceholders);
    };
    for (const auto& [command, list] : r_.held) {
      for (const auto& r : list) {
        if (!ran_one(r)) say(r);
      }
    }
    for (const auto& [name, list] : r_.named) {
      if (std::none_of(list.begin(), list.end(), ran_one)) say(list.front());
    }
    for (const auto& [file, list] : r_.prints) {
      for (const auto& r : list) {
        if (!ran_one(r)) say(r);
      }
    }
  }

  // The case's run: its steps once, or (stopping at the blow's end) one dump interval at a time
  // up to the cap.
  void runs(const ExecutedScript& ran) {
    long count = 0;
    for (const auto& e : ran.commands) count += e.words[0] == "run" ? 1 : 0;
    const auto& d = c_.derived();
    if (count == 0) {
      problem(c_.files().deck, fmt::format("the deck ran no '{}'", joined(r_.run)), kPlaceholders);
    } else if (c_.spec().stop == model::StopRule::duration && count != 1) {
      problem(c_.files().deck, fmt::format("the deck ran '{}' {} times: the case runs its {} steps once", joined(r_.run),
                                           count, d.steps),
              kPlaceholders);
    } else if (count * d.dump_every > d.steps) {
      problem(c_.files().deck, fmt::format("the deck ran {} runs of {} steps, past the case's cap of {} steps", count,
                                           d.dump_every, d.steps),
              kPlaceholders);
    }
  }

  const Case& c_;
  Reference r_;
  std::set<std::string> own_;
  std::string dumps_;
  std::set<std::string> additions_;
  DeckVerdict verdict_;
};

}  // namespace

DeckVerdict hold_executed(const Case& c, const ExecutedScript& ran, std::string_view reference) {
  Judge judge(c, reference);
  // A command's judgement depends on its words alone, which its text gives: one found right is not
  // judged again when a loop runs it again (a blow-end deck repeats its loop once per dump interval).
  std::unordered_set<std::string_view> right;
  for (const auto& e : ran.commands) {
    if (right.count(e.text) != 0) continue;
    const auto before = judge.findings();
    judge.command(e.words, joined(e.words), e.where());
    if (judge.findings() == before) right.insert(e.text);
  }
  if (!ran.complete) {
    DeckVerdict v = judge.take();
    v.problems.push_back({ran.commands.empty() ? c.files().deck : ran.commands.back().where(), ran.stopped,
                          ran.unfollowable ? "write out the commands it stands for, or take it out"
                                           : "run the case again (the log must be the whole run's)"});
    return v;
  }
  judge.whole_run(ran);
  return judge.take();
}

DeckVerdict hold_literal(const Case& c, std::string_view deck, const std::string& name, std::string_view reference) {
  Judge judge(c, reference);
  const auto one = [&](const std::string& text, long line) {
    if (text.find('$') != std::string::npos) return;  // its values are known when it runs
    const auto words = script_words(text);
    if (words && !words->empty()) judge.command(*words, joined(*words), fmt::format("{}:{}", name, line));
  };
  for (const auto& line : script_lines(deck)) {
    const std::string text(without_comment(line.text));
    const auto words = script_words(text);
    if (words && words->size() > 3 && (*words)[0] == "if") {
      for (std::size_t i = 3; i < words->size(); ++i) {
        if ((*words)[i] != "elif" && (*words)[i] != "else" && (*words)[i - 1] != "elif") one((*words)[i], line.line);
      }
      continue;
    }
    one(text, line.line);
  }
  return judge.take();
}

}  // namespace granstack::formats
