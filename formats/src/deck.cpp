#include <granstack/formats/case.hpp>
#include <granstack/formats/deck.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/line_reader.hpp>

#include <fmt/format.h>

#include <filesystem>
#include <set>
#include <vector>

namespace granstack::formats {

void check_rendered_files(const std::string& case_dir, const Manifest& manifest) {
  const auto check = [&](const std::string& name, const std::string& recorded, const char* what) {
    const auto path = (std::filesystem::path(case_dir) / name).string();
    const auto now = sha256_file(path);
    if (now == recorded) return;
    throw FormatError(path, 0, fmt::format(
        "the {} was edited after 'granstack generate' (SHA-256 {}, the manifest recorded {}), so its results would "
        "carry the manifest's labels, not the physics it holds; generate the case again with the values you want, or "
        "render a deck of your own with 'granstack generate --template FILE'",
        what, now.substr(0, 12), recorded.substr(0, 12)));
  };
  check(manifest.files.deck, manifest.rendered.deck_sha256, "deck");
  check(manifest.files.data, manifest.rendered.data_sha256, "data file");
}

namespace {
// The contact model words of a pair_style or wall/gran line (from `first` up to 'primitive', 'mesh'
// or the end) against the manifest's: a deck edited to another model would be labelled wrongly.
void check_contact_model(const std::vector<std::string_view>& words, std::size_t first, const std::string& expected,
                         const std::string& path, long line) {
  std::string found;
  for (std::size_t k = first; k < words.size() && words[k] != "primitive" && words[k] != "mesh" && words[k].front() != '#';
       ++k) {
    if (!found.empty()) found += ' ';
    found += words[k];
  }
  if (found == expected) return;
  throw FormatError(path, line, fmt::format("the deck's contact model is '{}', the manifest's is '{}'; the deck was "
                                            "edited after 'granstack generate': generate the case again with the "
                                            "model you want (--normal-model, --tangential-model, --rolling-model)",
                                            found, expected));
}

// The time step and the runs of a deck against the manifest's dt and steps (`fix` says how to
// mend a difference): the same for LIGGGHTS's deck and LAMMPS's.
class RunCheck {
 public:
  RunCheck(const Case& c, std::string path, std::string fix)
      : c_(c), path_(std::move(path)), fix_(std::move(fix)), cap_(fmt::format("$(step<{})", c.derived().steps)) {}
  // One line's words; true when the line was a timestep or a run.
  bool line(const std::vector<std::string_view>& words, std::string_view text, long number) {
    capped_ = capped_ || text.find(cap_) != std::string_view::npos;
    if (words[0] == "timestep") {
      double value = 0.0;
      if (!parse_double(words[1], value) || value != c_.derived().dt) {
        throw FormatError(path_, number, fmt::format("the time step is {}, the manifest's dt is {}{}", words[1], c_.derived().dt, fix_));
      }
      timestep_line_ = number;
      return true;
    }
    if (words[0] == "run") {
      if (!parse_long(words[1], run_steps_)) run_steps_ = -1;
      run_line_ = number;
      return true;
    }
    return false;
  }
  void finish() const {
    const double dt = c_.derived().dt;
    const long steps = c_.derived().steps;
    if (timestep_line_ == 0) throw FormatError(path_, 0, fmt::format("no 'timestep' line (the manifest's dt is {})", dt));
    if (run_line_ == 0) throw FormatError(path_, 0, fmt::format("no 'run' line (the manifest has {} steps)", steps));
    // A case that stops at the blow's end runs one dump interval at a time, up to its cap.
    if (c_.spec().stop == model::StopRule::blow_end) {
      if (run_steps_ != c_.derived().dump_every || !capped_) {
        throw FormatError(path_, run_line_, fmt::format("the deck does not run one dump interval ({} steps) at a time up "
                                                        "to the manifest's cap of {} steps, as a case that stops at the "
                                                        "blow's end does{}",
                                                        c_.derived().dump_every, steps, fix_));
      }
    } else if (run_steps_ != steps) {
      throw FormatError(path_, run_line_, fmt::format("the deck runs {} steps, the manifest has {}{}",
                                                      run_steps_ < 0 ? "an unknown number of" : std::to_string(run_steps_),
                                                      steps, fix_));
    }
  }

 private:
  const Case& c_;
  std::string path_, fix_, cap_;
  long timestep_line_ = 0, run_line_ = 0, run_steps_ = -1;
  bool capped_ = false;
};

}  // namespace

void check_deck_matches_manifest(const Case& c) {
  const auto& manifest = c.manifest();
  check_rendered_files(c.dir(), manifest);
  const auto path = c.path(manifest.files.deck).string();
  const auto model_words = model::liggghts_model_words(manifest.spec.contact_model());
  RunCheck runs(c, path, "; the deck was edited after 'granstack generate': generate the case again with the values you "
                         "want (--dt, --duration) instead");
  LineReader reader(path);
  std::string_view line;
  std::vector<std::string_view> words;
  while (reader.next(line)) {
    split_words(line, words);
    if (words.size() < 2 || words[0].front() == '#') continue;
    if (runs.line(words, line, reader.line_number())) continue;
    if (words[0] == "pair_style" || (words[0] == "fix" && words.size() > 3 && words[3] == "wall/gran")) {
      check_contact_model(words, words[0] == "pair_style" ? 2 : 4, model_words, path, reader.line_number());
    }
  }
  runs.finish();
}

}  // namespace granstack::formats
