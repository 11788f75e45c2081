// Where the normal law keeps a contact's energy with its history (refsim's thornton): each
// particle's share of the elastic energy in its contacts and of the work they have dissipated,
// for the in-situ series (model::series_contact_columns).
#include <granstack/refsim/system.hpp>

#include "contacts.hpp"
#include "contact_models/sub_models.hpp"

#include <algorithm>
#include <cmath>

namespace granstack::refsim {

System::ContactEnergies System::contact_energies() const {
  ContactEnergies e;
  if (banked_.empty()) return e;
  e.elastic.assign(n_, 0.0);
  e.dissipated = banked_;
  const auto add = [&e](std::size_t i, double share, const detail::ContactEnergy& c) {
    e.elastic[i] += share * c.elastic;
    e.dissipated[i] += share * c.dissipated;
  };
  const auto& t = *pairs_;
  for (std::size_t p = 0; p < t.count; ++p) {
    if (t.record[p] == 0 || !t.touching[p]) continue;  // padding, or no contact kept
    const auto i = static_cast<std::size_t>(t.i[p]), j = static_cast<std::size_t>(t.j[p]);
    double rsq = 0.0;
    for (std::size_t d = 0; d < 3; ++d) {
      const double del = x_[d * stride_ + i] - x_[d * stride_ + j];
      rsq += del * del;
    }
    const auto c = detail::pair_contact_energy(t, p, std::max(radius_[i] + radius_[j] - std::sqrt(rsq), 0.0));
    add(i, 0.5, c);
    add(j, 0.5, c);
  }
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    const Wall& wall = p_.walls[w];
    for (std::size_t i = 0; i < n_; ++i) {
      if (wall_touched_[w * n_ + i] == 0) continue;
      const double gap = detail::liggghts_wall_gap(wall.position, x_[static_cast<std::size_t>(wall.axis) * stride_ + i], radius_[i]);
      add(i, 1.0, wall_contact_energy(i, w, std::max(-gap, 0.0)));
    }
  }
  return e;
}

}  // namespace granstack::refsim
