#pragma once
// What the protected object under a stack takes from a blow: granstack's protection measures
// (docs/physics.md section 7). The protected object is the bottom wall, a rigid force sensor of
// the footprint's size, the same for every design of a space. Each measure is one function here,
// fed the same samples by refsim's in-situ run and by reduce of a LIGGGHTS or refsim case, so the
// two engines give the same number from the same run.
#include <granstack/model/stack.hpp>

#include <vector>

namespace granstack::model {

// The largest impulse (N s) the wall takes in a window of `window` seconds: the peak over the
// samples' times t of the integral of F from t to t + window, F linear between its samples. `force` holds the
// wall's force every `interval` seconds (the series' samples, from one interval after the start).
// A window longer than the samples gives the whole run's impulse. Over the mean force it is what
// a body behind the wall feels as a sustained load, where the peak force is what breaks it.
double peak_window_impulse(const std::vector<double>& force, double interval, double window);

// The stroke: how far the striker travels below where it started, the largest over the samples
// it is given (the dump's frames in both engines). Against a wall it is the stack's crush under
// the blow (its compression plus the striker's own indentation): a soft stack lowers every force
// measure by a longer stroke, so the stroke is what a force objective is traded against.
class StrokeMeter {
 public:
  explicit StrokeMeter(const Stack& stack);
  // The lowest z of any striker at one sample (m).
  void sample(double lowest_striker_z);
  double stroke() const { return stroke_; }  // m, >= 0

 private:
  double start_z_ = 0.0;
  double stroke_ = 0.0;
};

}  // namespace granstack::model
