#include <granstack/formats/line_reader.hpp>
#include <granstack/formats/log.hpp>

namespace granstack::formats {

namespace {
// "Loop time of SECONDS on PROCS procs[ (R MPI x T OpenMP)] for STEPS steps with ATOMS atoms[, finish
// time ...]" (finish.cpp); a blow-end run prints one per dump interval.
std::optional<LoopTime> loop_line(std::string_view line) {
  std::vector<std::string_view> w;
  split_words(line, w);
  if (w.size() < 13 || w[4] != "on" || w[6].substr(0, 5) != "procs") return std::nullopt;
  LoopTime t;
  long procs = 0;
  if (!parse_double(w[3], t.seconds) || !parse_long(w[5], procs)) return std::nullopt;
  t.procs = static_cast<int>(procs);
  // The last "for N steps with M atoms" (LIGGGHTS goes on: "atoms, finish time ...").
  for (std::size_t k = w.size() - 6;; --k) {
    if (w[k] == "for" && w[k + 2] == "steps" && w[k + 3] == "with" && w[k + 5].substr(0, 5) == "atoms" &&
        parse_long(w[k + 1], t.steps) && parse_long(w[k + 4], t.atoms)) {
      return t;
    }
    if (k == 7) return std::nullopt;
  }
}
}  // namespace

void LogScanner::add_text(std::string_view text) {
  while (!text.empty()) {
    auto nl = text.find('\n');
    add_line(text.substr(0, nl));
    if (nl == std::string_view::npos) break;
    text.remove_prefix(nl + 1);
  }
}

std::vector<std::string> LogScanner::tail() const {
  std::vector<std::string> out;
  for (std::size_t k = 0; k < tail_.size(); ++k) out.push_back(tail_[(tail_next_ + k) % tail_.size()]);
  return out;
}

void LogScanner::add_line(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (line.find_first_not_of(" \t-") != std::string_view::npos) {
    if (head_.size() < kQuoteLines) head_.emplace_back(line);
    if (tail_.size() < kQuoteLines) {
      tail_.emplace_back(line);
    } else {
      tail_[tail_next_] = std::string(line);
      tail_next_ = (tail_next_ + 1) % kQuoteLines;
    }
  }
  // LIGGGHTS's banner, "LIGGGHTS (Version ...)", or LAMMPS's, "LAMMPS (29 Sep 2021 - Update 2)".
  for (const std::string_view banner : {std::string_view("LIGGGHTS (Version "), std::string_view("LAMMPS (")}) {
    if (line.substr(0, banner.size()) != banner) continue;
    auto rest = line.substr(banner.size());
    if (auto close = rest.rfind(')'); close != std::string_view::npos) rest = rest.substr(0, close);
    version_ = std::string(rest);
    return;
  }
  if (line.substr(0, 5) == "ERROR" || line.find("MPI_ABORT was invoked") != std::string_view::npos) {
    errors_.emplace_back(line);
  } else if (line.substr(0, 7) == "WARNING") {
    warnings_.emplace_back(line);
  }
  if (line.find("Lost atoms") != std::string_view::npos) lost_atoms_ = true;
  // LIGGGHTS's own signal handler (signal_handling.cpp): it ends the run early, yet its "Loop
  // time" line still names the steps asked for.
  if (line.substr(0, 21) == "SIGINT/SIGTERM caught") stopped_by_signal_ = true;

  if (line.substr(0, 13) == "Loop time of ") {
    if (const auto t = loop_line(line)) {
      LoopTime sum = loop_.value_or(LoopTime{});
      sum.seconds += t->seconds;
      sum.procs = t->procs;
      sum.steps += t->steps;
      sum.atoms = t->atoms;
      loop_ = sum;
    }
    in_thermo_ = false;
    return;
  }
  // Thermo block: a header line starting with "Step", then rows of numbers.
  std::vector<std::string_view> words;
  split_words(line, words);
  if (scan_decomposition(words)) return;
  if (!words.empty() && words[0] == "Step") {
    in_thermo_ = true;
    thermo_.push_back({std::vector<std::string>(words.begin(), words.end()), {}});
    return;
  }
  if (in_thermo_ && !words.empty()) {
    long step = 0;
    std::vector<double> row(words.size());
    bool numbers = parse_long(words[0], step) && words.size() == thermo_.back().columns.size();
    for (std::size_t k = 0; numbers && k < words.size(); ++k) numbers = parse_double(words[k], row[k]);
    if (numbers) {
      last_step_ = step;
      thermo_.back().rows.push_back(std::move(row));
    } else {
      in_thermo_ = false;  // a warning or the end of the block
    }
  }
}

bool LogScanner::scan_decomposition(const std::vector<std::string_view>& w) {
  // "  4 by 4 by 1 MPI processor grid"
  if (w.size() == 8 && w[1] == "by" && w[3] == "by" && w[5] == "MPI" && w[7] == "grid") {
    std::array<long, 3> g{};
    if (parse_long(w[0], g[0]) && parse_long(w[2], g[1]) && parse_long(w[4], g[2])) {
      grid_ = std::array<int, 3>{static_cast<int>(g[0]), static_cast<int>(g[1]), static_cast<int>(g[2])};
      return true;
    }
  }
  // "Nlocal:    6120.06 ave 7812 max 4644 min"
  if (w.size() == 7 && (w[0] == "Nlocal:" || w[0] == "Nghost:") && w[2] == "ave" && w[4] == "max" && w[6] == "min") {
    RankSpread r;
    if (parse_double(w[1], r.mean) && parse_double(w[3], r.max) && parse_double(w[5], r.min)) {
      (w[0] == "Nlocal:" ? owned_ : ghosts_) = r;
      return true;
    }
  }
  return false;
}

LogScanner read_log(const std::string& path) {
  LineReader reader(path);
  LogScanner scanner;
  std::string_view line;
  while (reader.next(line)) scanner.add_line(line);
  return scanner;
}

}  // namespace granstack::formats
