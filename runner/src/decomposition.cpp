#include <granstack/model/resolution.hpp>
#include <granstack/formats/data_file.hpp>
#include <granstack/runner/decomposition.hpp>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <vector>

namespace granstack::runner {

namespace fs = std::filesystem;

namespace {

// LIGGGHTS's shrink-wrap "small" (domain.cpp: 1e-4 of the box's length).
constexpr double kSmall = 1.0e-4;

// One direction of the grid: the box's extent as LIGGGHTS sets it at the first step and the
// lower faces of its sub-domains (boxlo + prd * i/P, as comm.cpp's xsplit and domain.cpp).
class Axis {
 public:
  Axis(double lo, double hi, double centre_min, double centre_max, int cells) : cells_(cells) {
    const double small = kSmall * (hi - lo);
    lo = std::min(lo, centre_min - small);  // shrink-wrapped with the data file's box as its least
    hi = std::max(hi, centre_max + small);
    for (int c = 0; c < cells; ++c) lower_.push_back(lo + (hi - lo) * (c * 1.0 / cells));
  }
  // The sub-domain that owns a centre at q: the last whose lower face is at or below it.
  int owner(double q) const { return count_faces([&](double face) { return q >= face; }); }
  // The sub-domains that hold a sphere at q as a ghost if it reaches `reach` beyond their faces.
  int first_within(double q, double reach) const { return count_faces([&](double face) { return face < q - reach; }); }
  int last_within(double q, double reach) const { return count_faces([&](double face) { return q + reach >= face; }); }

 private:
  template <class Below>
  int count_faces(Below below) const {
    int c = 0;
    while (c + 1 < cells_ && below(lower_[static_cast<std::size_t>(c + 1)])) ++c;
    return c;
  }
  int cells_;
  std::vector<double> lower_;
};

double reach(const model::Stack& stack, double skin) {
  double r_max = 0.0;
  for (const auto& s : stack.spheres()) r_max = std::max(r_max, s.radius);
  return r_max * model::kContactDistanceFactor + skin;
}

Decomposition predict(const model::Stack& stack, const std::array<double, 6>& box, double skin,
                      const std::array<int, 3>& grid) {
  for (const int p : grid) {
    if (p < 1) throw std::invalid_argument("a processor grid has at least one rank along each direction");
  }
  const auto& spheres = stack.spheres();
  std::array<double, 3> cmin{}, cmax{};
  cmin.fill(std::numeric_limits<double>::max());
  cmax.fill(std::numeric_limits<double>::lowest());
  for (const auto& s : spheres) {
    const std::array<double, 3> x{s.x, s.y, s.z};
    for (std::size_t d = 0; d < 3; ++d) {
      cmin[d] = std::min(cmin[d], x[d]);
      cmax[d] = std::max(cmax[d], x[d]);
    }
  }
  std::vector<Axis> axes;
  for (std::size_t d = 0; d < 3; ++d) axes.emplace_back(box[2 * d], box[2 * d + 1], cmin[d], cmax[d], grid[d]);
  const auto flat = [&](int i, int j, int k) { return static_cast<std::size_t>((k * grid[1] + j) * grid[0] + i); };
  const std::size_t ranks = static_cast<std::size_t>(grid[0]) * static_cast<std::size_t>(grid[1]) * static_cast<std::size_t>(grid[2]);
  std::vector<long> owned(ranks, 0), ghosts(ranks, 0);
  const double slab = reach(stack, skin);
  for (const auto& s : spheres) {
    const std::array<double, 3> x{s.x, s.y, s.z};
    std::array<int, 3> own{}, lo{}, hi{};
    for (std::size_t d = 0; d < 3; ++d) {
      own[d] = axes[d].owner(x[d]);
      lo[d] = axes[d].first_within(x[d], slab + s.radius);
      hi[d] = axes[d].last_within(x[d], slab + s.radius);
    }
    ++owned[flat(own[0], own[1], own[2])];
    for (int k = lo[2]; k <= hi[2]; ++k) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int i = lo[0]; i <= hi[0]; ++i) {
          if (i != own[0] || j != own[1] || k != own[2]) ++ghosts[flat(i, j, k)];
        }
      }
    }
  }
  Decomposition d;
  d.grid = grid;
  const double n = static_cast<double>(ranks);
  double owned_sum = 0.0, ghost_sum = 0.0;
  for (std::size_t r = 0; r < ranks; ++r) {
    owned_sum += static_cast<double>(owned[r]);
    ghost_sum += static_cast<double>(ghosts[r]);
  }
  d.owned_mean = owned_sum / n;
  d.ghosts_mean = ghost_sum / n;
  d.owned_max = static_cast<double>(*std::max_element(owned.begin(), owned.end()));
  d.owned_min = static_cast<double>(*std::min_element(owned.begin(), owned.end()));
  d.ghosts_max = static_cast<double>(*std::max_element(ghosts.begin(), ghosts.end()));
  for (std::size_t r = 0; r < ranks; ++r) d.load_max = std::max(d.load_max, static_cast<double>(owned[r] + ghosts[r]));
  return d;
}

std::array<double, 6> data_box(const formats::Case& c) {
  return formats::read_data_header((fs::path(c.dir()) / c.files().data).string()).box;
}

}  // namespace

double ghost_reach(const formats::Case& c) { return reach(c.stack(), c.resolution().skin); }

Decomposition predict_decomposition(const formats::Case& c, const std::array<int, 3>& grid) {
  return predict(c.stack(), data_box(c), c.resolution().skin, grid);
}

std::vector<Decomposition> candidate_decompositions(const formats::Case& c, int ranks) {
  if (ranks < 1) throw std::invalid_argument("a run has at least one MPI rank");
  const auto& stack = c.stack();
  const auto box = data_box(c);
  const double skin = c.resolution().skin;
  const bool strip = !stack.three_d() && !stack.container();
  std::vector<Decomposition> all;
  for (int px = 1; px <= ranks; ++px) {
    for (int py = 1; px * py <= ranks; ++py) {
      if (ranks % (px * py) == 0 && !(strip && py > 1)) all.push_back(predict(stack, box, skin, {px, py, ranks / (px * py)}));
    }
  }
  std::stable_sort(all.begin(), all.end(), [](const Decomposition& a, const Decomposition& b) {
    return a.load_max != b.load_max ? a.load_max < b.load_max : a.ghosts_mean < b.ghosts_mean;
  });
  return all;
}

Decomposition choose_decomposition(const formats::Case& c, int ranks) {
  return candidate_decompositions(c, ranks).front();
}

}  // namespace granstack::runner
