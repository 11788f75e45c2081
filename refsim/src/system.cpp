#include <granstack/refsim/system.hpp>

#include <cmath>
#include <stdexcept>
#include <thread>

namespace granstack::refsim {

namespace {
// sqrt(5/6), with the digits LIGGGHTS hard-codes (normal_model_hertz.h).
constexpr double kSqrtFiveOverSix = 0.91287092917527685576161630466800355658790782499663875;
// I = 0.4 m R^2 for solid spheres (fix_nve_sphere.cpp).
constexpr double kInertia = 0.4;
}  // namespace

System::System(std::vector<Particle> particles, Parameters params) : n_(particles.size()), p_(std::move(params)) {
  const std::size_t tt = static_cast<std::size_t>(p_.types) * static_cast<std::size_t>(p_.types);
  if (p_.y_star.size() != tt || p_.g_star.size() != tt || p_.beta.size() != tt || p_.friction.size() != tt) {
    throw std::invalid_argument("refsim: every property table needs types x types entries");
  }
  type_.resize(n_);
  radius_.resize(n_);
  mass_.resize(n_);
  x_.resize(3 * n_);
  v_.resize(3 * n_);
  w_.resize(3 * n_);
  f_.assign(3 * n_, 0.0);
  t_.assign(3 * n_, 0.0);
  for (std::size_t i = 0; i < n_; ++i) {
    const auto& pa = particles[i];
    if (pa.type < 1 || pa.type > p_.types) throw std::invalid_argument("refsim: particle type outside the tables");
    type_[i] = pa.type;
    radius_[i] = pa.radius;
    mass_[i] = pa.mass;
    for (int d = 0; d < 3; ++d) {
      x_[3 * i + d] = pa.x[d];
      v_[3 * i + d] = pa.v[d];
      w_[3 * i + d] = pa.omega[d];
    }
  }
  wall_history_.assign(3 * n_ * p_.walls.size(), 0.0);
  const double dtf = 0.5 * p_.dt * 1.0;
  const double dtfrotate = dtf / kInertia;
  for (std::size_t i = 0; i < n_; ++i) {
    kick_.push_back(dtf / (mass_[i] * 1.0));
    spin_kick_.push_back(dtfrotate / (radius_[i] * radius_[i] * mass_[i]));
  }
  for (std::size_t k = 0; k < tt; ++k) {
    type_constants_.push_back({4. / 3. * p_.y_star[k], 2. * p_.y_star[k], 8. * p_.g_star[k], -2. * kSqrtFiveOverSix * p_.beta[k],
                               p_.friction[k], p_.beta[k] != 0.0});
  }
  build_pairs();
  threads_ = std::max(1, p_.threads);
  for (int t = 1; t < threads_; ++t) workers_.emplace_back([this, t] { worker(t); });
}

System::~System() {
  stop_ = true;
  generation_.fetch_add(1, std::memory_order_release);
  for (auto& w : workers_) w.join();
}

namespace {
void relax_cpu(long spins) {
  if (spins < 2000) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  } else {
    std::this_thread::yield();  // oversubscribed: let the other work run
  }
}
}  // namespace

void System::worker(int index) {
  long seen = 0;
  for (;;) {
    long g, spins = 0;
    while ((g = generation_.load(std::memory_order_acquire)) == seen) relax_cpu(spins++);
    seen = g;
    if (stop_) return;
    job_(index);
    finished_.fetch_add(1, std::memory_order_release);
  }
}

void System::parallel(const std::function<void(int)>& job) {
  job_ = job;
  finished_.store(0, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  job(0);
  long spins = 0;
  while (finished_.load(std::memory_order_acquire) < threads_ - 1) relax_cpu(spins++);
}

std::pair<std::size_t, std::size_t> System::share(std::size_t count, int index) const {
  const std::size_t t = static_cast<std::size_t>(threads_), k = static_cast<std::size_t>(index);
  return {count * k / t, count * (k + 1) / t};
}

void System::for_shares(std::size_t count, const std::function<void(std::size_t, std::size_t)>& job) {
  if (threads_ <= 1) {
    job(0, count);
    return;
  }
  parallel([&](int t) {
    const auto [begin, end] = share(count, t);
    job(begin, end);
  });
}

void System::build_pairs() {
  // Candidates: (R_i + R_j) * cdf + skin, as neigh_gran.cpp. A pair keeps its history across
  // the rebuild only if it was flagged as touching and is within the contact distance now.
  std::vector<std::size_t> old_i, old_j;
  std::vector<double> old_history;
  std::vector<unsigned char> old_flag;
  old_i.swap(pair_i_);
  old_j.swap(pair_j_);
  old_history.swap(pair_history_);
  old_flag.swap(pair_flag_);
  pair_reff_.clear();
  pair_meff_.clear();
  pair_constants_.clear();
  std::size_t old = 0;  // old pairs are sorted by (i, j): merge as we go
  const double cdf = p_.contact_distance_factor;
  for (std::size_t i = 0; i < n_; ++i) {
    const double xi = x_[3 * i], yi = x_[3 * i + 1], zi = x_[3 * i + 2];
    for (std::size_t j = i + 1; j < n_; ++j) {
      const double delx = xi - x_[3 * j];
      const double dely = yi - x_[3 * j + 1];
      const double delz = zi - x_[3 * j + 2];
      const double rsq = delx * delx + dely * dely + delz * delz;
      const double radsum = (radius_[i] + radius_[j]) * cdf;
      const double cut = radsum + p_.skin;
      if (rsq > cut * cut) continue;
      while (old < old_i.size() && (old_i[old] < i || (old_i[old] == i && old_j[old] < j))) ++old;
      const bool had = old < old_i.size() && old_i[old] == i && old_j[old] == j;
      pair_i_.push_back(i);
      pair_j_.push_back(j);
      pair_reff_.push_back(radius_[i] * radius_[j] / (radius_[i] + radius_[j]));
      pair_meff_.push_back(mass_[i] * mass_[j] / (mass_[i] + mass_[j]));
      pair_constants_.push_back(&type_constants_[static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                                 static_cast<std::size_t>(type_[j] - 1)]);
      if (had && old_flag[old] && rsq < radsum * radsum) {
        pair_flag_.push_back(1);
        pair_history_.insert(pair_history_.end(), old_history.begin() + 3 * old, old_history.begin() + 3 * old + 3);
      } else {
        pair_flag_.push_back(0);
        pair_history_.insert(pair_history_.end(), {0.0, 0.0, 0.0});
      }
    }
  }
  atom_pair_offsets_.assign(n_ + 1, 0);
  for (std::size_t q = 0; q < pair_i_.size(); ++q) {
    ++atom_pair_offsets_[pair_i_[q] + 1];
    ++atom_pair_offsets_[pair_j_[q] + 1];
  }
  for (std::size_t i = 0; i < n_; ++i) atom_pair_offsets_[i + 1] += atom_pair_offsets_[i];
  atom_pairs_.resize(2 * pair_i_.size());
  std::vector<std::size_t> fill(atom_pair_offsets_.begin(), atom_pair_offsets_.end() - 1);
  for (std::size_t q = 0; q < pair_i_.size(); ++q) {
    atom_pairs_[fill[pair_i_[q]]++] = 2 * q;
    atom_pairs_[fill[pair_j_[q]]++] = 2 * q + 1;
  }
  contributions_.resize(pair_i_.size());
  x_at_build_ = x_;
  ++builds_;
}

bool System::needs_rebuild() const {
  const double half = 0.5 * p_.skin;
  const double trigger = half * half;
  for (std::size_t i = 0; i < n_; ++i) {
    const double dx = x_[3 * i] - x_at_build_[3 * i];
    const double dy = x_[3 * i + 1] - x_at_build_[3 * i + 1];
    const double dz = x_[3 * i + 2] - x_at_build_[3 * i + 2];
    if (dx * dx + dy * dy + dz * dz > trigger) return true;
  }
  return false;
}

namespace {

struct Normal {
  double fn, kt, gammat;
};

// Hertz normal force with restitution damping, and the tangential stiffness and damping
// (normal_model_hertz.h). With beta = 0 (e = 1) the damping coefficients are -0.0 whatever the
// square root, so it is not taken.
template <typename Constants>
Normal hertz_normal(const Constants& k, double reff, double meff, double deltan, double vn, bool tangential_damping) {
  const double sqrtval = std::sqrt(reff * deltan);
  const double kt = k.st_factor * sqrtval;
  const double kn = k.kn_factor * sqrtval;
  const double gamman = k.damped ? k.damping_factor * std::sqrt(k.sn_factor * sqrtval * meff) : k.damping_factor;
  const double gammat = !tangential_damping ? 0.0 : k.damped ? k.damping_factor * std::sqrt(kt * meff) : k.damping_factor;
  return {-gamman * vn + kn * deltan, kt, gammat};
}

struct Tangential {
  double ft[3];   // the tangential force on i
  double tor[3];  // n x Ft: the torque on each sphere is -(its lever arm) times this
};

// The tangential history spring (tangential_model_history.h): increment by the sliding
// velocity, project on the tangent plane, Coulomb-truncate (no damping while sliding).
void tangential_history(double* shear, const double en[3], const double vtr[3], const Normal& n, double mu,
                        bool update_history, double dt, double ft[3]);

Tangential tangential_force(double* shear, const double en[3], const double vtr[3], const Normal& n, double mu,
                            bool update_history, double dt) {
  Tangential t;
  tangential_history(shear, en, vtr, n, mu, update_history, dt, t.ft);
  t.tor[0] = en[1] * t.ft[2] - en[2] * t.ft[1];
  t.tor[1] = en[2] * t.ft[0] - en[0] * t.ft[2];
  t.tor[2] = en[0] * t.ft[1] - en[1] * t.ft[0];
  return t;
}

void tangential_history(double* shear, const double en[3], const double vtr[3], const Normal& n, double mu,
                        bool update_history, double dt, double ft[3]) {
  if (update_history) {
    shear[0] += vtr[0] * dt;
    shear[1] += vtr[1] * dt;
    shear[2] += vtr[2] * dt;
    const double rsht = shear[0] * en[0] + shear[1] * en[1] + shear[2] * en[2];
    shear[0] -= rsht * en[0];
    shear[1] -= rsht * en[1];
    shear[2] -= rsht * en[2];
  }
  const double kt = n.kt;
  const double shear_sq = shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2];
  ft[0] = -(kt * shear[0]);
  ft[1] = -(kt * shear[1]);
  ft[2] = -(kt * shear[2]);
  if (mu == 0.0 && kt > 0.0 && shear_sq > 0.0) {
    // Frictionless: LIGGGHTS slides with ratio 0 / (kt |xi|), leaving a zero force and a zero
    // history; the same without the square root and the four divisions (only signs of zero differ).
    ft[0] = ft[1] = ft[2] = 0.0;
    if (update_history) shear[0] = shear[1] = shear[2] = 0.0;
    return;
  }
  const double shrmag = std::sqrt(shear_sq);
  const double ft_shear = kt * shrmag;
  const double ft_friction = mu * std::fabs(n.fn);
  if (ft_shear > ft_friction) {
    if (shrmag != 0.0) {
      const double ratio = ft_friction / ft_shear;
      for (int d = 0; d < 3; ++d) ft[d] *= ratio;
      if (update_history) {
        for (int d = 0; d < 3; ++d) shear[d] = -ft[d] / kt;
      }
    } else {
      ft[0] = ft[1] = ft[2] = 0.0;
    }
  } else {
    for (int d = 0; d < 3; ++d) ft[d] -= n.gammat * vtr[d];
  }
}

}  // namespace

void System::pair_force(std::size_t p, bool update_history, Contribution& c) {
  c.touching = false;
  const std::size_t i = pair_i_[p], j = pair_j_[p];
  const double* xi = &x_[3 * i];
  const double* xj = &x_[3 * j];
  const double delx = xi[0] - xj[0];
  const double dely = xi[1] - xj[1];
  const double delz = xi[2] - xj[2];
  const double rsq = delx * delx + dely * dely + delz * delz;
  const double radi = radius_[i], radj = radius_[j];
  const double radsum = radi + radj;
  double* shear = &pair_history_[3 * p];
  if (!(rsq < radsum * radsum)) {
    // Close but not touching: the history is reset (surfacesClose); farther: left alone.
    const double cdf = p_.contact_distance_factor;
    if (rsq < cdf * cdf * radsum * radsum) {
      pair_flag_[p] = 0;
      shear[0] = shear[1] = shear[2] = 0.0;
    }
    return;
  }
  pair_flag_[p] = 1;
  c.touching = true;
  const double r = std::sqrt(rsq);
  const double rinv = 1.0 / r;
  const double enx = delx * rinv, eny = dely * rinv, enz = delz * rinv;
  const double meff = pair_meff_[p];

  // Relative velocity at the contact point; lever arms shortened by half the overlap.
  const double* vi = &v_[3 * i];
  const double* vj = &v_[3 * j];
  const double* wi = &w_[3 * i];
  const double* wj = &w_[3 * j];
  const double vr1 = vi[0] - vj[0], vr2 = vi[1] - vj[1], vr3 = vi[2] - vj[2];
  const double vn = vr1 * enx + vr2 * eny + vr3 * enz;
  const double vt1 = vr1 - vn * enx, vt2 = vr2 - vn * eny, vt3 = vr3 - vn * enz;
  const double deltan = radsum - r;
  const double cri = radi - 0.5 * deltan;
  const double crj = radj - 0.5 * deltan;
  const double wr1 = (cri * wi[0] + crj * wj[0]) * rinv;
  const double wr2 = (cri * wi[1] + crj * wj[1]) * rinv;
  const double wr3 = (cri * wi[2] + crj * wj[2]) * rinv;
  const double vtr1 = vt1 - (delz * wr2 - dely * wr3);
  const double vtr2 = vt2 - (delx * wr3 - delz * wr1);
  const double vtr3 = vt3 - (dely * wr1 - delx * wr2);

  const PairConstants& k = *pair_constants_[p];
  const Normal n = hertz_normal(k, pair_reff_[p], meff, deltan, vn, p_.tangential_damping);
  const double fn = n.fn;
  // Contributions are summed onto zeroed accumulators, as LIGGGHTS's ForceData (0 + x turns a
  // -0 into +0, which a %.17g dump shows).
  double dfi[3] = {0.0 + fn * enx, 0.0 + fn * eny, 0.0 + fn * enz};
  double dfj[3] = {0.0 + -dfi[0], 0.0 + -dfi[1], 0.0 + -dfi[2]};
  const double en[3] = {enx, eny, enz}, vtr[3] = {vtr1, vtr2, vtr3};
  const auto tan = tangential_force(shear, en, vtr, n, k.friction, update_history, p_.dt);
  const double ft1 = tan.ft[0], ft2 = tan.ft[1], ft3 = tan.ft[2];
  const double tor1 = tan.tor[0], tor2 = tan.tor[1], tor3 = tan.tor[2];
  c.fi[0] = dfi[0] + ft1;
  c.fi[1] = dfi[1] + ft2;
  c.fi[2] = dfi[2] + ft3;
  c.fj[0] = dfj[0] + -ft1;
  c.fj[1] = dfj[1] + -ft2;
  c.fj[2] = dfj[2] + -ft3;
  c.ti[0] = 0.0 + -cri * tor1;
  c.ti[1] = 0.0 + -cri * tor2;
  c.ti[2] = 0.0 + -cri * tor3;
  c.tj[0] = 0.0 + -crj * tor1;
  c.tj[1] = 0.0 + -crj * tor2;
  c.tj[2] = 0.0 + -crj * tor3;
}

void System::wall_force(std::size_t i, std::size_t wi, bool update_history) {
  const Wall& wall = p_.walls[wi];
  const int a = wall.axis;
  const double radi = radius_[i];
  const double pos = x_[3 * i + a];
  double* shear = &wall_history_[3 * (wi * n_ + i)];
  // Vector from the centre to the plane, and the gap (primitive_wall_definitions.h).
  double delta[3] = {0., 0., 0.};
  delta[a] = wall.position - pos;
  const double gap = pos > wall.position ? pos - wall.position - radi : wall.position - pos - radi;
  if (!(gap <= 0.0)) {  // not touching: a wall's history never survives a separation
    shear[0] = shear[1] = shear[2] = 0.0;
    return;
  }
  const double overlap_in = -gap;
  const double dx = -delta[0], dy = -delta[1], dz = -delta[2];  // from the wall to the centre
  const double r = radi - overlap_in;
  const double rinv = 1.0 / r;
  const double enx = dx * rinv, eny = dy * rinv, enz = dz * rinv;
  const double meff = mass_[i];

  const double* v = &v_[3 * i];
  const double* w = &w_[3 * i];
  const double vr1 = v[0] - 0.0, vr2 = v[1] - 0.0, vr3 = v[2] - 0.0;
  const double vn = vr1 * enx + vr2 * eny + vr3 * enz;
  const double vt1 = vr1 - vn * enx, vt2 = vr2 - vn * eny, vt3 = vr3 - vn * enz;
  const double deltan = radi - r;
  const double cr = radi - 0.5 * overlap_in;
  const double wr1 = cr * w[0] * rinv, wr2 = cr * w[1] * rinv, wr3 = cr * w[2] * rinv;
  const double vtr1 = vt1 - (dz * wr2 - dy * wr3);
  const double vtr2 = vt2 - (dx * wr3 - dz * wr1);
  const double vtr3 = vt3 - (dy * wr1 - dx * wr2);

  const PairConstants& k = type_constants_[static_cast<std::size_t>(type_[i] - 1) * static_cast<std::size_t>(p_.types) +
                                           static_cast<std::size_t>(wall.type - 1)];
  const Normal n = hertz_normal(k, radi, meff, deltan, vn, p_.tangential_damping);  // a wall has R* = R_i
  const double fn = n.fn;
  double df[3] = {0.0 + fn * 1. * enx, 0.0 + fn * 1. * eny, 0.0 + fn * 1. * enz};  // * area_ratio (1)
  const double en[3] = {enx, eny, enz}, vtr[3] = {vtr1, vtr2, vtr3};
  const auto tan = tangential_force(shear, en, vtr, n, k.friction, update_history, p_.dt);
  const double ft1 = tan.ft[0], ft2 = tan.ft[1], ft3 = tan.ft[2];
  const double tor1 = tan.tor[0], tor2 = tan.tor[1], tor3 = tan.tor[2];
  df[0] += ft1 * 1.;
  df[1] += ft2 * 1.;
  df[2] += ft3 * 1.;
  double* f = &f_[3 * i];
  double* t = &t_[3 * i];
  f[0] += df[0];
  f[1] += df[1];
  f[2] += df[2];
  t[0] += 0.0 + -cr * tor1 * 1.;
  t[1] += 0.0 + -cr * tor2 * 1.;
  t[2] += 0.0 + -cr * tor3 * 1.;
}

void System::external_forces(std::size_t i, bool update_history) {
  for (std::size_t w = 0; w < p_.walls.size(); ++w) wall_force(i, w, update_history);
  if (p_.gravity[0] != 0.0 || p_.gravity[1] != 0.0 || p_.gravity[2] != 0.0) {
    const double m = mass_[i] * 1.;
    for (int d = 0; d < 3; ++d) f_[3 * i + d] += m * p_.gravity[d];
  }
}

void System::compute_forces(bool update_history) {
  if (threads_ > 1) {
    threaded_forces(update_history);
    return;
  }
  std::fill(f_.begin(), f_.end(), 0.0);
  std::fill(t_.begin(), t_.end(), 0.0);
  Contribution c;
  for (std::size_t p = 0; p < pair_i_.size(); ++p) {
    pair_force(p, update_history, c);
    if (!c.touching) continue;
    double* fi = &f_[3 * pair_i_[p]];
    double* fj = &f_[3 * pair_j_[p]];
    double* ti = &t_[3 * pair_i_[p]];
    double* tj = &t_[3 * pair_j_[p]];
    for (int d = 0; d < 3; ++d) {
      fi[d] += c.fi[d];
      ti[d] += c.ti[d];
      fj[d] += c.fj[d];
      tj[d] += c.tj[d];
    }
  }
  // Walls, then gravity: the post_force fixes after the pair style.
  for (std::size_t w = 0; w < p_.walls.size(); ++w) {
    for (std::size_t i = 0; i < n_; ++i) wall_force(i, w, update_history);
  }
  if (p_.gravity[0] != 0.0 || p_.gravity[1] != 0.0 || p_.gravity[2] != 0.0) {
    for (std::size_t i = 0; i < n_; ++i) {
      const double m = mass_[i] * 1.;
      for (int d = 0; d < 3; ++d) f_[3 * i + d] += m * p_.gravity[d];
    }
  }
}

// Contacts in parallel into their own slots, then each particle's slots added in pair order by
// the thread that owns the particle: the same sums, in the same order, as one thread.
void System::threaded_forces(bool update_history) {
  for_shares(pair_i_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t p = begin; p < end; ++p) pair_force(p, update_history, contributions_[p]);
  });
  for_shares(n_, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      double* f = &f_[3 * i];
      double* tq = &t_[3 * i];
      f[0] = f[1] = f[2] = tq[0] = tq[1] = tq[2] = 0.0;
      for (std::size_t k = atom_pair_offsets_[i]; k < atom_pair_offsets_[i + 1]; ++k) {
        const auto& c = contributions_[atom_pairs_[k] / 2];
        if (!c.touching) continue;
        const bool side_j = atom_pairs_[k] % 2 == 1;
        for (int d = 0; d < 3; ++d) {
          f[d] += side_j ? c.fj[d] : c.fi[d];
          tq[d] += side_j ? c.tj[d] : c.ti[d];
        }
      }
      external_forces(i, update_history);
    }
  });
}

void System::setup() { compute_forces(false); }

void System::first_half(std::size_t begin, std::size_t end) {
  const double dtv = p_.dt;
  for (std::size_t i = begin; i < end; ++i) {
    const double dtfm = kick_[i], dtirotate = spin_kick_[i];
    for (int d = 0; d < 3; ++d) {
      v_[3 * i + d] += dtfm * f_[3 * i + d];
      x_[3 * i + d] += dtv * v_[3 * i + d];
    }
    for (int d = 0; d < 3; ++d) w_[3 * i + d] += dtirotate * t_[3 * i + d];
  }
}

void System::second_half(std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    const double dtfm = kick_[i], dtirotate = spin_kick_[i];
    for (int d = 0; d < 3; ++d) v_[3 * i + d] += dtfm * f_[3 * i + d];
    for (int d = 0; d < 3; ++d) w_[3 * i + d] += dtirotate * t_[3 * i + d];
  }
}

void System::step() {
  for_shares(n_, [&](std::size_t begin, std::size_t end) { first_half(begin, end); });
  if (needs_rebuild()) build_pairs();
  compute_forces(true);
  for_shares(n_, [&](std::size_t begin, std::size_t end) { second_half(begin, end); });
  ++step_;
}

}  // namespace granstack::refsim
