#pragma once
// Exponential decay with depth, E_out/E_in = A exp(-alpha N_B) (docs/physics.md section 4),
// fitted by least squares on the logarithm (least_squares.hpp).
#include <optional>
#include <vector>

namespace granstack::postproc {

struct DecayFit {
  int points = 0;
  // Free prefactor: ln f = ln A - alpha N.
  double alpha = 0.0;
  std::optional<double> alpha_error;  // standard error; none with fewer than 3 points
  double prefactor = 0.0;             // A
  std::optional<double> prefactor_error;
  std::optional<double> covariance_ln_prefactor_alpha;  // cov(ln A, alpha); none with fewer than 3 points
  // Through the origin (A = 1): ln f = -alpha N.
  double alpha_origin = 0.0;
  std::optional<double> alpha_origin_error;  // none with fewer than 2 points
};

// Fits (N_B, fraction) pairs; fractions must be > 0 and at least two distinct N_B are needed.
// Throws std::invalid_argument otherwise.
DecayFit fit_decay(const std::vector<int>& blocks, const std::vector<double>& fractions);

}  // namespace granstack::postproc
