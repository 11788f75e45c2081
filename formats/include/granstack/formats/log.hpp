#pragma once
// What granstack needs from LIGGGHTS's screen output and log file (docs/liggghts.md section 9):
// the version banner, thermo progress, errors, warnings, lost atoms and the loop time.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

// One thermo block: the header line's column names and the rows of numbers under it.
struct ThermoBlock {
  std::vector<std::string> columns;  // e.g. Step Atoms KinEng CPU
  std::vector<std::vector<double>> rows;
};

struct LoopTime {
  double seconds = 0.0;
  int procs = 0;
  long steps = 0;
  long atoms = 0;
};

// A per-rank count of LIGGGHTS's run summary ("Nlocal:    6120.06 ave 7812 max 4644 min").
struct RankSpread {
  double mean = 0.0, max = 0.0, min = 0.0;
};

class LogScanner {
 public:
  // Feed the output line by line, as it arrives.
  void add_line(std::string_view line);
  void add_text(std::string_view text);  // several lines

  const std::string& version() const { return version_; }  // e.g. "LIGGGHTS-PUBLIC 3.8.0, compiled ..."
  const std::vector<std::string>& errors() const { return errors_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  bool lost_atoms() const { return lost_atoms_; }
  // LIGGGHTS caught SIGINT or SIGTERM and quit early (writing a forced restart).
  bool stopped_by_signal() const { return stopped_by_signal_; }
  std::optional<long> last_step() const { return last_step_; }  // of the last thermo row seen
  // The deck's runs together: their seconds and steps summed (a case that stops at the blow's
  // end runs one dump interval at a time, a "Loop time" line each), the last one's atoms and ranks.
  const std::optional<LoopTime>& loop_time() const { return loop_; }
  // The MPI processor grid LIGGGHTS chose or was given ("4 by 4 by 1 MPI processor grid").
  const std::optional<std::array<int, 3>>& processor_grid() const { return grid_; }
  // Owned (Nlocal) and ghost (Nghost) atoms per rank at the end of the last run.
  const std::optional<RankSpread>& owned_per_rank() const { return owned_; }
  const std::optional<RankSpread>& ghosts_per_rank() const { return ghosts_; }
  // Every thermo block, one per run command.
  const std::vector<ThermoBlock>& thermo() const { return thermo_; }
  // The first and the last few lines of text seen (at most kQuoteLines each; blank lines and
  // rules of dashes left out), oldest first: what to quote for a failure that printed no ERROR
  // line. An MPI start-up failure says what went wrong first; a crash says it last.
  static constexpr std::size_t kQuoteLines = 6;
  const std::vector<std::string>& head() const { return head_; }
  std::vector<std::string> tail() const;

 private:
  bool scan_decomposition(const std::vector<std::string_view>& words);
  std::string version_;
  std::vector<std::string> errors_;
  std::vector<std::string> warnings_;
  bool lost_atoms_ = false;
  bool stopped_by_signal_ = false;
  bool in_thermo_ = false;
  std::optional<long> last_step_;
  std::optional<LoopTime> loop_;
  std::optional<std::array<int, 3>> grid_;
  std::optional<RankSpread> owned_, ghosts_;
  std::vector<ThermoBlock> thermo_;
  std::vector<std::string> head_;
  std::vector<std::string> tail_;  // ring of kQuoteLines entries
  std::size_t tail_next_ = 0;
};

// Reads a LIGGGHTS log or screen file. Throws FormatError when it cannot be opened.
LogScanner read_log(const std::string& path);

}  // namespace granstack::formats
