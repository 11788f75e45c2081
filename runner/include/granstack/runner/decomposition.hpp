#pragma once
// How LIGGGHTS 3.8 shares a case's spheres among MPI ranks, predicted from the stack, and the
// processor grid `run --np N` passes to the deck.
//
// LIGGGHTS-PUBLIC 3.8.0 splits its box into a uniform grid of Px x Py x Pz sub-domains (it has
// no `balance` command nor `fix balance`, and `neighbor multi` is an empty stub for granular
// styles), so the only choices are the grid and the box (model::Stack::box). A rank owns the
// spheres whose centres lie in its sub-domain and holds as ghosts those of other ranks within
// R_max cdf + skin + r_i of it (comm.cpp's granular border test: half the largest neighbour
// cutoff plus half the skin plus the sphere's own radius), whatever the sizes of the spheres
// it owns: the largest sphere sets every rank's ghost reach.
#include <granstack/formats/case.hpp>

#include <array>
#include <vector>

namespace granstack::runner {

struct Decomposition {
  std::array<int, 3> grid{1, 1, 1};  // ranks along x, y, z
  double owned_mean = 0.0;           // spheres a rank owns
  double owned_max = 0.0;
  double owned_min = 0.0;
  double ghosts_mean = 0.0;          // ghost spheres a rank holds
  double ghosts_max = 0.0;
  double load_max = 0.0;             // the most spheres, owned and ghost, one rank holds
  // The busiest rank's owned spheres over the mean: the wait of every other rank at each step.
  double imbalance() const { return owned_mean > 0.0 ? owned_max / owned_mean : 1.0; }
  double ghosts_per_owned() const { return owned_mean > 0.0 ? ghosts_mean / owned_mean : 0.0; }
  int ranks() const { return grid[0] * grid[1] * grid[2]; }
};

// m: how far beyond a rank's faces the spheres it holds as ghosts reach, less their own radius:
// R_max cdf + skin (half the largest neighbour cutoff plus half the skin).
double ghost_reach(const formats::Case& c);

// The loads of `grid` on the case as its data file starts (its box, LIGGGHTS's plane positions
// and comparisons, so the counts are LIGGGHTS's own: tests/liggghts/test_decomposition.cpp).
Decomposition predict_decomposition(const formats::Case& c, const std::array<int, 3>& grid);

// Of every grid of `ranks` ranks that the geometry allows (a strip is one sphere thick in y, so
// never split in y), the one whose busiest rank holds the fewest spheres, owned and ghost
// together: each step that rank integrates its own, receives its ghosts and finds their
// contacts, and every other rank waits for it. Ties go to fewer ghosts in all.
Decomposition choose_decomposition(const formats::Case& c, int ranks);

// Every grid of `ranks` ranks the geometry allows, the chosen one first, in that order.
std::vector<Decomposition> candidate_decompositions(const formats::Case& c, int ranks);

}  // namespace granstack::runner
