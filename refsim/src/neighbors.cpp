#include <granstack/refsim/neighbors.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>

namespace granstack::refsim {

namespace {

using Pairs = std::vector<std::pair<std::int32_t, std::int32_t>>;

// The criterion itself, for i < j, with the neighbour list's operations in its order.
bool within(const SphereArrays& s, std::size_t i, std::size_t j, double factor, double skin) {
  const double dx = s.x[i] - s.x[j];
  const double dy = s.y[i] - s.y[j];
  const double dz = s.z[i] - s.z[j];
  const double rsq = dx * dx + dy * dy + dz * dz;
  const double cut = (s.radius[i] + s.radius[j]) * factor + skin;
  return !(rsq > cut * cut);
}

// Every pair tested: for what the grid cannot place (a coordinate or radius that is not finite).
Pairs every_pair(const SphereArrays& s, double factor, double skin) {
  Pairs found;
  for (std::size_t i = 0; i < s.count; ++i) {
    for (std::size_t j = i + 1; j < s.count; ++j) {
      if (within(s, i, j, factor, skin)) found.emplace_back(static_cast<std::int32_t>(i), static_cast<std::int32_t>(j));
    }
  }
  return found;
}

}  // namespace

std::vector<std::pair<std::int32_t, std::int32_t>> candidate_pairs(const SphereArrays& s, double factor, double skin,
                                                                   const ForShares& for_shares) {
  const ForShares run = for_shares ? for_shares : ForShares([](std::size_t count, const auto& job) { job(0, count); });
  const std::size_t n = s.count;
  if (n < 2) return {};
  const std::array<const double*, 3> p{s.x, s.y, s.z};
  std::array<double, 3> lo{}, hi{};
  double r_min = s.radius[0];
  bool finite = std::isfinite(factor) && std::isfinite(skin) && factor >= 0.0 && skin >= 0.0;
  for (std::size_t d = 0; d < 3; ++d) lo[d] = hi[d] = p[d][0];
  for (std::size_t k = 0; k < n && finite; ++k) {
    finite = std::isfinite(s.radius[k]) && s.radius[k] >= 0.0;
    r_min = std::min(r_min, s.radius[k]);
    for (std::size_t d = 0; d < 3; ++d) {
      finite = finite && std::isfinite(p[d][k]);
      lo[d] = std::min(lo[d], p[d][k]);
      hi[d] = std::max(hi[d], p[d][k]);
    }
  }
  // Cells as wide as the smallest spheres' cut, unless that would make more than about four
  // cells per sphere (a sphere far from the rest): then wider.
  double h = 2.0 * r_min * factor + skin;
  if (!finite || !(h > 0.0)) return every_pair(s, factor, skin);
  std::array<std::size_t, 3> dims{};
  const double most = 4.0 * static_cast<double>(n) + 64.0;
  for (;;) {
    double cells = 1.0;
    for (std::size_t d = 0; d < 3; ++d) cells *= std::floor((hi[d] - lo[d]) / h) + 1.0;
    if (cells <= most) break;
    h *= 2.0;
  }
  for (std::size_t d = 0; d < 3; ++d) dims[d] = static_cast<std::size_t>(std::floor((hi[d] - lo[d]) / h)) + 1;
  // A monotone map from a coordinate to its cell: a sphere at or beyond q is in q's cell or later.
  const auto cell = [&](std::size_t d, double q) {
    const double c = std::floor((q - lo[d]) / h);
    return c <= 0.0 ? std::size_t{0} : std::min(dims[d] - 1, static_cast<std::size_t>(c));
  };
  const auto flat = [&](const std::array<std::size_t, 3>& c) { return (c[2] * dims[1] + c[1]) * dims[0] + c[0]; };
  // The spheres by cell (a counting sort): those of cell c are members[first[c] .. first[c + 1]].
  std::vector<std::size_t> home(n), first(dims[0] * dims[1] * dims[2] + 1, 0), members(n);
  for (std::size_t k = 0; k < n; ++k) {
    home[k] = flat({cell(0, s.x[k]), cell(1, s.y[k]), cell(2, s.z[k])});
    ++first[home[k] + 1];
  }
  for (std::size_t c = 1; c < first.size(); ++c) first[c] += first[c - 1];
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t k = 0; k < n; ++k) members[next[home[k]]++] = k;
  }
  // Each pair is looked for from its larger sphere (of equal ones, the lower-numbered), so
  // within 2 R_i factor + skin of it; with a margin far above the rounding of the bounds. Each
  // share of the spheres keeps what it finds apart (by where the share begins).
  std::mutex m;
  std::vector<std::pair<std::size_t, Pairs>> by_share;
  run(n, [&](std::size_t begin, std::size_t end) {
    Pairs found;
    for (std::size_t i = begin; i < end; ++i) {
      const double reach = 2.0 * s.radius[i] * factor + skin;
      std::array<std::size_t, 3> from{}, to{};
      for (std::size_t d = 0; d < 3; ++d) {
        const double margin = 1.01 * reach + 1e-15 * (std::abs(p[d][i]) + reach);
        from[d] = cell(d, p[d][i] - margin);
        to[d] = cell(d, p[d][i] + margin);
      }
      std::array<std::size_t, 3> c{};
      for (c[2] = from[2]; c[2] <= to[2]; ++c[2]) {
        for (c[1] = from[1]; c[1] <= to[1]; ++c[1]) {
          for (c[0] = from[0]; c[0] <= to[0]; ++c[0]) {
            const std::size_t f = flat(c);
            for (std::size_t q = first[f]; q < first[f + 1]; ++q) {
              const std::size_t j = members[q];
              if (!(s.radius[j] < s.radius[i] || (s.radius[j] == s.radius[i] && j > i))) continue;
              const std::size_t a = std::min(i, j), b = std::max(i, j);
              if (within(s, a, b, factor, skin)) found.emplace_back(static_cast<std::int32_t>(a), static_cast<std::int32_t>(b));
            }
          }
        }
      }
    }
    const std::lock_guard<std::mutex> lock(m);
    by_share.emplace_back(begin, std::move(found));
  });
  // In (i, j) order: each share of the first spheres gathers the pairs that start in it, sorts
  // them, and the shares follow one another.
  std::vector<std::pair<std::size_t, Pairs>> sorted;
  run(n, [&](std::size_t begin, std::size_t end) {
    Pairs mine;
    for (const auto& share : by_share) {
      for (const auto& q : share.second) {
        if (static_cast<std::size_t>(q.first) >= begin && static_cast<std::size_t>(q.first) < end) mine.push_back(q);
      }
    }
    std::sort(mine.begin(), mine.end());
    const std::lock_guard<std::mutex> lock(m);
    sorted.emplace_back(begin, std::move(mine));
  });
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Pairs all;
  std::size_t total = 0;
  for (const auto& share : sorted) total += share.second.size();
  all.reserve(total);
  for (const auto& share : sorted) all.insert(all.end(), share.second.begin(), share.second.end());
  return all;
}

}  // namespace granstack::refsim
