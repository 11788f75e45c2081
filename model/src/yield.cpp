#include <granstack/model/contact.hpp>
#include <granstack/model/yield.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace granstack::model {

double hertz_peak_pressure(double y_star, double r_star, double overlap) {
  return 2.0 * y_star / kPi * std::sqrt(overlap / r_star);
}

std::optional<double> first_yield_pressure(const Material& a, const Material& b) {
  std::optional<double> lower;
  for (const auto* m : {&a, &b}) {
    if (m->yield_strength && (!lower || *m->yield_strength < *lower)) lower = m->yield_strength;
  }
  if (!lower) return std::nullopt;
  return kFirstYieldPressurePerYield * *lower;
}

namespace {
// The constants of a contact of materials a and b: Y* and the first-yield pressure (0: none).
auto contact_constants(const Material& a, const Material& b) {
  return std::pair{effective_youngs_modulus(a, b), first_yield_pressure(a, b).value_or(0.0)};
}
}  // namespace

YieldContacts yield_contacts(const Stack& stack) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  YieldContacts c;
  for (const auto& name : stack.type_materials()) c.type_materials.push_back(lib.at(name));
  for (const auto& s : stack.spheres()) {
    c.sphere_type.push_back(s.atom_type);
    c.radius.push_back(s.radius);
  }
  c.walls = stack.walls();
  if (stack.has_walls()) c.wall_material = lib.at(spec.effective_wall_material());
  c.hertz = spec.contact_model().normal == NormalModel::hertz;
  return c;
}

YieldMeter::YieldMeter(const YieldContacts& contacts) : radius_(contacts.radius), walls_(contacts.walls) {
  if (!contacts.hertz) {
    why_not_ = "the normal contacts are linear springs (normal_model = hooke), which have no Hertz pressure";
  }
  const auto& types = contacts.type_materials;
  ntypes_ = types.size();
  pairs_.resize(ntypes_ * ntypes_);
  for (std::size_t a = 0; a < ntypes_; ++a) {
    for (std::size_t b = 0; b < ntypes_; ++b) {
      const auto [y_star, yield] = contact_constants(types[a], types[b]);
      pairs_[a * ntypes_ + b] = {y_star, yield};
    }
  }
  std::vector<Material> used(types.begin(), types.end());
  if (contacts.wall_material) {
    used.push_back(*contacts.wall_material);
    for (std::size_t a = 0; a < ntypes_; ++a) {
      const auto [y_star, yield] = contact_constants(types[a], *contacts.wall_material);
      wall_.push_back({y_star, yield});
    }
  }
  for (const auto& m : used) {
    if (!m.yield_strength && std::find(unjudged_.begin(), unjudged_.end(), m.name) == unjudged_.end()) {
      unjudged_.push_back(m.name);
    }
  }
  for (const int t : contacts.sphere_type) type_.push_back(t - 1);
}

const YieldMeter::PairConstants& YieldMeter::pair(std::size_t i, std::size_t j) const {
  return pairs_[static_cast<std::size_t>(type_[i]) * ntypes_ + static_cast<std::size_t>(type_[j])];
}

YieldPeak YieldMeter::at(long step, const std::vector<double>& x, const std::vector<double>& y,
                         const std::vector<double>& z, const std::vector<std::pair<std::size_t, std::size_t>>& pairs) const {
  YieldPeak peak;
  peak.step = step;
  if (!judged()) return peak;
  // A larger ratio wins; on a tie the contact first in (sphere, sphere) order, then the walls.
  const auto offer = [&](double ratio, double p0, int a, int b, const std::string* wall) {
    const bool better = ratio > peak.ratio ||
                        (ratio == peak.ratio && ratio > 0.0 && wall == nullptr && peak.wall.empty() &&
                         std::pair{a, b} < std::pair{peak.id_a, peak.id_b});
    if (!better) return;
    peak.ratio = ratio;
    peak.pressure = p0;
    peak.id_a = a;
    peak.id_b = b;
    peak.wall = wall != nullptr ? *wall : std::string();
  };
  for (const auto& [i, j] : pairs) {
    const auto& c = pair(i, j);
    if (c.yield == 0.0) continue;
    const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
    const double sum = radius_[i] + radius_[j];
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (!(d2 < sum * sum)) continue;
    const double p0 = hertz_peak_pressure(c.y_star, radius_[i] * radius_[j] / sum, sum - std::sqrt(d2));
    offer(p0 / c.yield, p0, static_cast<int>(std::min(i, j)) + 1, static_cast<int>(std::max(i, j)) + 1, nullptr);
  }
  if (wall_.empty()) return peak;
  for (std::size_t i = 0; i < radius_.size(); ++i) {
    const auto& c = wall_[static_cast<std::size_t>(type_[i])];
    if (c.yield == 0.0) continue;
    const std::array<double, 3> centre{x[i], y[i], z[i]};
    for (const auto& w : walls_) {
      const double overlap = w.overlap(centre, radius_[i]);
      if (!(overlap > 0.0)) continue;
      const double p0 = hertz_peak_pressure(c.y_star, radius_[i], overlap);  // a wall: R* = R_i
      offer(p0 / c.yield, p0, static_cast<int>(i) + 1, 0, &w.name);
    }
  }
  return peak;
}

std::string describe_contact(const Stack& stack, const YieldPeak& peak) {
  if (peak.id_a == 0) return "none";
  const auto types = stack.type_materials();
  const auto sphere = [&](int id) {
    const auto& s = stack.sphere(id);
    const auto& material = types[static_cast<std::size_t>(s.atom_type - 1)];
    if (s.block == 0) return fmt::format("sphere {} (the striker, {})", id, material);
    if (stack.is_matrix(s)) return fmt::format("sphere {} (the container's matrix, {})", id, material);
    return fmt::format("sphere {} (block {}, row {}, {})", id, s.block, s.row, material);
  };
  if (peak.id_b == 0) return fmt::format("{} on {} ({})", sphere(peak.id_a), peak.wall, stack.spec().effective_wall_material());
  return fmt::format("{} and {}", sphere(peak.id_a), sphere(peak.id_b));
}

void YieldMeter::add(const YieldPeak& frame) {
  if (!seen_ || frame.ratio > largest_.ratio) largest_ = frame;
  seen_ = true;
}

}  // namespace granstack::model
