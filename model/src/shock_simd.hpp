#pragma once
// The shock response spectrum's oscillators, all natural frequencies in one pass over the samples
// (shock_simd.cpp, Google Highway: a lane per frequency).
#include <cstddef>
#include <vector>

namespace granstack::model::detail {

// Oscillators side by side, one per frequency, each stepped over a sample interval exactly for a
// base acceleration linear between samples: z' = P z + c a_before + d a_after (z: relative
// displacement and velocity), its absolute acceleration o . z'. Each array holds a value per
// oscillator; `count` is a whole number of kOscillatorLanes, the last ones repeating a real one.
inline constexpr std::size_t kOscillatorLanes = 8;
struct Oscillators {
  std::vector<double> p00, p01, p10, p11, c0, c1, d0, d1, o0, o1;
  std::size_t count = 0;
};
// Every oscillator from rest and a base at zero through the samples `base[0..n)`: its largest
// |acceleration| at the samples into `peak`, its state after the last into `z0`, `z1` (each
// `count` long). Every instruction set gives the same bits: each lane does the same exactly
// rounded operations in the same order, none fused.
void run_oscillators(const Oscillators& o, const double* base, std::size_t n, double* z0, double* z1, double* peak);

}  // namespace granstack::model::detail
