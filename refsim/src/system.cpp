#include <granstack/refsim/system.hpp>

#include <granstack/refsim/neighbors.hpp>

#include "contacts.hpp"

#include <granstack/model/contact.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <thread>

namespace granstack::refsim {

namespace {
// sqrt(5/6), with the digits LIGGGHTS hard-codes (normal_model_hertz.h).
constexpr double kSqrtFiveOverSix = 0.91287092917527685576161630466800355658790782499663875;
// I = 0.4 m R^2 for solid spheres (fix_nve_sphere.cpp).
constexpr double kInertia = 0.4;
}  // namespace

System::System(std::vector<Particle> particles, Parameters params)
    : n_(particles.size()),
      p_(std::move(params)),
      pairs_(std::make_unique<detail::PairTable>()),
      sum_plan_(std::make_unique<detail::SumPlan>()) {
  const std::size_t tt = static_cast<std::size_t>(p_.types) * static_cast<std::size_t>(p_.types);
  if (p_.y_star.size() != tt || p_.g_star.size() != tt || p_.beta.size() != tt || p_.friction.size() != tt) {
    throw std::invalid_argument("refsim: every property table needs types x types entries");
  }
  if (!p_.contact.is_study_model() && (p_.restitution.size() != tt || p_.rolling_friction.size() != tt)) {
    throw std::invalid_argument("refsim: the hooke and epsd2 models need restitution and rolling_friction per type pair");
  }
  type_.resize(n_);
  stride_ = (n_ + detail::kLanes - 1) / detail::kLanes * detail::kLanes + 2 * detail::kLanes;
  radius_.assign(stride_, 0.0);  // zeros past the last particle, for whole vectors of them
  mass_.assign(stride_, 0.0);
  for (auto* a : {&x_, &v_, &w_, &f_, &t_}) a->assign(3 * stride_, 0.0);
  position_changed_.assign(stride_ / detail::kLanes + sizeof(std::uint32_t), 0xff);
  sums_due_.assign(stride_ / detail::kLanes, 1);
  for (std::size_t i = 0; i < n_; ++i) {
    const auto& pa = particles[i];
    if (pa.type < 1 || pa.type > p_.types) throw std::invalid_argument("refsim: particle type outside the tables");
    type_[i] = pa.type;
    for (double w : pa.omega) negative_zero_spin_ |= w == 0.0 && std::signbit(w);
    radius_[i] = pa.radius;
    mass_[i] = pa.mass;
    for (std::size_t d = 0; d < 3; ++d) {
      x_[d * stride_ + i] = pa.x[d];
      v_[d * stride_ + i] = pa.v[d];
      w_[d * stride_ + i] = pa.omega[d];
    }
  }
  wall_history_.assign(3 * n_ * p_.walls.size(), 0.0);
  wall_roll_.assign(3 * n_ * p_.walls.size(), 0.0);
  wall_store_.assign(p_.stored_wall >= 0 ? 3 * n_ : 0, 0.0);
  wall_touched_.assign(n_ * p_.walls.size(), 0);
  external_ = !p_.walls.empty() || p_.gravity[0] != 0.0 || p_.gravity[1] != 0.0 || p_.gravity[2] != 0.0;
  const double dtf = 0.5 * p_.dt * 1.0;
  const double dtfrotate = dtf / kInertia;
  kick_.assign(stride_, 0.0);
  spin_kick_.assign(stride_, 0.0);
  for (std::size_t i = 0; i < n_; ++i) {
    kick_[i] = dtf / (mass_[i] * 1.0);
    spin_kick_[i] = dtfrotate / (radius_[i] * radius_[i] * mass_[i]);
  }
  for (std::size_t k = 0; k < tt; ++k) {
    type_constants_.push_back({4. / 3. * p_.y_star[k], 2. * p_.y_star[k], 8. * p_.g_star[k], -2. * kSqrtFiveOverSix * p_.beta[k],
                               p_.friction[k]});
    if (!p_.contact.is_study_model()) {
      model_constants_.push_back({p_.y_star[k], std::log(p_.restitution[k]), p_.rolling_friction[k],
                                  p_.contact.characteristic_velocity});
    } else {
      model_constants_.push_back({});
    }
    if (p_.lammps_rules) {  // the coefficients granstack's LAMMPS deck gives (model/lammps.hpp)
      const double e = p_.restitution.empty() ? 1.0 : p_.restitution[k];
      model_constants_.back().lammps_alpha = e < 1.0 ? model::tsuji_alpha(model::lammps_tsuji_restitution(e)) : 0.0;
      model_constants_.back().lammps_tangential_ratio = std::sqrt(4.0 * p_.g_star[k] / p_.y_star[k]);
    }
  }
  choose_kernels();
  // The threads first: the first neighbour build runs on them.
  workers_ = std::make_unique<os::Workers>(p_.threads);
  build_pairs();
}

std::vector<std::string> vector_kernels() { return detail::vector_targets(); }

void System::choose_kernels() {
  const auto targets = detail::vector_targets();
  // The vector kernels are written for the study's model: any other runs on the reference.
  if (p_.kernel == "reference" || (p_.kernel == "auto" && (!p_.contact.is_study_model() || p_.lammps_rules))) {
    kernel_ = "reference";
    return;
  }
  if (!p_.contact.is_study_model()) {
    throw std::invalid_argument(fmt::format(
        "refsim: the {} kernels run the study's contact model (hertz, history, no rolling friction) only, not '{}'; "
        "use --kernel auto or reference",
        p_.kernel, model::liggghts_model_words(p_.contact)));
  }
  if (p_.kernel != "auto" && std::find(targets.begin(), targets.end(), p_.kernel) == targets.end()) {
    throw std::invalid_argument(fmt::format(
        "refsim: the {} kernels were asked for (--kernel {}), but this CPU and build run only {}; use --kernel auto, "
        "reference or one of those",
        p_.kernel, p_.kernel, fmt::join(targets, ", ")));
  }
  kernel_ = p_.kernel == "auto" ? targets.front() : p_.kernel;
  vector_ = std::make_unique<detail::VectorKernels>(detail::vector_kernels(kernel_));
}

System::~System() = default;

namespace {

struct Candidate {
  std::int32_t i, j;
  bool touching;
};
// A pair's history carried across a rebuild.
struct Kept {
  bool touching;
  double shear[3], roll[3];
};

// The table's entries: the candidates in `order`, each tile's group padded to whole kernel
// blocks (padding repeats the group's last pair with record 0), filled in the shares of the
// groups. Each share numbers the records it meets; the table's numbers are then given in the
// groups' order, as one pass through the table gives them. describe(i, j) gives a pair's records.
// Returns where each group starts in the table, and the table's end.
template <class Describe>
std::vector<std::size_t> fill_table(detail::PairTable& pairs, const std::vector<Candidate>& found, const std::vector<std::size_t>& order,
                const std::vector<std::size_t>& tile_start, const std::vector<Kept>& kept, const ForShares& shares,
                Describe describe) {
  const std::size_t groups = tile_start.size() - 1;
  std::vector<std::size_t> entry_start(groups + 1, 0);
  for (std::size_t g = 0; g < groups; ++g) {
    entry_start[g + 1] = entry_start[g] + (tile_start[g + 1] - tile_start[g] + detail::kPairBlock - 1) / detail::kPairBlock * detail::kPairBlock;
  }
  pairs.resize(entry_start[groups], shares);
  struct Local {
    std::size_t first_group = 0, end_group = 0;
    detail::RecordSet records;  // its padding record first, as the table's
  };
  std::mutex m;
  std::vector<Local> locals;
  shares(groups, [&](std::size_t first_group, std::size_t end_group) {
    Local local{first_group, end_group, {}};
    for (std::size_t g = first_group; g < end_group; ++g) {
      std::size_t q = entry_start[g];
      for (std::size_t c = tile_start[g]; c < tile_start[g + 1]; ++c, ++q) {
        const auto& f = found[order[c]];
        pairs.i[q] = f.i;
        pairs.j[q] = f.j;
        const auto [r, mr] = describe(static_cast<std::size_t>(f.i), static_cast<std::size_t>(f.j));
        pairs.record[q] = local.records.intern(r, mr);
        if (!kept.empty() && kept[order[c]].touching) {
          const auto& k = kept[order[c]];
          pairs.touching[q] = 1;
          pairs.shear_x[q] = k.shear[0];
          pairs.shear_y[q] = k.shear[1];
          pairs.shear_z[q] = k.shear[2];
          pairs.roll_x[q] = k.roll[0];
          pairs.roll_y[q] = k.roll[1];
          pairs.roll_z[q] = k.roll[2];
        }
      }
      for (; q < entry_start[g + 1]; ++q) {  // padding
        pairs.i[q] = pairs.i[q - 1];
        pairs.j[q] = pairs.j[q - 1];
      }
    }
    const std::lock_guard<std::mutex> lock(m);
    locals.push_back(std::move(local));
  });
  std::sort(locals.begin(), locals.end(), [](const Local& a, const Local& b) { return a.first_group < b.first_group; });
  std::vector<std::vector<std::int32_t>> renumber;
  for (const auto& local : locals) renumber.push_back(pairs.merge_records(local.records));
  shares(locals.size(), [&](std::size_t first, std::size_t end) {
    for (std::size_t l = first; l < end; ++l) {
      for (std::size_t q = entry_start[locals[l].first_group]; q < entry_start[locals[l].end_group]; ++q) {
        pairs.record[q] = renumber[l][static_cast<std::size_t>(pairs.record[q])];
      }
    }
  });
  return entry_start;
}

// The history each candidate keeps from the table before the rebuild: a pair keeps it only if it
// was flagged as touching and is within the contact distance now (none at the first build).
std::vector<Kept> kept_history(const detail::PairTable& old, const std::vector<Candidate>& found) {
  std::vector<std::size_t> old_order;
  for (std::size_t q = 0; q < old.count; ++q) {
    if (old.record[q] != 0) old_order.push_back(q);  // padding has record 0
  }
  if (old_order.empty()) return {};
  std::sort(old_order.begin(), old_order.end(),
            [&](std::size_t a, std::size_t b) { return old.i[a] != old.i[b] ? old.i[a] < old.i[b] : old.j[a] < old.j[b]; });
  std::vector<Kept> kept(found.size(), Kept{false, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}});
  for (std::size_t c = 0, o = 0; c < found.size(); ++c) {
    const auto& f = found[c];
    while (o < old_order.size() && (old.i[old_order[o]] < f.i || (old.i[old_order[o]] == f.i && old.j[old_order[o]] < f.j))) ++o;
    const std::size_t q = o < old_order.size() ? old_order[o] : 0;
    if (o < old_order.size() && old.i[q] == f.i && old.j[q] == f.j && old.touching[q] && f.touching) {
      kept[c] = {true, {old.shear_x[q], old.shear_y[q], old.shear_z[q]}, {old.roll_x[q], old.roll_y[q], old.roll_z[q]}};
    }
  }
  return kept;
}

// The table's order of the candidates: by tile of i, then j - i, then i, so that a block's
// particles lie in a window (tiles of tile_size particles). The candidates come in (i, j) order,
// so each tile's are together (tile_start gets where each tile's group starts, and their end), and
// each is sorted on its own.
std::vector<std::size_t> table_order(const std::vector<Candidate>& found, std::size_t tile_size, const ForShares& shares,
                                     std::vector<std::size_t>& tile_start) {
  std::vector<std::size_t> order(found.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = c;
  const auto tile = [&](std::int32_t i) { return static_cast<std::size_t>(i) / tile_size; };
  tile_start.clear();
  for (std::size_t c = 0; c < found.size(); ++c) {
    if (c == 0 || tile(found[c].i) != tile(found[c - 1].i)) tile_start.push_back(c);
  }
  tile_start.push_back(found.size());
  shares(tile_start.size() - 1, [&](std::size_t first_tile, std::size_t end_tile) {
    for (std::size_t t = first_tile; t < end_tile; ++t) {
      std::sort(order.begin() + static_cast<std::ptrdiff_t>(tile_start[t]),
                order.begin() + static_cast<std::ptrdiff_t>(tile_start[t + 1]), [&](std::size_t a, std::size_t b) {
                  const auto &u = found[a], &v = found[b];
                  return u.j - u.i != v.j - v.i ? u.j - u.i < v.j - v.i : u.i < v.i;
                });
    }
  });
  return order;
}

// Each particle's contributions in LIGGGHTS's pair order, by the other particle's index (counted,
// placed, then each particle's sorted in the shares): particle k's are contributions[offsets[k]
// .. offsets[k + 1]], j's entries at padded() + p.
void list_contributions(const detail::PairTable& pairs, std::size_t n, const ForShares& shares,
                        std::vector<std::size_t>& offsets, std::vector<std::pair<std::int32_t, std::uint32_t>>& contributions) {
  const std::size_t side_j = pairs.padded();
  offsets.assign(n + 1, 0);
  for (std::size_t p = 0; p < pairs.count; ++p) {
    if (pairs.record[p] == 0) continue;  // padding
    ++offsets[static_cast<std::size_t>(pairs.i[p]) + 1];
    ++offsets[static_cast<std::size_t>(pairs.j[p]) + 1];
  }
  for (std::size_t k = 0; k < n; ++k) offsets[k + 1] += offsets[k];
  contributions.resize(offsets[n]);
  std::vector<std::size_t> next(offsets.begin(), offsets.end() - 1);
  for (std::size_t p = 0; p < pairs.count; ++p) {
    if (pairs.record[p] == 0) continue;
    contributions[next[static_cast<std::size_t>(pairs.i[p])]++] = {pairs.j[p], static_cast<std::uint32_t>(p)};
    contributions[next[static_cast<std::size_t>(pairs.j[p])]++] = {pairs.i[p], static_cast<std::uint32_t>(side_j + p)};
  }
  shares(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      std::sort(contributions.begin() + static_cast<std::ptrdiff_t>(offsets[k]),
                contributions.begin() + static_cast<std::ptrdiff_t>(offsets[k + 1]));
    }
  });
}

}  // namespace

void System::build_pairs() {
  // Candidates: (R_i + R_j) * cdf + skin, as neigh_gran.cpp. A pair keeps its history across
  // the rebuild only if it was flagged as touching and is within the contact distance now.
  std::vector<Candidate> found;
  const double cdf = p_.contact_distance_factor;
  const double* x = x_.data();
  const double* y = x + stride_;
  const double* z = y + stride_;
  const auto shares = [this](std::size_t count, const std::function<void(std::size_t, std::size_t)>& job) {
    for_shares(count, job, 1);
  };
  const auto candidates = candidate_pairs({x, y, z, radius_.data(), n_}, cdf, p_.skin, shares);
  found.reserve(candidates.size());
  for (const auto& [a, b] : candidates) {
    const auto i = static_cast<std::size_t>(a), j = static_cast<std::size_t>(b);
    const double delx = x[i] - x[j];
    const double dely = y[i] - y[j];
    const double delz = z[i] - z[j];
    const double rsq = delx * delx + dely * dely + delz * delz;
    const double radsum = (radius_[i] + radius_[j]) * cdf;
    found.push_back({a, b, rsq < radsum * radsum});
  }
  // The history of the old pairs, merged in (i, j) order.
  detail::PairTable old;
  std::swap(old, *pairs_);
  const auto kept = kept_history(old, found);
  std::vector<std::size_t> tile_start;
  const auto order = table_order(found, kTile, shares, tile_start);
  const auto tile = [](std::int32_t i) { return static_cast<std::size_t>(i) / kTile; };
  pairs_->clear();
  pairs_->model = p_.contact;
  const auto entry_start = fill_table(*pairs_, found, order, tile_start, kept, shares, [&](std::size_t i, std::size_t j) {
    const std::size_t type_pair = static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                  static_cast<std::size_t>(type_[j] - 1);
    return detail::PairTable::describe(p_.contact, radius_[i], radius_[j], mass_[i], mass_[j], type_constants_[type_pair],
                                       model_constants_[type_pair]);
  });
  // Where each tile's pairs start (a tile without pairs where the next one's do).
  tile_first_.assign(1, 0);
  for (std::size_t g = 0; g + 1 < tile_start.size(); ++g) {
    while (tile_first_.size() <= tile(found[tile_start[g]].i)) tile_first_.push_back(entry_start[g]);
  }
  while (tile_first_.size() <= (n_ + kTile - 1) / kTile) tile_first_.push_back(pairs_->count);
  auto& pairs = *pairs_;
  pairs.finish(shares);
  const std::size_t side_j = pairs.padded();
  list_contributions(pairs, n_, shares, contribution_offsets_, contributions_);
  if (vector_) {
    sum_plan_->build(contribution_offsets_, contributions_, side_j, shares);
  }
  x_at_build_ = x_;
  find_wall_candidates();
  ++builds_;
}

namespace {
// A sphere's gap to a plane wall, negative where they overlap (primitive_wall_definitions.h).
double wall_gap(const Wall& wall, double pos, double radius) {
  return pos > wall.position ? pos - wall.position - radius : wall.position - pos - radius;
}
}  // namespace

void System::wall_force(std::size_t i, std::size_t wi, bool update_history) {
  const Wall& wall = p_.walls[wi];
  const int a = wall.axis;
  const double radi = radius_[i];
  const double pos = x_[static_cast<std::size_t>(a) * stride_ + i];
  double* shear = &wall_history_[3 * (wi * n_ + i)];
  double* roll = &wall_roll_[3 * (wi * n_ + i)];
  // Vector from the centre to the plane, and the gap (primitive_wall_definitions.h).
  double delta[3] = {0., 0., 0.};
  delta[a] = wall.position - pos;
  const double gap = wall_gap(wall, pos, radi);
  wall_touched_[wi * n_ + i] = gap <= 0.0;
  const bool stored = static_cast<int>(wi) == p_.stored_wall;
  if (stored) wall_store_[3 * i] = wall_store_[3 * i + 1] = wall_store_[3 * i + 2] = 0.0;
  if (p_.lammps_rules) {
    wall_force_lammps_rules(i, wi, update_history);
    return;
  }
  if (!(gap <= 0.0)) {  // not touching: a wall's history never survives a separation
    shear[0] = shear[1] = shear[2] = 0.0;
    roll[0] = roll[1] = roll[2] = 0.0;
    return;
  }
  const double overlap_in = -gap;
  const double dx = -delta[0], dy = -delta[1], dz = -delta[2];  // from the wall to the centre
  const double r = radi - overlap_in;
  const double rinv = 1.0 / r;
  const double enx = dx * rinv, eny = dy * rinv, enz = dz * rinv;
  const double meff = mass_[i];

  const Vec3 v = this->v(i), w = omega(i);
  const double vr1 = v[0] - 0.0, vr2 = v[1] - 0.0, vr3 = v[2] - 0.0;
  const double vn = vr1 * enx + vr2 * eny + vr3 * enz;
  const double vt1 = vr1 - vn * enx, vt2 = vr2 - vn * eny, vt3 = vr3 - vn * enz;
  const double deltan = radi - r;
  const double cr = radi - 0.5 * overlap_in;
  const double wr1 = cr * w[0] * rinv, wr2 = cr * w[1] * rinv, wr3 = cr * w[2] * rinv;
  const double vtr1 = vt1 - (dz * wr2 - dy * wr3);
  const double vtr2 = vt2 - (dx * wr3 - dz * wr1);
  const double vtr3 = vt3 - (dy * wr1 - dx * wr2);

  const std::size_t type_pair = static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                static_cast<std::size_t>(wall.type - 1);
  const auto& k = type_constants_[type_pair];
  // A wall has R* = R_i and m* = m_i.
  const auto model = detail::model_record(p_.contact, model_constants_[type_pair], radi, meff);
  const detail::Normal n = p_.contact.normal == model::NormalModel::hooke
                               ? detail::hooke_normal(model, deltan, vn, p_.tangential_damping)
                               : detail::hertz_normal(k, radi, meff, deltan, vn, p_.tangential_damping);
  const double fn = n.fn;
  double df[3] = {0.0 + fn * 1. * enx, 0.0 + fn * 1. * eny, 0.0 + fn * 1. * enz};  // * area_ratio (1)
  const double en[3] = {enx, eny, enz}, vtr[3] = {vtr1, vtr2, vtr3};
  double ft[3], tor[3];
  if (p_.contact.tangential == model::TangentialModel::no_history) {
    detail::tangential_no_history(en, vtr, n, k.friction, ft, tor);
  } else {
    detail::tangential_force(shear, en, vtr, n, k.friction, update_history, p_.dt, ft, tor);
  }
  df[0] += ft[0] * 1.;
  df[1] += ft[1] * 1.;
  df[2] += ft[2] * 1.;
  // epsd2 on a wall turns the contact point's rotation speed, wr = cr omega / r, not omega.
  double rt[3] = {0.0, 0.0, 0.0};
  if (p_.contact.rolling != model::RollingModel::off) {
    const double wr[3] = {wr1, wr2, wr3};
    detail::rolling_torque(roll, en, wr, n, radi, model.rolling_friction, update_history, p_.dt, rt);
  }
  for (std::size_t d = 0; d < 3; ++d) {
    const double before = f_[d * stride_ + i];
    f_[d * stride_ + i] += df[d];
    if (stored) wall_store_[3 * i + d] = f_[d * stride_ + i] - before;
    double dt = 0.0 + -cr * tor[d] * 1.;
    if (p_.contact.rolling != model::RollingModel::off) dt -= rt[d];
    t_[d * stride_ + i] += dt;
  }
}

void System::wall_force_lammps_rules(std::size_t i, std::size_t wi, bool update_history) {
  const Wall& wall = p_.walls[wi];
  const std::size_t type_pair = static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                static_cast<std::size_t>(wall.type - 1);
  const double pos = x_[static_cast<std::size_t>(wall.axis) * stride_ + i];
  const Vec3 v = this->v(i), w = omega(i);
  const auto record = detail::model_record(p_.contact, model_constants_[type_pair], radius_[i], mass_[i]);
  double force[3], torque[3];
  if (!detail::wall_force_lammps(wall.axis, pos - wall.position, radius_[i], mass_[i], v.data(), w.data(),
                                 type_constants_[type_pair], record, &wall_history_[3 * (wi * n_ + i)], update_history,
                                 p_.dt, force, torque)) {
    return;
  }
  const bool stored = static_cast<int>(wi) == p_.stored_wall;
  for (std::size_t d = 0; d < 3; ++d) {
    f_[d * stride_ + i] += force[d];
    if (stored) wall_store_[3 * i + d] = force[d];
    t_[d * stride_ + i] += torque[d];
  }
}

// The particles that may touch each wall before the next build (wall_near_): those touching it
// at their last force call, and those within a skin of it now.
void System::find_wall_candidates() {
  wall_near_.assign(p_.walls.size(), {});
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    const double* pos = x_.data() + static_cast<std::size_t>(p_.walls[w].axis) * stride_;
    for (std::size_t i = 0; i < n_; ++i) {
      // Within a skin: twice the half skin a particle may move, for a margin far above rounding.
      if (wall_touched_[w * n_ + i] != 0 || wall_gap(p_.walls[w], pos[i], radius_[i]) <= p_.skin) {
        wall_near_[w].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
}

// Each particle of [begin, end) in turn meets the walls, then gravity (each particle's sums in the
// deck's order: walls by number, then gravity). Of the particles that may touch a wall, those
// neither touching it now nor at their last call have nothing to compute or clear there.
void System::external_forces(std::size_t begin, std::size_t end, bool update_history) {
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    if (p_.lammps_rules) {  // LAMMPS's rules: every particle, as wall_force_lammps_rules decides
      for (std::size_t i = begin; i < end; ++i) wall_force(i, w, update_history);
      continue;
    }
    const Wall wall = p_.walls[w];
    const double* pos = x_.data() + static_cast<std::size_t>(wall.axis) * stride_;
    const auto& near = wall_near_[w];
    auto k = std::lower_bound(near.begin(), near.end(), static_cast<std::uint32_t>(begin));
    for (; k != near.end() && *k < end; ++k) {
      if (wall_touched_[w * n_ + *k] != 0 || wall_gap(wall, pos[*k], radius_[*k]) <= 0.0) wall_force(*k, w, update_history);
    }
  }
  if (p_.gravity[0] != 0.0 || p_.gravity[1] != 0.0 || p_.gravity[2] != 0.0) {
    for (std::size_t i = begin; i < end; ++i) {
      const double m = mass_[i] * 1.;
      for (std::size_t d = 0; d < 3; ++d) f_[d * stride_ + i] += m * p_.gravity[d];
    }
  }
}

// Each particle's force and torque: its contacts' contributions in pair order, then the walls
// and gravity, the post_force fixes that follow the pair style. The same sums in the same order
// as LIGGGHTS's pair loop, whichever thread adds them.
void System::sum_forces(std::size_t begin, std::size_t end, bool update_history, bool kick, bool drift) {
  const auto& c = *pairs_;
  const auto m = motion();
  bool moved = false;
  if (vector_) {
    std::size_t kept = 0;  // groups whose sums were kept
    // In chunks that stay in the L1 cache from the sums to the kick.
    constexpr std::size_t chunk = 8 * detail::kLanes;
    for (std::size_t b = begin; b < end; b += chunk) {
      const std::size_t e = std::min(end, b + chunk);
      // The groups due, in runs.
      const std::size_t last = (e + detail::kLanes - 1) / detail::kLanes;
      for (std::size_t g = b / detail::kLanes; g < last;) {
        if (skip_sums_ && sums_due_[g] == 0) {
          ++g;
          ++kept;
          continue;
        }
        std::size_t h = g + 1;
        while (h < last && (!skip_sums_ || sums_due_[h] != 0)) ++h;
        vector_->sum_contributions(c, *sum_plan_, f_.data(), t_.data(), stride_, g, h, m.spin);
        g = h;
      }
      if (external_) external_forces(b, e, update_history);
      if (kick && drift) {
        moved |= vector_->second_and_first_half(m, b, e);
      } else if (kick) {
        vector_->second_half(m, b, e);
      }
    }
    if (kept > 0) kept_sums_.fetch_add(kept, std::memory_order_relaxed);
    if (moved) moved_.store(true, std::memory_order_relaxed);
    return;
  }
  const std::size_t y = stride_, z = 2 * stride_, side_j = c.padded();
  for (std::size_t k = begin; k < end; ++k) {
    double fx = 0.0, fy = 0.0, fz = 0.0, tx = 0.0, ty = 0.0, tz = 0.0;
    for (std::size_t e = contribution_offsets_[k]; e < contribution_offsets_[k + 1]; ++e) {
      const std::size_t q = contributions_[e].second;
      if (q < side_j) {
        fx += c.fx[q];
        fy += c.fy[q];
        fz += c.fz[q];
      } else {  // j of the pair: minus the force on i
        fx -= c.fx[q - side_j];
        fy -= c.fy[q - side_j];
        fz -= c.fz[q - side_j];
      }
      tx += c.tx[q];
      ty += c.ty[q];
      tz += c.tz[q];
    }
    f_[k] = fx;
    f_[y + k] = fy;
    f_[z + k] = fz;
    t_[k] = tx;
    t_[y + k] = ty;
    t_[z + k] = tz;
    if (external_) external_forces(k, k + 1, update_history);
    if (kick) detail::second_half_reference(m, k, k + 1);
    if (drift) moved |= detail::first_half_reference(m, k, k + 1);
  }
  if (moved) moved_.store(true, std::memory_order_relaxed);
}

// The pair forces, then per particle its sums, walls and gravity and, within a step, the
// second half kick (a particle's kick needs only its own force and torque), and if the next
// step follows at once, its first half too: no pair left to compute uses the particle.
void System::compute_forces(bool update_history, bool kick, bool drift) {
  detail::ContactStep s{x_.data(),      v_.data(),           w_.data(),
                        stride_,        p_.dt,               p_.contact_distance_factor,
                        update_history, p_.tangential_damping, p_.lammps_rules, position_changed_.data()};
  // Elastic frictionless pairs and nothing else acting: a group of particles none of whose pairs
  // was evaluated again keeps its force sums (the same contributions in the same order give the
  // same bits), so they are not taken again (sum_forces). On one thread its pairs all lie in
  // tiles up to its own, so by its tile's sums their evaluation is known; on several, every
  // pair is evaluated before any sum is taken.
  // Marking the groups costs about as much as it saves once most spheres move: it is tried for
  // a step every kSumsProbe steps, and kept on while it keeps a quarter of the sums or more.
  constexpr long kSumsProbe = 64;
  const bool may_skip = vector_ && pairs_->torque_free && !external_;
  const std::size_t groups = sums_due_.size();
  if (skip_sums_) skip_sums_ = 4 * kept_sums_.load(std::memory_order_relaxed) >= groups;  // the last step's
  if (!skip_sums_) skip_sums_ = step_ % kSumsProbe == 0;
  skip_sums_ = skip_sums_ && may_skip;
  kept_sums_.store(0, std::memory_order_relaxed);
  if (skip_sums_) {
    std::fill(sums_due_.begin(), sums_due_.end(), std::uint8_t{0});
    s.sums_due = sums_due_.data();
  }
  auto& pairs = *pairs_;
  const auto contacts = [&](std::size_t begin, std::size_t end) {
    if (vector_) {
      vector_->contacts(pairs, s, begin, end);
    } else {
      detail::contacts_reference(pairs, s, begin, end);
    }
  };
  if (workers_->size() == 1) {
    // Tile by tile: every pair of a particle has its i at or before the particle, so its sums
    // can be taken right after its tile's pairs, while their contributions are in the cache.
    for (std::size_t t = 0; t + 1 < tile_first_.size(); ++t) {
      contacts(tile_first_[t], tile_first_[t + 1]);
      sum_forces(t * kTile, std::min(n_, (t + 1) * kTile), update_history, kick, drift);
    }
    return;
  }
  for_shares(pairs.padded(), contacts, detail::kPairBlock);
  for_shares(
      n_, [&](std::size_t begin, std::size_t end) { sum_forces(begin, end, update_history, kick, drift); }, detail::kLanes);
}

void System::setup() { compute_forces(false, false, false); }


std::array<double, 2> System::kinetic_energy(std::size_t begin, std::size_t end) const {
  double ke[detail::kLanes] = {}, rot[detail::kLanes] = {};
  const detail::KineticInput in{mass_.data(), radius_.data(), v_.data(), w_.data(), stride_};
  if (vector_) {
    vector_->kinetic_sums(in, begin, end, ke, rot);
  } else {
    detail::kinetic_sums_reference(in, begin, end, ke, rot);
  }
  static_assert(detail::kLanes == 8, "the pairwise order below is written for eight partial sums");
  const auto total = [](const double* s) { return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])); };
  return {total(ke) * (0.5 * 1.0), total(rot) * (0.5 * 1.0 * kInertia)};
}

detail::Motion System::motion() {
  const double half = 0.5 * p_.skin;
  const bool spinless = pairs_->torque_free && p_.walls.empty() && !negative_zero_spin_;
  return {x_.data(), v_.data(), w_.data(), f_.data(), t_.data(), kick_.data(), spin_kick_.data(), x_at_build_.data(),
          position_changed_.data(), stride_, p_.dt, half * half, !spinless};
}

void System::step() { advance(1); }

void System::advance(long steps) {
  for (long k = 0; k < steps; ++k) {
    if (!drifted_) {
      const auto m = motion();
      moved_ = false;
      for_shares(
          n_,
          [&](std::size_t begin, std::size_t end) {
            if (vector_ ? vector_->first_half(m, begin, end) : detail::first_half_reference(m, begin, end)) {
              moved_.store(true, std::memory_order_relaxed);
            }
          },
          detail::kLanes);
    }
    if (moved_.load(std::memory_order_relaxed)) build_pairs();
    drifted_ = k + 1 < steps;
    moved_ = false;
    compute_forces(true, true, drifted_);
    ++step_;
  }
}

}  // namespace granstack::refsim
