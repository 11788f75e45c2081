#pragma once
// Energies of one dump frame, grouped as the study measures them (physics.md section 4).
#include <granstack/formats/dump.hpp>
#include <granstack/model/contact_candidates.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/yield.hpp>
#include <granstack/model/stack.hpp>

#include <memory>
#include <vector>

namespace granstack::postproc {

struct FrameEnergy {
  long step = 0;
  std::vector<double> block_ke;  // translational + rotational, index 0 = block 1 (top)
  // Its parts: translational sideways (x, y), translational downward (z), rotational.
  std::vector<double> block_ke_sideways, block_ke_downward, block_ke_rotational;
  // Per row and per column of each block (translational + rotational), [block - 1][row - 1]; a
  // column (along x) sums every y-column in a 3D nest (every panel in a container), whose
  // y-columns (along y, summing every x-column) are column_y_ke (one per block, the whole block,
  // in the strip; one per panel in a container). A container's matrix is in none of them.
  std::vector<std::vector<double>> row_ke, column_ke, column_y_ke;
  double matrix_ke = 0.0;        // a container's matrix spheres
  // The friction study's quantities: the top row of the top block, 1/2 m vx^2 (+ vy^2) against
  // 1/2 m vz^2 (physics.md section 4).
  double top_row_sideways = 0.0, top_row_downward = 0.0;
  double striker_ke = 0.0;
  double striker_vz = 0.0;       // m/s, the striker's velocity along z (negative: moving down)
  model::Crush crush;            // this frame's crush and penetration (model::CrushMeter::at)
  model::YieldPeak yield;        // this frame's largest contact pressure over first yield (model::YieldMeter::at)
  // What model::BlowEnd reads: what is over the footprint (with a bottom wall); the output sphere
  // touching no other, and another on course to hit it.
  model::OverFootprint over_footprint;
  bool output_free = false;
  bool output_threatened = false;  // another sphere on course to hit it (model::on_collision_course)
  model::StrikerCourse striker;     // model::striker_course
  double output_sphere_ke = 0.0;
  double bottom_row_ke = 0.0;
  double bottom_row_max_ke = 0.0;  // the most energetic sphere of the bottom row
  double kinetic = 0.0;          // everything
  double momentum_z = 0.0;       // kg m/s: every sphere's m vz, summed in id order (up positive)
  double elastic = 0.0;          // elastic energy of every overlapping pair (and sphere-wall contact), the contact model's
};

// Maps the frame's rows to sphere ids and checks them against the stack: every id present
// exactly once. Throws FormatError naming the frame otherwise.
class FrameView {
 public:
  FrameView(const model::Stack& stack, const std::string& path);
  // The dump columns the energies need (a reader may leave the others unparsed).
  static const std::vector<std::string>& needed_columns();
  // Throws FormatError naming file, line, step, atom and column at the first NaN or inf.
  void require_finite(const formats::DumpFrame& frame) const;
  // Binds a frame (checking every value finite); returns the row of each id (index id - 1).
  void bind(const formats::DumpFrame& frame);
  long row(int id) const { return rows_[static_cast<std::size_t>(id - 1)]; }

  // 1/2 m v^2 + 1/2 (2/5 m R^2) w^2, and the rotational part alone.
  double kinetic_energy(const formats::DumpFrame& f, long row) const;
  double rotational_energy(const formats::DumpFrame& f, long row) const;
  double translational_energy(const formats::DumpFrame& f, long row) const;

 private:
  const model::Stack& stack_;
  std::string path_;
  std::vector<long> rows_;
  int c_id_ = -1, c_mass_ = -1, c_radius_ = -1, c_vx_ = -1, c_vy_ = -1, c_vz_ = -1, c_wx_ = -1, c_wy_ = -1, c_wz_ = -1;
  int c_x_ = -1, c_y_ = -1, c_z_ = -1;
  friend class FrameAnalyser;
};

// The energies of the frames of one case, frame after frame: what stays the same (Hertz
// parameters, the group of every sphere) is worked out once, and the contact candidates are
// kept between frames. Not thread-safe: one per thread.
class FrameAnalyser {
 public:
  FrameAnalyser(const model::Stack& stack, const std::string& path);
  FrameAnalyser(const FrameAnalyser&) = delete;
  FrameAnalyser& operator=(const FrameAnalyser&) = delete;
  ~FrameAnalyser();
  // Binds the frame (checking its ids; FormatError otherwise) and fills `e`, reusing its storage;
  // over a protected plate, displaced by `plate_z` and moving at `plate_vz` at the frame's step.
  void analyse(const formats::DumpFrame& frame, FrameEnergy& e, double plate_z = 0.0, double plate_vz = 0.0);
  // The view of the frame last analysed.
  const FrameView& view() const { return view_; }
  // Whether sphere `id` has separated in the frame last analysed: the elastic energy left in its
  // contacts (with spheres and walls) is at most kSeparatedContactEnergy of its kinetic energy.
  bool has_separated(const formats::DumpFrame& frame, int id) const;
  long candidate_builds() const { return candidates_.builds(); }

 private:
  struct Constants;
  const model::Stack& stack_;
  FrameView view_;
  model::ContactCandidates candidates_;
  std::unique_ptr<Constants> constants_;
  std::vector<double> x_, y_, z_, vx_, vy_, vz_, m_, r_;  // as the frame has them
  double plate_z_ = 0.0;  // the protected plate's displacement at that frame
};

// A sphere has separated (FrameAnalyser::has_separated) when the elastic energy left in its
// contacts can change its kinetic energy by less than this fraction. (Exactly touching neighbours that leave together keep a
// round-off overlap of ~1e-14 m, whose energy is ~1e-21 J: a count of overlaps would call them
// touching forever.)
inline constexpr double kSeparatedContactEnergy = 1e-6;

}  // namespace granstack::postproc
