#pragma once
// What refsim composes a contact of (sub_models.hpp): a frame, a normal model with its damping,
// a tangential model and a rolling model, each a scalar kernel in a file of its own in this
// folder. An engine's contact rules are a choice of these, made once per run (rules_for), not a
// flag the kernels test: LIGGGHTS's pair style and fix wall/gran, or LAMMPS's pair_style granular
// and fix wall/gran granular as granstack's LAMMPS deck sets them (model/lammps.hpp).
#include <cstddef>
#include <cstdint>

#include <granstack/model/contact.hpp>

namespace granstack::refsim::detail {

// The contact's geometry as the engine forms it (frame_liggghts.cpp, frame_lammps.cpp): the
// normal, the contact point's sliding velocity, the torque's lever arms, when a pair forgets its
// history, when a sphere touches a wall, and the wall force kept for the stored wall.
enum class Frame : std::uint8_t { liggghts, lammps };
// The normal force with its damping, and the tangential stiffness and damping it sets for the
// tangential model: by LIGGGHTS's rules the spec's normal model's kernel (composition.cpp's table,
// one row per model::NormalModel); by LAMMPS's, hertz/material with tsuji damping (normal_tsuji.cpp).
struct SubModels {
  Frame frame = Frame::liggghts;
  model::NormalModel normal = model::NormalModel::hertz;
  // The spec's tangential model, whose kernel is its frame's (composition.cpp's tables): by
  // LIGGGHTS's rules history and no_history; by LAMMPS's, history is its mindlin
  // (linear_nohistory 0 0, which gives no force, where the pair has no friction), and
  // mindlin_rescale its own.
  model::TangentialModel tangential = model::TangentialModel::history;
  // LIGGGHTS's rolling models, by the spec's own name (LAMMPS's deck has none): a kernel each,
  // in composition.cpp's table.
  model::RollingModel rolling = model::RollingModel::off;
  bool operator==(const SubModels&) const = default;
  // LIGGGHTS's hertz/history without rolling friction, the study's: the only choice the vector
  // kernels (contacts_simd.cpp) run, held to this composition to the bit.
  bool vector_kernels_run() const { return *this == SubModels{}; }
};

// Where each sub-model's per-contact history lies in a contact's history, and its length: each
// kernel declares how many values it keeps (composition.cpp's tables), and the pair table and the
// walls carry that many per contact, forgotten together.
struct HistoryLayout {
  std::size_t tangential = 0, rolling = 0, normal = 0, size = 0;
};
inline constexpr std::size_t kMaxHistory = 24;  // the most any choice keeps (checked)
HistoryLayout history_layout(const SubModels& s);

// The spec's model as LIGGGHTS runs it.
SubModels liggghts_rules(const model::ContactModel& m);
// (LIGGGHTS's refusal of a model it lacks, model/contact.hpp's rows, is thrown as
// std::invalid_argument.)
// ... as granstack's LAMMPS deck runs it: hertz with history or mindlin_rescale, without rolling
// friction (LAMMPS's refusal of the others is thrown likewise).
SubModels lammps_rules(const model::ContactModel& m);

}  // namespace granstack::refsim::detail
