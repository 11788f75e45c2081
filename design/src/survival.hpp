#pragma once
// The asynchronous search's survival rules (space.hpp, Algorithm): which member of a population
// one too large leaves. The fitness vectors are the normalised ones (all minimised; an infeasible
// design's are its penalty, behind every feasible one).
#include <granstack/design/space.hpp>

#include <cstddef>
#include <vector>

namespace granstack::design {

std::size_t leaving(const std::vector<std::vector<double>>& f, Algorithm algorithm);

// Das and Dennis's (1998) reference directions: every point of the unit simplex in m dimensions
// whose coordinates are multiples of 1 / divisions.
std::vector<std::vector<double>> reference_directions(std::size_t m, std::size_t divisions);

}  // namespace granstack::design
