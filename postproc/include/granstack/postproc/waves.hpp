#pragma once
// Solitary waves in each block (physics.md sections 4 and 5): how many distinct peaks the
// block's energy curve has, and the leading wave's speed, peak force and width down a central
// column, against Nesterenko's law.
#include <granstack/formats/dump.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/energy.hpp>

#include <optional>
#include <string>
#include <vector>

namespace granstack::postproc {

// A local maximum counts as a peak when its prominence (its height above the higher of the
// lowest points between it and a higher point on either side) is at least this fraction of
// the curve's maximum.
inline constexpr double kPeakProminence = 0.05;

// Local maxima of `y` with prominence >= min_prominence, by index.
std::vector<std::size_t> prominent_peaks(const std::vector<double>& y, double min_prominence);

// A solitary wave moves at Nesterenko's speed for its peak force (0.992 of it in a 30-row block,
// Physics.LeadingWaveFollowsNesterenko; within 5 % in the 24-row sandwich and its all-steel
// control, Physics.TheLowestSteelBlockOfTheSandwichCarriesASolitaryWaveBelowItsEntrance). A
// leading pulse outside this band is no solitary wave: no speed is given for it.
inline constexpr double kSolitaryWaveBand[2] = {0.8, 1.25};

// A row's leading pulse is its first speed maximum reaching this fraction of the row's largest
// speed: the maxima before it are round-off (1e-15 of it), and a later blow can be twice the
// leading pulse or more (rows 5 to 9 of the sandwich's lowest steel block at 24 rows).
inline constexpr double kLeadingPulseFraction = 0.1;

// That rule in words, as the study's record of a claim reading a wave speed writes it.
std::string leading_pulse_rule();

struct BlockWaves {
  int block = 0;                   // 1 = top
  int peaks = 0;                   // of the block's KE curve (in-situ series), kPeakProminence rule
  // Pulses passing the middle row of the impact path's column: the prominent maxima (same rule)
  // of that sphere's kinetic energy (middle_ke). A block's total energy can rise to a
  // plateau with no maximum while a train of waves runs through it (a Teflon block under steel).
  int pulses = 0;
  int column = 0;                  // the impact path's column followed (model::Stack::impact_column)
  // The kinetic energy of that middle-row sphere (model::Stack::middle_path_id), away from the
  // block's interfaces, from the in-situ series (the dump frames for a case whose series lacks
  // it): its largest value, and its first prominent maximum (the leading wave's), J.
  double middle_peak_ke = 0.0;
  double middle_leading_ke = 0.0;
  std::vector<double> middle_time, middle_ke;  // s, J: that sphere's energy over time
  int rows_used = 0;               // rows whose leading pulse was timed
  int rows_entrance = 0;           // rows 1 to this one are entrance, left out: the leading pulse
                                   // reaches a deeper row no later than one of them
  std::optional<double> speed;     // m/s, least squares of the leading pulse's arrival time against
                                   // depth, the rows below the entrance; none when the dumps
                                   // sample a row crossing less than twice, when fewer than 3 rows
                                   // are below the entrance, or when it is no solitary wave
  bool no_solitary_wave = false;   // the leading pulse's speed is outside kSolitaryWaveBand
  std::optional<double> maximum_speed;  // m/s: the leading pulse's speed, timed as `speed`,
                                        // given even when it is no solitary wave
  double peak_force = 0.0;         // N, largest Hertz force between vertical neighbours of the column
  std::optional<double> nesterenko_speed;  // m/s, for that force (physics.md section 5)
  std::optional<double> width;     // diameters: the cos^4 support with the same RMS width as the
                                   // column's overlaps when the wave is at its middle row
  std::string note;                // why a value is missing
};

// Needs a case that has run; the dumps set the time resolution of the speed (a few frames per
// row crossing: see --dump-every). Throws like reduce_case.
std::vector<BlockWaves> analyse_waves(const std::string& case_dir);

// The same, fed one frame at a time, so reduce reads the dump once. Memory does not grow with
// the number of frames: of each row's speed curve it keeps the running maximum and the local
// maxima that are higher than every earlier one (only those can be the first to reach a fraction
// of the final maximum, kLeadingPulseFraction), with the column's overlaps at each of the middle
// row's.
class WaveTracker {
 public:
  WaveTracker(const model::Stack& stack, double dt);
  // What add() needs of one bound frame: the speed of each sphere of the followed columns and the
  // overlap of each pair of vertical neighbours. Const, so worker threads can call it.
  void sample(const formats::DumpFrame& frame, const FrameView& view, std::vector<double>& samples) const;
  // The frames' samples, in frame order.
  void add(long step, const std::vector<double>& samples);
  void add(const formats::DumpFrame& frame, const FrameView& view);
  // `series` gives the peaks of each block's energy curve.
  std::vector<BlockWaves> finish(const formats::Series& series) const;

 private:
  void middle_sphere(BlockWaves& w, const formats::Series& series, int k) const;
  struct Column;
  struct Arrivals {
    std::vector<double> depth, arrival;  // m, s: the rows below the entrance
    int entrance = 0;                    // the deepest entrance row (0: none)
    const std::vector<double>* middle_overlaps = nullptr;  // at the middle row's arrival, if timed
  };
  static Arrivals leading_pulse_arrivals(const Column& c, double diameter, long frames);
  struct Maximum {
    double speed = 0.0, time = 0.0;
    std::vector<double> overlaps;  // the column's, at this frame (middle row only)
  };
  struct Row {
    double top = 0.0;              // largest speed so far
    double before = 0.0, last = 0.0;  // the speeds of the last two frames
    std::vector<Maximum> records;  // local maxima, each higher than every earlier one
  };
  struct Column {
    std::vector<int> ids;         // rows top to bottom
    std::vector<double> radius_sum;  // of rows i and i + 1
    std::size_t offset = 0;       // of its speeds in a frame's samples; its overlaps follow
    std::vector<Row> rows;
    std::vector<double> middle_energy;  // speed^2 of the middle row's sphere, every frame
    std::vector<double> overlaps, overlaps_before;  // the last two frames'
    double max_overlap = 0.0;
  };
  const model::Stack& stack_;
  double dt_;
  std::vector<Column> columns_;
  std::size_t samples_per_frame_ = 0;
  long frames_ = 0;
  double times_[3] = {0.0, 0.0, 0.0};  // of the last three frames, the newest last
  double first_interval_ = 0.0;        // between the first two frames
  std::vector<double> frame_times_;    // of every frame
  std::vector<double> scratch_;
};

}  // namespace granstack::postproc
