#include "survival.hpp"

#include <granstack/design/convergence.hpp>

#include <pagmo/utils/hypervolume.hpp>
#include <pagmo/utils/multi_objective.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace granstack::design {

namespace {

// NSGA-II: the one pagmo2's best-N selection (rank, then crowding) leaves out.
std::size_t nsga2_leaving(const std::vector<std::vector<double>>& f) {
  auto keep = pagmo::select_best_N_mo(f, f.size() - 1);
  std::sort(keep.begin(), keep.end());
  for (std::size_t i = 0; i < keep.size(); ++i) {
    if (keep[i] != i) return i;
  }
  return f.size() - 1;
}

// SMS-EMOA: of the last front, the least exclusive hypervolume against the box's reference point
// (moved beyond any point outside it, as an infeasible design's penalty is).
std::size_t sms_emoa_leaving(const std::vector<std::vector<double>>& f, const std::vector<std::size_t>& last) {
  std::vector<pagmo::vector_double> points;
  for (const auto i : last) points.push_back(f[i]);
  pagmo::vector_double ref(f.front().size(), kReferencePoint);
  for (const auto& p : points) {
    for (std::size_t k = 0; k < ref.size(); ++k) ref[k] = std::max(ref[k], p[k] * (1.0 + 1e-9) + 1e-9);
  }
  const auto c = pagmo::hypervolume(points, false).contributions(ref);
  return last[static_cast<std::size_t>(std::min_element(c.begin(), c.end()) - c.begin())];
}

// NSGA-III: every member tied to its nearest reference direction (perpendicular distance); of the
// last front, the one tied to the most crowded direction, the farthest from it.
std::size_t nsga3_leaving(const std::vector<std::vector<double>>& f, const std::vector<std::size_t>& last) {
  const std::size_t m = f.front().size();
  std::size_t h = 1;  // the fewest divisions giving a direction per member
  const auto count = [m](std::size_t d) {
    double c = 1.0;
    for (std::size_t i = 1; i < m; ++i) c = c * static_cast<double>(d + i) / static_cast<double>(i);
    return c;
  };
  while (count(h) < static_cast<double>(f.size() - 1)) ++h;
  const auto directions = reference_directions(m, h);
  std::vector<std::size_t> tied(f.size());
  std::vector<double> distance(f.size());
  std::vector<int> niche(directions.size(), 0);
  for (std::size_t i = 0; i < f.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < directions.size(); ++j) {
      const auto& w = directions[j];
      const double along = std::inner_product(f[i].begin(), f[i].end(), w.begin(), 0.0) / std::inner_product(w.begin(), w.end(), w.begin(), 0.0);
      double d2 = 0.0;
      for (std::size_t k = 0; k < m; ++k) d2 += std::pow(f[i][k] - along * w[k], 2);
      if (d2 < best) {
        best = d2;
        tied[i] = j;
      }
    }
    distance[i] = std::sqrt(best);
    ++niche[tied[i]];
  }
  return *std::max_element(last.begin(), last.end(), [&](std::size_t a, std::size_t b) {
    if (niche[tied[a]] != niche[tied[b]]) return niche[tied[a]] < niche[tied[b]];
    return distance[a] < distance[b];
  });
}

}  // namespace

std::vector<std::vector<double>> reference_directions(std::size_t m, std::size_t divisions) {
  std::vector<std::vector<double>> out;
  std::vector<std::size_t> parts(m, 0);
  // Every composition of `divisions` into m parts, in order.
  const auto fill = [&](auto&& self, std::size_t k, std::size_t left) -> void {
    if (k + 1 == m) {
      parts[k] = left;
      std::vector<double> w;
      for (const auto p : parts) w.push_back(static_cast<double>(p) / static_cast<double>(divisions));
      out.push_back(std::move(w));
      return;
    }
    for (std::size_t p = 0; p <= left; ++p) {
      parts[k] = p;
      self(self, k + 1, left - p);
    }
  };
  fill(fill, 0, divisions);
  return out;
}

std::size_t leaving(const std::vector<std::vector<double>>& f, Algorithm algorithm) {
  if (algorithm == Algorithm::nsga2) return nsga2_leaving(f);
  const auto fronts = std::get<0>(pagmo::fast_non_dominated_sorting(f));
  const auto& last = fronts.back();
  if (last.size() == 1) return last.front();
  return algorithm == Algorithm::sms_emoa ? sms_emoa_leaving(f, last) : nsga3_leaving(f, last);
}

void mutate(const Space& space, const std::pair<std::vector<double>, std::vector<double>>& bounds, std::vector<double>& x,
            double pm, std::mt19937& rng) {
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(chance(rng) < pm)) continue;
    const int lo = static_cast<int>(bounds.first[i]), hi = static_cast<int>(bounds.second[i]), now = static_cast<int>(x[i]);
    if (!space.is_material_gene(i) && chance(rng) < space.search.step_mutation) {
      x[i] = std::clamp(now + (chance(rng) < 0.5 ? -1 : 1), lo, hi);
    } else {
      const int other = std::uniform_int_distribution<int>(lo, hi - 1)(rng);
      x[i] = other >= now ? other + 1 : other;
    }
  }
}

}  // namespace granstack::design
