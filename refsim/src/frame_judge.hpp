#pragma once
// What refsim reads from its own state at a dump frame for the blow's end (model::BlowEnd) and the
// crush, the same quantities, summed in the same order, as reduce reads from the dump and the
// generated deck computes in LIGGGHTS: the in-situ run and the case run share them.
#include <granstack/model/contact_candidates.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/model/yield.hpp>
#include <granstack/refsim/system.hpp>

#include <cstddef>
#include <vector>

namespace granstack::refsim::detail {

// Whether sphere i overlaps no other (positions at the current step).
bool touches_nothing(const System& s, std::size_t i);
// Whether any sphere is on course to hit sphere i (model::on_collision_course).
bool threatened(const System& s, std::size_t i);
// The momentum along z of every sphere, in id order.
double momentum_z(const System& s);
// The crush and penetration at the system's current step (model::CrushMeter::at).
model::Crush crush_at(const model::CrushMeter& meter, const System& s);
// The contact pressures over first yield at the system's current step (model::YieldMeter::at), from
// the same candidate pairs reduce finds in the dump's frames; the meter keeps the run's largest.
class FramePressures {
 public:
  explicit FramePressures(const model::Stack& stack) : meter_(stack), candidates_(stack) {}
  void add(const System& s);
  const model::YieldMeter& meter() const { return meter_; }

 private:
  model::YieldMeter meter_;
  model::ContactCandidates candidates_;
  std::vector<double> x_, y_, z_;
};
// Gives `blow` the frame at the system's current step: what is over the footprint with a bottom
// wall, whether the output sphere is free and threatened with a free bottom.
void judge_blow_end(model::BlowEnd& blow, const model::Stack& stack, const System& s);

}  // namespace granstack::refsim::detail
