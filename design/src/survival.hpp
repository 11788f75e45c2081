#pragma once
// The asynchronous search's survival rules (space.hpp, Algorithm): which member of a population
// one too large leaves (the fitness vectors are the normalised ones, all minimised; an infeasible
// design's are its penalty, behind every feasible one); and its mutation.
#include <granstack/design/space.hpp>

#include <cstddef>
#include <random>
#include <utility>
#include <vector>

namespace granstack::design {

std::size_t leaving(const std::vector<std::vector<double>>& f, Algorithm algorithm);

// Das and Dennis's (1998) reference directions: every point of the unit simplex in m dimensions
// whose coordinates are multiples of 1 / divisions.
std::vector<std::vector<double>> reference_directions(std::size_t m, std::size_t divisions);

// The asynchronous search's mutation of a bred design's genes x (whole numbers within `bounds`,
// Space::bounds): each gene mutates with probability pm; an ordinal one (the blocks, a ratio's
// index, a block's rows) by one step up or down with probability space.search.step_mutation
// (held at its bounds), else, and a material always, to another of its values at random.
void mutate(const Space& space, const std::pair<std::vector<double>, std::vector<double>>& bounds, std::vector<double>& x,
            double pm, std::mt19937& rng);

}  // namespace granstack::design
