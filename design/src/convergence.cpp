#include <granstack/design/convergence.hpp>
#include <granstack/design/search.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <pagmo/utils/hypervolume.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace granstack::design {

namespace {

constexpr const char* kMetaKey = "normalisation";

// The largest and the least positive value of objective `o` over evaluations that have it.
struct Span {
  double most = -std::numeric_limits<double>::infinity();
  double least_positive = std::numeric_limits<double>::infinity();
  int count = 0;
};
Span span_of(Objective o, const std::vector<Evaluation>& evaluations) {
  Span s;
  for (const auto& e : evaluations) {
    const auto v = objective_value(e, o);
    if (!v || !std::isfinite(*v)) continue;
    ++s.count;
    s.most = std::max(s.most, *v);
    if (*v > 0.0) s.least_positive = std::min(s.least_positive, *v);
  }
  return s;
}

// A geometric measure's axis: the space's lightest to heaviest design, the constraint's bound
// where it is lower, and the probes (the study's designs may lie outside the space) inside.
Axis geometric_axis(const Space& space, Objective o, const std::vector<Evaluation>& probes) {
  const auto [light, heavy] = space.extreme_designs();
  const auto g_light = measure(space, light), g_heavy = measure(space, heavy);
  const bool mass = o->name == "areal_mass";
  Axis a{std::string(o->name), o->log_axis, mass ? g_light.areal_mass : g_light.height,
         mass ? g_heavy.areal_mass : g_heavy.height, "the space's lightest and heaviest designs"};
  const auto bound = mass ? space.constraints.max_areal_mass : space.constraints.max_height;
  if (bound && *bound < a.nadir && *bound > a.ideal) {
    a.nadir = *bound;
    a.basis = "the space's lightest design and its constraint";
  }
  for (const auto& e : probes) {
    a.ideal = std::min(a.ideal, *objective_value(e, o));
    a.nadir = std::max(a.nadir, *objective_value(e, o));
  }
  return a;
}

// A run measure's axis: 0 (or, on a log axis, kLogDecadesBelowProbes decades below the least) to
// the probes' largest; of the first generation's when no probe has it.
Axis run_axis(Objective o, const std::vector<Evaluation>& probes, const std::vector<Evaluation>& first) {
  Axis a{std::string(o->name), o->log_axis, 0.0, 1.0, "the study's and the space's extreme designs"};
  auto s = span_of(o, probes);
  if (s.count == 0) {
    s = span_of(o, first);
    a.basis = "the first generation (the probes have no such measure)";
  }
  if (s.count == 0 || !(s.most > 0.0)) {
    a.basis = "no design measured it: a unit box";
    return a;
  }
  a.nadir = s.most;
  if (a.log) a.ideal = s.least_positive * std::pow(10.0, -kLogDecadesBelowProbes);
  if (a.log && !(a.ideal < a.nadir)) a.ideal = a.nadir * std::pow(10.0, -kLogDecadesBelowProbes);
  return a;
}

std::vector<double> front_points(const Space& space, const Normalisation& n, const std::vector<Evaluation>& all) {
  std::vector<double> flat;
  for (const auto& e : pareto_front(space, all)) {
    const auto p = n.point(objective_values(space, e));
    flat.insert(flat.end(), p.begin(), p.end());
  }
  return flat;
}

}  // namespace

std::vector<double> Normalisation::point(const std::vector<double>& values) const {
  std::vector<double> p;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const auto& a = axes[k];
    const double v = values.at(k);
    double t = a.log ? (v > 0.0 ? (std::log10(v) - std::log10(a.ideal)) / (std::log10(a.nadir) - std::log10(a.ideal)) : 0.0)
                     : (v - a.ideal) / (a.nadir - a.ideal);
    p.push_back(std::max(t, 0.0));
  }
  return p;
}

Normalisation fix_normalisation(const Space& space, const std::vector<Evaluation>& probes, const std::vector<Evaluation>& first) {
  Normalisation n;
  for (const auto o : space.objectives) {
    auto a = o->geometric != nullptr ? geometric_axis(space, o, probes) : run_axis(o, probes, first);
    if (!(a.nadir > a.ideal)) a.nadir = a.ideal + (a.ideal != 0.0 ? std::fabs(a.ideal) : 1.0);  // one design: a box all the same
    n.axes.push_back(std::move(a));
  }
  return n;
}

std::optional<Normalisation> stored_normalisation(const Store& store) {
  const auto text = store.meta(kMetaKey);
  if (!text) return std::nullopt;
  Normalisation n;
  for (const auto& j : nlohmann::json::parse(*text)) {
    n.axes.push_back({j.at("objective"), j.at("log"), j.at("ideal"), j.at("nadir"), j.at("basis")});
  }
  return n;
}

void store_normalisation(Store& store, const Normalisation& n) {
  auto j = nlohmann::json::array();
  for (const auto& a : n.axes) {
    j.push_back({{"objective", a.objective}, {"log", a.log}, {"ideal", a.ideal}, {"nadir", a.nadir}, {"basis", a.basis}});
  }
  store.set_meta(kMetaKey, j.dump());
}

std::vector<double> objective_values(const Space& space, const Evaluation& e) {
  std::vector<double> v;
  for (const auto o : space.objectives) v.push_back(objective_value(e, o).value_or(std::numeric_limits<double>::quiet_NaN()));
  return v;
}

double box_hypervolume(const std::vector<std::vector<double>>& points) {
  std::vector<pagmo::vector_double> inside;
  for (const auto& p : points) {
    if (std::all_of(p.begin(), p.end(), [](double x) { return x < kReferencePoint; })) inside.push_back(p);
  }
  if (inside.empty()) return 0.0;
  return pagmo::hypervolume(inside, false).compute(pagmo::vector_double(inside.front().size(), kReferencePoint));
}

double normalised_hypervolume(const Space& space, const Normalisation& n, const std::vector<Evaluation>& all) {
  const auto m = space.objectives.size();
  const auto flat = front_points(space, n, all);
  std::vector<std::vector<double>> points;
  for (std::size_t at = 0; at < flat.size(); at += m) {
    points.emplace_back(flat.begin() + static_cast<long>(at), flat.begin() + static_cast<long>(at + m));
  }
  return box_hypervolume(points);
}

double igd_plus(const Space& space, const Normalisation& n, const std::vector<Evaluation>& all,
                const std::vector<Evaluation>& reference) {
  const auto m = space.objectives.size();
  const auto front = front_points(space, n, all), ref = front_points(space, n, reference);
  if (ref.empty()) return 0.0;
  if (front.empty()) return std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (std::size_t r = 0; r < ref.size(); r += m) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < front.size(); f += m) {
      double d2 = 0.0;
      for (std::size_t k = 0; k < m; ++k) d2 += std::pow(std::max(front[f + k] - ref[r + k], 0.0), 2);
      nearest = std::min(nearest, std::sqrt(d2));
    }
    sum += nearest;
  }
  return sum / static_cast<double>(ref.size() / m);
}

}  // namespace granstack::design
