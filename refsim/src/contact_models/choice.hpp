#pragma once
// What refsim composes a contact of (sub_models.hpp): a frame, a normal model with its damping,
// a tangential model and a rolling model, each a scalar kernel in a file of its own in this
// folder. An engine's contact rules are a choice of these, made once per run (rules_for), not a
// flag the kernels test: LIGGGHTS's pair style and fix wall/gran, or LAMMPS's pair_style granular
// and fix wall/gran granular as granstack's LAMMPS deck sets them (model/lammps.hpp).
#include <cstdint>

#include <granstack/model/contact.hpp>

namespace granstack::refsim::detail {

// The contact's geometry as the engine forms it (frame_liggghts.cpp, frame_lammps.cpp): the
// normal, the contact point's sliding velocity, the torque's lever arms, when a pair forgets its
// history, when a sphere touches a wall, and the wall force kept for the stored wall.
enum class Frame : std::uint8_t { liggghts, lammps };
// The normal force with its damping, and the tangential stiffness and damping it sets for the
// tangential model: LIGGGHTS's hertz and hooke (restitution damping), LAMMPS's hertz/material
// with tsuji damping (normal_tsuji.cpp).
enum class NormalKernel : std::uint8_t { hertz, hooke, hertz_material_tsuji };

struct SubModels {
  Frame frame = Frame::liggghts;
  NormalKernel normal = NormalKernel::hertz;
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

// The spec's model as LIGGGHTS runs it.
SubModels liggghts_rules(const model::ContactModel& m);
// (LIGGGHTS's refusal of a model it lacks, model/contact.hpp's rows, is thrown as
// std::invalid_argument.)
// ... as granstack's LAMMPS deck runs it: hertz with history or mindlin_rescale, without rolling
// friction (LAMMPS's refusal of the others is thrown likewise).
SubModels lammps_rules(const model::ContactModel& m);

}  // namespace granstack::refsim::detail
