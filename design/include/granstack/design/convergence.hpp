#pragma once
// How far a search has come, on axes that see every objective: each objective mapped onto [0, 1]
// between an ideal and a nadir fixed before the first design runs (log10 for the measures that
// span decades, objective_table's log_axis), the hypervolume taken in that box against the
// reference point 1.1 on every axis, and IGD+ against a reference front.
//
// The box comes from the space and the study's designs, never from the search's own designs (a
// reference point from generation 0 moved with the seed, and a fraction falling from 1e-4 to
// 1e-6 moved a raw hypervolume by 0.02 %). The probes are the study's designs and the space's
// lightest and heaviest designs, run before the search: a geometric measure spans the space's
// lightest to its heaviest design (its constraint, where lower); a run measure, from 0 (linear)
// or kLogDecadesBelowProbes decades below the probes' least (log) to their largest. The study's
// designs lie inside it.
#include <granstack/design/store.hpp>

#include <string>
#include <vector>

namespace granstack::design {

struct Space;

struct Axis {
  std::string objective;
  bool log = false;
  double ideal = 0.0, nadir = 1.0;  // in the objective's unit
  std::string basis;                // what fixed them, for the report
};

struct Normalisation {
  std::vector<Axis> axes;  // the space's objectives, in its order
  // The point in [0, 1]^m of a value vector in the objectives' units; a value beyond the ideal
  // (or a log measure at or below 0) sits at 0.
  std::vector<double> point(const std::vector<double>& values) const;
};
inline constexpr double kReferencePoint = 1.1;  // on every normalised axis
inline constexpr double kLogDecadesBelowProbes = 3.0;

// The box for `space`, from its extreme designs (geometry) and the probes' evaluations (the study's
// designs and the space's extreme ones: their run measures). A run measure none of them has spans
// the first generation's designs instead (`first`), and says so in its basis.
Normalisation fix_normalisation(const Space& space, const std::vector<Evaluation>& probes, const std::vector<Evaluation>& first = {});

// Kept in the store's meta table (key "normalisation"); nullopt for a store from before it.
std::optional<Normalisation> stored_normalisation(const Store& store);
void store_normalisation(Store& store, const Normalisation& n);

// The objective values of an evaluation, in the space's order (feasible ones only).
std::vector<double> objective_values(const Space& space, const Evaluation& e);
// The hypervolume of points in the normalised box against kReferencePoint (a point not below it
// on every axis adds nothing and is left out).
double box_hypervolume(const std::vector<std::vector<double>>& points);
// The hypervolume of the feasible front of `all` in the normalised box, against kReferencePoint.
double normalised_hypervolume(const Space& space, const Normalisation& n, const std::vector<Evaluation>& all);
// IGD+ (Ishibuchi et al. 2015) of the feasible front of `all` against `reference` (a front), in
// the normalised box: the mean over the reference points of the distance to the nearest of the
// front's points, counting only where that point is worse. 0: the front reaches every reference point.
double igd_plus(const Space& space, const Normalisation& n, const std::vector<Evaluation>& all,
                const std::vector<Evaluation>& reference);

}  // namespace granstack::design
