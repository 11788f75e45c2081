#include <granstack/model/contact.hpp>
#include <granstack/model/yield.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace granstack::model {

std::optional<double> yield_pressure(const Material& a, const Material& b, double factor) {
  std::optional<double> lower;
  for (const auto* m : {&a, &b}) {
    if (m->yield_strength && (!lower || *m->yield_strength < *lower)) lower = m->yield_strength;
  }
  if (!lower) return std::nullopt;
  return factor * *lower;
}

std::optional<double> first_yield_pressure(const Material& a, const Material& b) {
  return yield_pressure(a, b, kFirstYieldPressurePerYield);
}

namespace {
// The ratio q with r * q == a_y exactly, searched a few doubles either side of a_y / r; 0 if none.
double exact_ratio(double a_y, double r) {
  double q = a_y / r;
  for (int k = 0; k < 8 && r * q != a_y; ++k) q = r * q < a_y ? std::nextafter(q, 2.0) : std::nextafter(q, 0.0);
  return r * q == a_y ? q : 0.0;
}
}  // namespace

YieldRadiusPlan thornton_ning_plan(const Stack& stack) {
  const auto& spec = stack.spec();
  const auto lib = spec.material_library();
  const double factor = spec.yield_pressure_factor;
  YieldRadiusPlan plan;
  const auto& top = stack.block(1);
  const auto& m1 = lib.at(top.material);
  const auto kind_of = [&](std::string what, const ContactPair& c, const Material& a, const Material& b) {
    const double intended = yield_pressure(a, b, factor).value_or(0.0);
    const double a_y = kPi * c.r_star * intended / (2.0 * c.y_star);
    return std::pair{YieldRadiusPlan::Kind{std::move(what), 0.0, intended}, a_y};
  };
  plan.yield_radius = kind_of("", sphere_sphere(m1, top.radius, m1, top.radius), m1, m1).second;
  plan.honoured = "block 1 - block 1";
  // Each sphere type's radius (one per type), and its ratio.
  const auto types = stack.type_materials();
  std::vector<double> radius(types.size(), 0.0);
  std::string order;  // the first reason the answer would depend on LIGGGHTS's atom order
  for (const auto& s : stack.spheres()) {
    auto& r = radius[static_cast<std::size_t>(s.atom_type - 1)];
    if (r != 0.0 && r != s.radius && order.empty()) {
      order = fmt::format("atom type {} has spheres of two radii ({:g} and {:g} m), so no one coefficientYieldRatio "
                          "gives its contacts one yield radius",
                          s.atom_type, r, s.radius);
    }
    r = s.radius;
  }
  plan.ratio.assign(types.size(), 0.0);
  for (std::size_t t = 0; t < types.size(); ++t) {
    if (radius[t] == 0.0) continue;  // the wall's type: LIGGGHTS reads only atom i's ratio
    const double q = exact_ratio(plan.yield_radius, radius[t]);
    plan.ratio[t] = q != 0.0 ? q : plan.yield_radius / radius[t];
    if (order.empty() && q == 0.0) {
      order = fmt::format("no double coefficientYieldRatio gives atom type {} ({}, radius {:g} m) the yield radius "
                          "a_y = {:.17g} m exactly, so its contacts would depend on which sphere LIGGGHTS calls i",
                          t + 1, types[t], radius[t], plan.yield_radius);
    }
    if (plan.refusal.empty() && plan.ratio[t] > 1.0) {
      plan.refusal = fmt::format("the yield radius a_y = {:.4g} m of block 1's contacts exceeds the radius {:g} m of "
                                 "atom type {} ({}): its coefficientYieldRatio would be {:.4g}, and LIGGGHTS takes "
                                 "0..1; use fewer blocks, a stiffer or weaker top block, or normal_model = 'thornton' "
                                 "(refsim)",
                                 plan.yield_radius, radius[t], t + 1, types[t], plan.ratio[t]);
    }
  }
  if (spec.order_dependent_yield == OrderDependentYield::accept) {
    plan.order_dependent = order;
  } else if (plan.refusal.empty() && !order.empty()) {
    plan.refusal = order + "; order_dependent_yield = 'accept' runs it anyway, the yield of that type's contacts "
                           "then depending on which sphere LIGGGHTS calls i";
  }
  for (std::size_t t = 0; t < types.size(); ++t) {
    if (radius[t] == 0.0) plan.ratio[t] = plan.ratio[0];
  }
  // Every kind of contact, at the one a_y: p_y,eff = 2 E* a_y / (pi R*).
  const auto add = [&](std::string what, const ContactPair& c, const Material& a, const Material& b) {
    auto kind = kind_of(std::move(what), c, a, b).first;
    kind.effective = 2.0 * c.y_star * plan.yield_radius / (kPi * c.r_star);
    plan.kinds.push_back(std::move(kind));
  };
  const auto& striker = lib.at(spec.effective_striker_material());
  add("striker - block 1", sphere_sphere(striker, stack.striker_radius(), m1, top.radius), striker, m1);
  for (const auto& b : stack.blocks()) {
    const auto& m = lib.at(b.material);
    add(fmt::format("block {} - block {}", b.index, b.index), sphere_sphere(m, b.radius, m, b.radius), m, m);
    if (b.index < spec.blocks) {
      const auto& below = stack.block(b.index + 1);
      const auto& mb = lib.at(below.material);
      add(fmt::format("block {} - block {}", b.index, below.index), sphere_sphere(m, b.radius, mb, below.radius), m, mb);
    }
    if (stack.has_walls()) {
      const auto& w = lib.at(spec.effective_wall_material());
      add(fmt::format("block {} - wall", b.index), sphere_wall(m, b.radius, w), m, w);
    }
  }
  return plan;
}

std::optional<std::pair<double, double>> yield_pressure_departure(const Stack& stack) {
  if (stack.spec().normal_model != NormalModel::thornton_ning) return std::nullopt;
  std::optional<std::pair<double, double>> out;
  for (const auto& k : thornton_ning_plan(stack).kinds) {
    if (!(k.intended > 0.0)) continue;
    const double r = k.effective / k.intended;
    out = out ? std::pair{std::min(out->first, r), std::max(out->second, r)} : std::pair{r, r};
  }
  return out;
}

namespace {
// The constants of a contact of materials a and b: Y*, the first-yield pressure (0: none) and
// (2 Y* / (pi p_y))^2.
struct Constants {
  double y_star, yield, scale2;
};
Constants contact_constants(const Material& a, const Material& b) {
  const double y_star = effective_youngs_modulus(a, b), yield = first_yield_pressure(a, b).value_or(0.0);
  const double scale = yield > 0.0 ? 2.0 * y_star / (kPi * yield) : 0.0;
  return {y_star, yield, scale * scale};
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
  c.normal = spec.contact_model().normal;
  return c;
}

YieldMeter::YieldMeter(const YieldContacts& contacts) : radius_(contacts.radius), walls_(contacts.walls) {
  if (const auto& law = normal_law(contacts.normal); !law.hertzian) {
    why_not_ = fmt::format("the normal contacts follow {}'s law (normal_model = {}), which has no Hertz pressure", law.name,
                           to_string(contacts.normal));
  }
  const auto& types = contacts.type_materials;
  ntypes_ = types.size();
  pairs_.resize(ntypes_ * ntypes_);
  for (std::size_t a = 0; a < ntypes_; ++a) {
    for (std::size_t b = 0; b < ntypes_; ++b) {
      const auto k = contact_constants(types[a], types[b]);
      pairs_[a * ntypes_ + b] = {k.y_star, k.yield, k.scale2};
    }
  }
  std::vector<Material> used(types.begin(), types.end());
  if (contacts.wall_material) {
    used.push_back(*contacts.wall_material);
    for (std::size_t a = 0; a < ntypes_; ++a) {
      const auto k = contact_constants(types[a], *contacts.wall_material);
      wall_.push_back({k.y_star, k.yield, k.scale2});
    }
  }
  for (const auto& m : used) {
    if (!m.yield_strength && std::find(unjudged_.begin(), unjudged_.end(), m.name) == unjudged_.end()) {
      unjudged_.push_back(m.name);
    }
  }
  for (const int t : contacts.sphere_type) type_.push_back(t - 1);
  for (const double r : radius_) inverse_radius_.push_back(1.0 / r);
}

const YieldMeter::PairConstants& YieldMeter::pair(std::size_t i, std::size_t j) const {
  return pairs_[static_cast<std::size_t>(type_[i]) * ntypes_ + static_cast<std::size_t>(type_[j])];
}

void YieldMeter::offer(YieldFrame& f, double ratio2, const PairConstants& c, int a, int b, const Wall* wall) const {
  // A larger ratio wins; on a tie the contact first in (sphere, sphere) order, then the walls.
  const bool better = ratio2 > f.ratio2 || (ratio2 == f.ratio2 && ratio2 > 0.0 && wall == nullptr && f.wall == nullptr &&
                                            std::pair{a, b} < std::pair{f.id_a, f.id_b});
  if (!better) return;
  f.ratio2 = ratio2;
  f.yield = c.yield;
  f.id_a = a;
  f.id_b = b;
  f.wall = wall;
}

void YieldMeter::pair(YieldFrame& f, std::size_t i, std::size_t j, double overlap) const {
  const auto& c = pair(i, j);
  if (c.yield == 0.0) return;
  offer(f, c.scale2 * overlap * (inverse_radius_[i] + inverse_radius_[j]), c, static_cast<int>(i) + 1,
        static_cast<int>(j) + 1, nullptr);
}

void YieldMeter::walls(YieldFrame& f, const std::vector<double>& x, const std::vector<double>& y,
                       const std::vector<double>& z, double plate_z) const {
  if (wall_.empty()) return;
  for (std::size_t i = 0; i < radius_.size(); ++i) {
    const auto& c = wall_[static_cast<std::size_t>(type_[i])];
    if (c.yield == 0.0) continue;
    const std::array<double, 3> centre{x[i], y[i], z[i]};
    for (const auto& w : walls_) {
      const double overlap = w.overlap(centre, radius_[i], plate_z);
      if (overlap > 0.0) offer(f, c.scale2 * overlap * inverse_radius_[i], c, static_cast<int>(i) + 1, 0, &w);  // R* = R_i
    }
  }
}

YieldPeak YieldMeter::peak(long step, const YieldFrame& f) const {
  YieldPeak p;
  p.step = step;
  if (!judged() || f.ratio2 == 0.0) return p;
  p.ratio = std::sqrt(f.ratio2);
  p.pressure = p.ratio * f.yield;
  p.id_a = f.id_a;
  p.id_b = f.id_b;
  if (f.wall != nullptr) p.wall = f.wall->name;
  return p;
}

YieldPeak YieldMeter::at(long step, const std::vector<double>& x, const std::vector<double>& y,
                         const std::vector<double>& z, const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                         double plate_z) const {
  YieldFrame f;
  if (!judged()) return peak(step, f);
  for (const auto& [i, j] : pairs) {
    const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
    const double sum = radius_[i] + radius_[j];
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < sum * sum) pair(f, i, j, sum - std::sqrt(d2));
  }
  walls(f, x, y, z, plate_z);
  return peak(step, f);
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
