#include <granstack/refsim/system.hpp>

#include <granstack/model/plate.hpp>

#include <granstack/refsim/neighbors.hpp>

#include "contacts.hpp"
#include "contact_models/sub_models.hpp"

#include <granstack/model/contact.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

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
  if (p_.contact.normal == model::NormalModel::thornton && p_.yield_pressure.size() != tt) {
    throw std::invalid_argument("refsim: normal_model thornton needs the yield pressure per type pair");
  }
  if (p_.contact.normal == model::NormalModel::thornton_ning && p_.yield_ratio.size() != static_cast<std::size_t>(p_.types)) {
    throw std::invalid_argument("refsim: normal_model thornton_ning needs the yield ratio per type");
  }
  // The engine's rules: the sub-models every contact is composed of (contact_models/choice.hpp).
  pairs_->sub_models = p_.lammps_rules ? detail::lammps_rules(p_.contact) : detail::liggghts_rules(p_.contact);
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
  wall_history_.assign(detail::history_layout(pairs_->sub_models).size * n_ * p_.walls.size(), 0.0);
  wall_store_.assign(p_.stored_wall >= 0 ? 3 * n_ : 0, 0.0);
  if (p_.plate.wall >= 0) {
    if (p_.plate.wall != p_.stored_wall || p_.walls[static_cast<std::size_t>(p_.plate.wall)].axis != 2) {
      throw std::invalid_argument("refsim: the plate must be the stored wall, normal to z");
    }
    if (!(p_.plate.mass > 0.0) || !(p_.plate.stiffness >= 0.0) || !(p_.plate.damping >= 0.0)) {
      throw std::invalid_argument("refsim: a plate needs a positive mass and a mount of stiffness and damping >= 0");
    }
    plate_body_ = p_.plate.body_start;
    plate_body_at_build_ = plate_body_;
  }
  if (detail::has_contact_energy(pairs_->sub_models)) banked_.assign(n_, 0.0);
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
    if (pairs_->sub_models.frame == detail::Frame::lammps) {
      detail::tsuji_constants(p_.restitution.empty() ? 1.0 : p_.restitution[k], p_.g_star[k], p_.y_star[k],
                              model_constants_.back());
    }
    if (!p_.yield_pressure.empty()) model_constants_.back().yield_pressure = p_.yield_pressure[k];
    if (!p_.yield_ratio.empty()) model_constants_.back().yield_ratio = p_.yield_ratio[k / static_cast<std::size_t>(p_.types)];
  }
  choose_kernels();
  // The threads first: the first neighbour build runs on them.
  workers_ = std::make_unique<os::Workers>(p_.threads);
  build_pairs();
}

std::vector<std::string> vector_kernels() { return detail::vector_targets(); }

void System::choose_kernels() {
  const auto targets = detail::vector_targets();
  // The vector kernels run LIGGGHTS's rules: LAMMPS's run on the reference, which `auto` then picks.
  if (p_.kernel == "reference" || (p_.kernel == "auto" && p_.lammps_rules)) {
    kernel_ = "reference";
    return;
  }
  if (p_.lammps_rules) {
    throw std::invalid_argument(fmt::format("the {} kernels run LIGGGHTS's contact rules only, not LAMMPS's; use --kernel "
                                            "auto or reference",
                                            p_.kernel));
  }
  if (p_.kernel != "auto" && std::find(targets.begin(), targets.end(), p_.kernel) == targets.end()) {
    throw std::invalid_argument(fmt::format(
        "refsim: the {} kernels were asked for (--kernel {}), but this CPU and build run only {}; use --kernel auto, "
        "reference or one of those",
        p_.kernel, p_.kernel, fmt::join(targets, ", ")));
  }
  const std::string target = p_.kernel == "auto" ? targets.front() : p_.kernel;
  vector_ = std::make_unique<detail::VectorKernels>(detail::vector_kernels(target));
  choose_pair_kernels(target);
}

// The vector pair kernels are written for the study's model: any other's pairs run on the
// reference kernel, its particles (integration, force sums, kinetic sums) on the vector kernels,
// which give the reference's bits whatever the pairs' model.
void System::choose_pair_kernels(const std::string& target) {
  const auto& m = pairs_->sub_models;
  vector_contacts_ = m.vector_kernels_run();
  // On a torque_free table (no friction, no damping, no rolling friction): Thornton's law by
  // LIGGGHTS's rules in lanes; another positional law's still blocks kept.
  const bool thornton = m.frame == detail::Frame::liggghts && m.normal == model::NormalModel::thornton;
  if (!vector_contacts_ && thornton) {
    still_kernel_ = vector_->thornton;
  } else if (!vector_contacts_ && detail::positional_force(m)) {
    still_kernel_ = vector_->still_reference;
  }
  const bool torque_free = m.rolling == model::RollingModel::off &&
                           std::all_of(type_constants_.begin(), type_constants_.end(),
                                       [](const detail::PairConstants& k) { return !k.damped() && k.friction == 0.0; });
  kernel_ = vector_contacts_ || (thornton && torque_free) ? target : target + kReferencePairs;
}

System::~System() = default;

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
                        update_history, p_.tangential_damping, position_changed_.data()};
  s.banked = banked_.empty() ? nullptr : banked_.data();
  // Elastic frictionless pairs and nothing else acting: a group of particles none of whose pairs
  // was evaluated again keeps its force sums (the same contributions in the same order give the
  // same bits), so they are not taken again (sum_forces). On one thread its pairs all lie in
  // tiles up to its own, so by its tile's sums their evaluation is known; on several, every
  // pair is evaluated before any sum is taken.
  // Marking the groups costs about as much as it saves once most spheres move: it is tried for
  // a step every kSumsProbe steps, and kept on while it keeps a quarter of the sums or more.
  constexpr long kSumsProbe = 64;
  // A torque_free table of a positional law (still_kernel_) keeps still blocks' entries too.
  const bool still_pairs = still_kernel_ != nullptr && pairs_->torque_free;
  const bool may_skip = (vector_contacts_ || still_pairs) && pairs_->torque_free && !external_;
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
    if (vector_contacts_) {
      vector_->contacts(pairs, s, begin, end);
    } else if (still_pairs) {
      still_kernel_(pairs, s, begin, end);
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
  } else {
    for_shares(pairs.padded(), contacts, detail::kPairBlock);
    for_shares(
        n_, [&](std::size_t begin, std::size_t end) { sum_forces(begin, end, update_history, kick, drift); },
        detail::kLanes);
  }
  if (p_.plate.wall >= 0) plate_after_forces(kick, drift);
}

double System::stored_wall_total() const {
  double sum = 0.0;  // compute reduce sum: from 0, atom by atom in id order
  for (std::size_t i = 0; i < n_; ++i) sum += wall_store_.empty() ? 0.0 : wall_store_[3 * i + 2];
  return sum;
}

// The plate as fix nve/sphere moves an atom of its mass (dtf / m, then x += dt v), pushed by the
// addforce of the deck's formula (model::plate_force) once every particle's wall force is known.
void System::plate_after_forces(bool kick, bool drift) {
  plate_f_ = model::plate_force(stored_wall_total(), plate_body_ - p_.plate.body_start, plate_v_, p_.plate.stiffness,
                                p_.plate.damping);
  if (kick) plate_v_ += (0.5 * p_.dt * 1.0) / p_.plate.mass * plate_f_;
  if (drift) plate_first_half();
}

void System::plate_first_half() {
  plate_v_ += (0.5 * p_.dt * 1.0) / p_.plate.mass * plate_f_;
  plate_z_ += p_.dt * plate_v_;      // fix move/mesh: the mesh's travel, v dt summed
  plate_body_ += p_.dt * plate_v_;   // fix nve/sphere: the body's x += dt v
  // A neighbour build when the body has moved half the skin (the mesh, moving with it, asks for
  // one a step later, which that build has already made).
  const double moved = plate_body_ - plate_body_at_build_, half = 0.5 * p_.skin;
  if (moved * moved > half * half) moved_.store(true, std::memory_order_relaxed);
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
      if (p_.plate.wall >= 0) plate_first_half();
    }
    if (moved_.load(std::memory_order_relaxed)) build_pairs();
    drifted_ = k + 1 < steps;
    moved_ = false;
    compute_forces(true, true, drifted_);
    ++step_;
  }
}

}  // namespace granstack::refsim
