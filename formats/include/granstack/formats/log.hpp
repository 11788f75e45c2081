#pragma once
// What granstack needs from LIGGGHTS's screen output and log file (liggghts-3.8.md section 9):
// the version banner, thermo progress, errors, warnings, lost atoms and the loop time.
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

class LogScanner {
 public:
  // Feed the output line by line, as it arrives.
  void add_line(std::string_view line);
  void add_text(std::string_view text);  // several lines

  const std::string& version() const { return version_; }  // e.g. "LIGGGHTS-PUBLIC 3.8.0, compiled ..."
  const std::vector<std::string>& errors() const { return errors_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  bool lost_atoms() const { return lost_atoms_; }
  std::optional<long> last_step() const { return last_step_; }  // of the last thermo row seen
  const std::optional<LoopTime>& loop_time() const { return loop_; }
  // Every thermo block, one per run command.
  const std::vector<ThermoBlock>& thermo() const { return thermo_; }

 private:
  std::string version_;
  std::vector<std::string> errors_;
  std::vector<std::string> warnings_;
  bool lost_atoms_ = false;
  bool in_thermo_ = false;
  std::optional<long> last_step_;
  std::optional<LoopTime> loop_;
  std::vector<ThermoBlock> thermo_;
};

// Reads a LIGGGHTS log or screen file. Throws FormatError when it cannot be opened.
LogScanner read_log(const std::string& path);

}  // namespace granstack::formats
