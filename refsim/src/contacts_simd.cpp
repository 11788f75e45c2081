// refsim's vector kernels, written once with Google Highway and compiled for every instruction
// set it targets (SSSE3, SSE4, AVX2 and AVX-512 on x86, NEON on ARM, and a scalar fallback); the
// best one this CPU runs is chosen at run time. They are contacts.cpp's reference with every
// branch turned into lane masks: each lane does the reference's floating-point operations in
// the reference's order (IEEE addition, multiplication, division and square root are exactly
// rounded on every target, refsim is built without contraction into fused multiply-adds and no
// operation here fuses), so every target gives the reference's bits. Work a branch would skip
// is skipped when no lane of a vector needs it. The kernel tests run every target this CPU runs.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "contacts_simd.cpp"
// Scalable vectors (SVE, RISC-V V) cannot be held in the arrays and structures below; an ARM CPU
// with SVE runs the NEON kernels.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "contacts.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace granstack::refsim::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Up to kLanes doubles per vector: eight with AVX-512, four with AVX2, two with SSE4 or NEON,
// one in the scalar fallback; a table's group of kLanes pairs or particles is kSub vectors.
using D = hn::CappedTag<double, kLanes>;
using DI = hn::RebindToSigned<D>;           // int64 lanes, as many
using DI32 = hn::Rebind<std::int32_t, D>;  // int32 lanes, as many
using V = hn::Vec<D>;
using VI = hn::Vec<DI>;
using M = hn::Mask<D>;
constexpr std::size_t kN = hn::MaxLanes(D());
constexpr std::size_t kSub = kLanes / kN;
static_assert(kLanes % kN == 0, "a group of kLanes must be whole vectors");

HWY_INLINE V broadcast(double a) { return hn::Set(D(), a); }
HWY_INLINE V load(const double* p) { return hn::LoadU(D(), p); }
HWY_INLINE void store(double* p, V a) { hn::StoreU(a, D(), p); }
HWY_INLINE VI indices(const std::int32_t* p) { return hn::PromoteTo(DI(), hn::LoadU(DI32(), p)); }
// C++'s != (true where either is NaN), which Highway's Ne is not.
HWY_INLINE M not_equal(V a, V b) { return hn::Not(hn::Eq(a, b)); }
// Bit k of the result: lane k of m.
HWY_INLINE unsigned bits(M m) {
  std::uint8_t b[8] = {};
  hn::StoreMaskBits(D(), m, b);
  return b[0] & ((1U << kN) - 1U);
}
HWY_INLINE M mask(unsigned b) {
  const std::uint8_t byte[8] = {static_cast<std::uint8_t>(b & ((1U << kN) - 1U))};
  return hn::LoadMaskBits(D(), byte);
}

struct Vec {
  V x, y, z;
};

// Where kN pairs from p find one side's particles: at a run's window plus their lane (one
// load), else gathered by index.
struct Side {
  bool run;
  std::size_t at;  // the run's first particle
  VI index;
};

HWY_INLINE Side side(const AlignedVector<std::int32_t>& index, const std::vector<std::int32_t>& window,
                     const std::vector<Fetch>& how, std::size_t p) {
  const std::size_t g = p / kLanes;
  if (how[g] == kRun) return {true, static_cast<std::size_t>(window[g]) + p % kLanes, hn::Zero(DI())};
  return {false, 0, indices(&index[p])};
}

HWY_INLINE V fetch(const double* component, const Side& s) {
  return s.run ? load(component + s.at) : hn::GatherIndex(D(), component, s.index);
}

HWY_INLINE Vec fetch(const double* a, std::size_t stride, const Side& s) {
  return {fetch(a, s), fetch(a + stride, s), fetch(a + 2 * stride, s)};
}

// kN pairs' records: one broadcast when their group shares one, else gathered.
struct Record {
  const double* shared;
  const double* table;
  VI index;  // record x 9 doubles
  HWY_INLINE V field(std::size_t offset) const {
    const std::size_t d = offset / sizeof(double);
    return shared != nullptr ? broadcast(shared[d]) : hn::GatherIndex(D(), table + d, index);
  }
};

HWY_INLINE Record record(const PairTable& t, std::size_t p) {
  static_assert(sizeof(PairRecord) == 9 * sizeof(double));
  const auto* table = reinterpret_cast<const double*>(t.records.data());
  const std::int32_t shared = t.shared_record[p / kLanes];
  if (shared >= 0) return {reinterpret_cast<const double*>(&t.records[static_cast<std::size_t>(shared)]), table, hn::Zero(DI())};
  const VI r = indices(&t.record[p]);
  return {nullptr, table, hn::Add(hn::ShiftLeft<3>(r), r)};
}

// Force on i (the sums subtract it from j's), zero where not touching.
HWY_INLINE void store_forces(PairTable& t, std::size_t p, M touching, const Vec& f) {
  store(&t.fx[p], hn::IfThenElseZero(touching, f.x));
  store(&t.fy[p], hn::IfThenElseZero(touching, f.y));
  store(&t.fz[p], hn::IfThenElseZero(touching, f.z));
}

// Torques on i and on j, zero where not touching.
HWY_INLINE void store_torques(PairTable& t, std::size_t p, M touching, const Vec& ti, const Vec& tj) {
  const std::size_t q = t.padded() + p;
  store(&t.tx[p], hn::IfThenElseZero(touching, ti.x));
  store(&t.ty[p], hn::IfThenElseZero(touching, ti.y));
  store(&t.tz[p], hn::IfThenElseZero(touching, ti.z));
  store(&t.tx[q], hn::IfThenElseZero(touching, tj.x));
  store(&t.ty[q], hn::IfThenElseZero(touching, tj.y));
  store(&t.tz[q], hn::IfThenElseZero(touching, tj.z));
}

// The touching flags of kN pairs: set where touching, cleared where only close.
HWY_INLINE void update_flags(std::uint8_t* flags, M touching, M close) {
  const unsigned t = bits(touching), c = bits(close);
  for (std::size_t k = 0; k < kN; ++k) {
    if (t >> k & 1U) {
      flags[k] = 1;
    } else if (c >> k & 1U) {
      flags[k] = 0;
    }
  }
}

// What both kernels find first of kN pairs from p: where their spheres are, their records,
// their separation and which of them touch.
struct Found {
  Side si, sj;
  Record rec;
  V delx, dely, delz, rsq, radi, radj, radsum;
  M touching;
};

HWY_INLINE Found find(const PairTable& t, const ContactStep& s, std::size_t p) {
  const Side si = side(t.i, t.window_i, t.fetch_i, p), sj = side(t.j, t.window_j, t.fetch_j, p);
  const Record rec = record(t, p);
  const Vec xi = fetch(s.x, s.stride, si), xj = fetch(s.x, s.stride, sj);
  const V delx = xi.x - xj.x;
  const V dely = xi.y - xj.y;
  const V delz = xi.z - xj.z;
  const V rsq = delx * delx + dely * dely + delz * delz;
  const V radi = rec.field(offsetof(PairRecord, radi)), radj = rec.field(offsetof(PairRecord, radj));
  const V radsum = radi + radj;
  return {si, sj, rec, delx, dely, delz, rsq, radi, radj, radsum, hn::Lt(rsq, radsum * radsum)};
}

HWY_INLINE Vec select(M m, const Vec& yes, const Vec& no) {
  return {hn::IfThenElse(m, yes.x, no.x), hn::IfThenElse(m, yes.y, no.y), hn::IfThenElse(m, yes.z, no.z)};
}

HWY_INLINE void store_history(PairTable& t, std::size_t p, const Vec& h) {
  store(&t.shear_x[p], h.x);
  store(&t.shear_y[p], h.y);
  store(&t.shear_z[p], h.z);
}

HWY_INLINE void clear_history_where(PairTable& t, std::size_t p, M m) {
  const V zero = hn::Zero(D());
  for (double* a : {&t.shear_x[p], &t.shear_y[p], &t.shear_z[p]}) hn::BlendedStore(zero, m, D(), a);
}

// The tangential history spring of tangential_force (contacts.cpp) on kN pairs: increment,
// projection, Coulomb truncation or the frictionless slide, then the damping of sticking pairs.
// Returns the tangential force on i; `shear` becomes the new history where touching.
HWY_INLINE Vec tangential(Vec& shear, const Vec& en, const Vec& vtr, V kt, V gammat, V fn, V mu, M touching,
                          const ContactStep& s) {
  const V zero = hn::Zero(D());
  if (s.update_history) {
    const V dt = broadcast(s.dt);
    shear = {shear.x + vtr.x * dt, shear.y + vtr.y * dt, shear.z + vtr.z * dt};
    const V rsht = shear.x * en.x + shear.y * en.y + shear.z * en.z;
    shear = {shear.x - rsht * en.x, shear.y - rsht * en.y, shear.z - rsht * en.z};
  }
  const V shear_sq = shear.x * shear.x + shear.y * shear.y + shear.z * shear.z;
  Vec ft{hn::Neg(kt * shear.x), hn::Neg(kt * shear.y), hn::Neg(kt * shear.z)};
  const M frictionless = hn::Eq(mu, zero);
  // Frictionless sliding leaves a zero force and a zero history (as the reference).
  const M zero_slide = hn::And(hn::And(touching, frictionless), hn::And(hn::Gt(kt, zero), hn::Gt(shear_sq, zero)));
  // A frictionless pair that does not slide sticks: its kt |xi| is 0, not above mu |fn| = 0.
  const M coulomb = hn::AndNot(frictionless, touching);
  M sliding = hn::FirstN(D(), 0);
  const Vec zeros{zero, zero, zero};
  if (!hn::AllFalse(D(), coulomb)) {
    const V shrmag = hn::Sqrt(shear_sq);
    const V ft_shear = kt * shrmag;
    const V ft_friction = mu * hn::Abs(fn);
    sliding = hn::And(coulomb, hn::Gt(ft_shear, ft_friction));
    if (!hn::AllFalse(D(), sliding)) {
      // Sliding: scaled down to the Coulomb limit, or zero if there is no displacement to scale.
      const M scaled = hn::And(sliding, not_equal(shrmag, zero));
      const V ratio = ft_friction / ft_shear;
      ft = select(scaled, Vec{ft.x * ratio, ft.y * ratio, ft.z * ratio}, select(sliding, zeros, ft));
      if (s.update_history) {
        shear = select(scaled, Vec{hn::Neg(ft.x) / kt, hn::Neg(ft.y) / kt, hn::Neg(ft.z) / kt}, shear);
      }
    }
  }
  if (!hn::AllFalse(D(), zero_slide)) {
    ft = select(zero_slide, zeros, ft);
    if (s.update_history) shear = select(zero_slide, zeros, shear);
  }
  const M sticking = hn::AndNot(hn::Or(zero_slide, sliding), touching);
  return select(sticking, Vec{ft.x - gammat * vtr.x, ft.y - gammat * vtr.y, ft.z - gammat * vtr.z}, ft);
}

// contacts.cpp's pair_force on the kN pairs from p.
HWY_INLINE void pair_block(PairTable& t, const ContactStep& s, std::size_t p) {
  const auto [si, sj, rec, delx, dely, delz, rsq, radi, radj, radsum, touching] = find(t, s, p);
  const V cdf = broadcast(s.contact_distance_factor);
  // Close but not touching: the history is reset (surfacesClose); farther: left alone.
  const M close = hn::AndNot(touching, hn::Lt(rsq, cdf * cdf * radsum * radsum));
  update_flags(&t.touching[p], touching, close);
  const V zero = hn::Zero(D());
  const Vec zeros{zero, zero, zero};
  if (hn::AllFalse(D(), touching)) {
    clear_history_where(t, p, close);
    store_forces(t, p, touching, zeros);
    store_torques(t, p, touching, zeros, zeros);
    return;
  }
  const V r = hn::Sqrt(rsq);
  const V rinv = broadcast(1.0) / r;
  const Vec en{delx * rinv, dely * rinv, delz * rinv};
  const V deltan = radsum - r;
  if (t.elastic_frictionless[p / kLanes] != 0) {
    // kn delta n: the reference's -gamman vn and ft are +-0 here (PairRecord::elastic_frictionless).
    const V fn = rec.field(offsetof(PairRecord, kn_factor)) * hn::Sqrt(rec.field(offsetof(PairRecord, reff)) * deltan) * deltan;
    // The history never acts on such a pair; it is cleared where the reference's slide clears it.
    clear_history_where(t, p, s.update_history ? hn::Or(close, touching) : close);
    store_forces(t, p, touching, {fn * en.x, fn * en.y, fn * en.z});
    // The torque entries: zero since the table was built, unless other pairs may write them.
    if (!t.torque_free) store_torques(t, p, touching, zeros, zeros);
    return;
  }

  // Relative velocity at the contact point; lever arms shortened by half the overlap.
  const Vec vi = fetch(s.v, s.stride, si), vj = fetch(s.v, s.stride, sj);
  const V vr1 = vi.x - vj.x, vr2 = vi.y - vj.y, vr3 = vi.z - vj.z;
  const V vn = vr1 * en.x + vr2 * en.y + vr3 * en.z;
  const V vt1 = vr1 - vn * en.x, vt2 = vr2 - vn * en.y, vt3 = vr3 - vn * en.z;
  const V half = broadcast(0.5);
  const V cri = radi - half * deltan;
  const V crj = radj - half * deltan;
  const Vec wi = fetch(s.w, s.stride, si), wj = fetch(s.w, s.stride, sj);
  const V wr1 = (cri * wi.x + crj * wj.x) * rinv;
  const V wr2 = (cri * wi.y + crj * wj.y) * rinv;
  const V wr3 = (cri * wi.z + crj * wj.z) * rinv;
  const Vec vtr{vt1 - (delz * wr2 - dely * wr3), vt2 - (delx * wr3 - delz * wr1), vt3 - (dely * wr1 - delx * wr2)};

  // hertz_normal
  const V meff = rec.field(offsetof(PairRecord, meff));
  const V damping = rec.field(offsetof(PairRecord, damping_factor));
  const V sqrtval = hn::Sqrt(rec.field(offsetof(PairRecord, reff)) * deltan);
  const V kt = rec.field(offsetof(PairRecord, st_factor)) * sqrtval;
  const V kn = rec.field(offsetof(PairRecord, kn_factor)) * sqrtval;
  const M damped = hn::And(touching, not_equal(damping, zero));
  V gamman = damping, gammat = s.tangential_damping ? damping : zero;
  if (!hn::AllFalse(D(), damped)) {
    gamman = hn::IfThenElse(damped, damping * hn::Sqrt(rec.field(offsetof(PairRecord, sn_factor)) * sqrtval * meff), gamman);
    if (s.tangential_damping) gammat = hn::IfThenElse(damped, damping * hn::Sqrt(kt * meff), gammat);
  }
  const V fn = hn::Neg(gamman) * vn + kn * deltan;

  const Vec shear_before{load(&t.shear_x[p]), load(&t.shear_y[p]), load(&t.shear_z[p])};
  Vec shear = shear_before;
  const Vec ft = tangential(shear, en, vtr, kt, gammat, fn, rec.field(offsetof(PairRecord, friction)), touching, s);
  const Vec tor{en.y * ft.z - en.z * ft.y, en.z * ft.x - en.x * ft.z, en.x * ft.y - en.y * ft.x};

  // The history: the new one where touching, zero where close, unchanged farther away.
  store_history(t, p, select(touching, shear, select(close, zeros, shear_before)));
  store_forces(t, p, touching, {fn * en.x + ft.x, fn * en.y + ft.y, fn * en.z + ft.z});
  store_torques(t, p, touching, {hn::Neg(cri) * tor.x, hn::Neg(cri) * tor.y, hn::Neg(cri) * tor.z},
                {hn::Neg(crj) * tor.x, hn::Neg(crj) * tor.y, hn::Neg(crj) * tor.z});
}

// Particles window .. window + 15 of Motion::position_changed, as bits 0 .. 15.
HWY_INLINE std::uint32_t changed_in_window(const std::uint8_t* changed, std::int32_t window) {
  const auto w = static_cast<std::size_t>(window);
  std::uint32_t word;
  std::memcpy(&word, changed + w / 8, sizeof word);
  return word >> (w % 8);
}

// Whether no particle of the kLanes pairs from g * kLanes has a new position since they were
// last evaluated (as far as windows can tell; a gathered side is never still).
HWY_INLINE bool still(const PairTable& t, const std::uint8_t* changed, std::size_t g) {
  return t.fetch_i[g] != kGather && t.fetch_j[g] != kGather &&
         (changed_in_window(changed, t.window_i[g]) & t.particles_i[g]) == 0 &&
         (changed_in_window(changed, t.window_j[g]) & t.particles_j[g]) == 0;
}

// pairs() for a table whose every pair is elastic and frictionless (PairTable::torque_free):
// the force kn delta n alone. The history of such a pair is +0 from its start to its end (no
// path of the model makes it anything else), so neither it nor the touching flags that decide
// which history survives a rebuild need to be written; the torque entries stay +0. The force
// is a function of the two positions alone, so a block none of whose spheres has a new
// position since its last evaluation keeps its entries: the stack at rest ahead of the wave,
// whose spheres' round-off forces are far too small to change a position's bits.
HWY_INLINE void elastic_block(PairTable& t, const ContactStep& s, std::size_t p) {
  std::uint8_t& evaluated = t.evaluated[p / kPairBlock];
  if (evaluated != 0 && still(t, s.position_changed, p / kLanes) && still(t, s.position_changed, p / kLanes + 1)) return;
  evaluated = 1;
  std::uint8_t& stored = t.forces_stored[p / kPairBlock];  // else every entry of the block is +0
  bool any = false;
  for (std::size_t q = p; q < p + kPairBlock; q += kN) {
    const auto [si, sj, rec, delx, dely, delz, rsq, radi, radj, radsum, touching] = find(t, s, q);
    if (hn::AllFalse(D(), touching)) {
      if (stored != 0) {
        const V zero = hn::Zero(D());
        store_forces(t, q, touching, {zero, zero, zero});
      }
      continue;
    }
    any = true;
    const V r = hn::Sqrt(rsq);
    const V rinv = broadcast(1.0) / r;
    const V deltan = radsum - r;
    const V fn = rec.field(offsetof(PairRecord, kn_factor)) * hn::Sqrt(rec.field(offsetof(PairRecord, reff)) * deltan) * deltan;
    store_forces(t, q, touching, {fn * (delx * rinv), fn * (dely * rinv), fn * (delz * rinv)});
  }
  stored = any ? 1 : 0;
}

void contacts(PairTable& t, const ContactStep& s, std::size_t begin, std::size_t end) {
  if (t.torque_free) {
    for (std::size_t p = begin; p < end; p += kPairBlock) elastic_block(t, s, p);
    return;
  }
  for (std::size_t p = begin; p < end; p += kN) pair_block(t, s, p);
}

// The plan's arrays as plain pointers, which the compiler keeps in registers.
struct PlanView {
  const std::size_t* first_round;
  const std::size_t* first_added;
  const std::uint8_t* lanes_in;
  const Fetch* fetch;
  const std::int32_t* window;
  const std::int32_t* entry;
};

// Rounds [first, last) of a group over `Components` arrays (3: forces only, 6: and torques),
// into sums in registers: the forces added, or subtracted with the torques read `torque_side`
// entries on (the pairs' j side). A run may read, for the lanes not in the round, entries of
// other pairs or the tables' padding (and a gather reads the round's lowest entry there): those
// lanes keep their sums, as adding the +0 of the reference's order would (no sum that starts at
// +0 is ever -0).
template <int Components, bool Subtract>
HWY_INLINE void sum_rounds(const PlanView& plan, std::size_t first, std::size_t last, const double* const* in,
                           std::size_t torque_side, V (&sum)[Components][kSub]) {
  for (std::size_t r = first; r < last; ++r) {
    const unsigned lanes = plan.lanes_in[r];
    const bool run = plan.fetch[r] == kRun;
    const std::size_t w = static_cast<std::size_t>(plan.window[r]);
    for (std::size_t k = 0; k < kSub; ++k) {
      const unsigned in_sub = lanes >> (k * kN) & ((1U << kN) - 1U);
      if (in_sub == 0) continue;
      const M m = mask(in_sub);
      const VI index = run ? hn::Zero(DI()) : indices(&plan.entry[r * kLanes + k * kN]);
      for (int c = 0; c < Components; ++c) {
        const double* a = in[c] + (c < 3 ? 0 : torque_side);
        const V x = run ? load(a + w + k * kN) : hn::GatherIndex(D(), a, index);
        sum[c][k] = hn::IfThenElse(m, Subtract && c < 3 ? sum[c][k] - x : sum[c][k] + x, sum[c][k]);
      }
    }
  }
}

// One group's sums: its rounds as the pairs' j, then as their i.
template <int Components>
HWY_INLINE void sum_group(const PlanView& plan, std::size_t g, const double* const* in, std::size_t j_side,
                          double* const* out) {
  V sum[Components][kSub];
  for (auto& c : sum) {
    for (auto& s : c) s = hn::Zero(D());
  }
  sum_rounds<Components, true>(plan, plan.first_round[g], plan.first_added[g], in, j_side, sum);
  sum_rounds<Components, false>(plan, plan.first_added[g], plan.first_round[g + 1], in, 0, sum);
  for (int c = 0; c < Components; ++c) {
    for (std::size_t k = 0; k < kSub; ++k) store(out[c] + g * kLanes + k * kN, sum[c][k]);
  }
}

void sum_contributions(const PairTable& pairs, const SumPlan& plan, double* f, double* t, std::size_t stride,
                       std::size_t group_begin, std::size_t group_end, bool zero_torques) {
  const double* in[6] = {pairs.fx.data(), pairs.fy.data(), pairs.fz.data(), pairs.tx.data(), pairs.ty.data(), pairs.tz.data()};
  double* out[6] = {f, f + stride, f + 2 * stride, t, t + stride, t + 2 * stride};
  const PlanView view{plan.first_round.data(), plan.first_added.data(), plan.lanes_in.data(),
                      plan.fetch.data(),       plan.window.data(),      plan.entry.data()};
  const std::size_t j_side = pairs.padded();
  for (std::size_t g = group_begin; g < group_end; ++g) {
    if (pairs.torque_free) {
      // Without torques (PairTable::torque_free) every torque sum is 0 + +-0 + ... = +0.
      sum_group<3>(view, g, in, j_side, out);
      if (zero_torques) {
        for (int c = 3; c < 6; ++c) {
          for (std::size_t k = 0; k < kLanes; k += kN) store(out[c] + g * kLanes + k, hn::Zero(D()));
        }
      }
    } else {
      sum_group<6>(view, g, in, j_side, out);
    }
  }
}

// The first half (kick, drift, spin kick, rebuild check), after the previous step's second
// half (kick, spin kick) when SecondHalfFirst: each particle's operations in the reference's order.
template <bool SecondHalfFirst>
HWY_INLINE bool first_half(const Motion& m, std::size_t begin, std::size_t end) {
  // The arrays do not overlap one another (nor the Motion), which the compiler cannot know.
  double* HWY_RESTRICT x = m.x;
  double* HWY_RESTRICT v = m.v;
  double* HWY_RESTRICT w = m.w;
  const double* HWY_RESTRICT f = m.f;
  const double* HWY_RESTRICT t = m.t;
  const double* HWY_RESTRICT kicks = m.kick;
  const double* HWY_RESTRICT spins = m.spin_kick;
  const double* HWY_RESTRICT x0 = m.x_at_build;
  std::uint8_t* HWY_RESTRICT changed = m.position_changed;
  const std::size_t stride = m.stride;
  const bool spin_on = m.spin;
  const V dt = broadcast(m.dt), trigger = broadcast(m.trigger);
  M moved = hn::FirstN(D(), 0);
  for (std::size_t group = begin; group < end; group += kLanes) {
    unsigned changed_bits = 0;
    for (std::size_t sub = 0; sub < kLanes; sub += kN) {
      const std::size_t i = group + sub;
      const V kick = load(&kicks[i]), spin = load(&spins[i]);
      V dsq = hn::Zero(D());
      M new_position = hn::FirstN(D(), 0);
      for (std::size_t d = 0; d < 3; ++d) {
        const std::size_t e = i + d * stride;
        const V fe = load(&f[e]);
        V ve = load(&v[e]);
        if (SecondHalfFirst) ve = ve + kick * fe;
        ve = ve + kick * fe;
        const V x_before = load(&x[e]);
        const V xe = x_before + dt * ve;
        new_position = hn::Or(new_position, hn::RebindMask(D(), hn::Ne(hn::BitCast(DI(), xe), hn::BitCast(DI(), x_before))));
        store(&v[e], ve);
        store(&x[e], xe);
        if (spin_on) {
          const V te = load(&t[e]);
          V we = load(&w[e]);
          if (SecondHalfFirst) we = we + spin * te;
          store(&w[e], we + spin * te);
        }
        const V de = xe - load(&x0[e]);
        dsq = dsq + de * de;  // dx^2, then + dy^2, then + dz^2: the reference's order
      }
      moved = hn::Or(moved, hn::Gt(dsq, trigger));
      changed_bits |= bits(new_position) << sub;
    }
    changed[group / kLanes] = static_cast<std::uint8_t>(changed_bits);
  }
  return !hn::AllFalse(D(), moved);
}

bool first_half_only(const Motion& m, std::size_t begin, std::size_t end) { return first_half<false>(m, begin, end); }

bool second_and_first_half(const Motion& m, std::size_t begin, std::size_t end) { return first_half<true>(m, begin, end); }

void second_half(const Motion& m, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; i += kN) {
    const V kick = load(&m.kick[i]), spin = load(&m.spin_kick[i]);
    for (std::size_t e = i; e < i + 3 * m.stride; e += m.stride) {
      store(&m.v[e], load(&m.v[e]) + kick * load(&m.f[e]));
      if (m.spin) store(&m.w[e], load(&m.w[e]) + spin * load(&m.t[e]));
    }
  }
}

void kinetic_sums(const KineticInput& in, std::size_t begin, std::size_t end, double* translational, double* rotational) {
  V ke[kSub], rot[kSub];
  for (std::size_t k = 0; k < kSub; ++k) {
    ke[k] = load(translational + k * kN);
    rot[k] = load(rotational + k * kN);
  }
  const std::size_t y = in.stride, z = 2 * in.stride;
  for (std::size_t i = begin; i < end; i += kLanes) {
    for (std::size_t k = 0; k < kSub && i + k * kN < end; ++k) {
      // Past `end` the lanes add +0 (every array holds whole groups of particles).
      const std::size_t at = i + k * kN;
      const M in_range = hn::FirstN(D(), end - at);
      const V m = load(in.mass + at), r = load(in.radius + at);
      const V vx = load(in.v + at), vy = load(in.v + y + at), vz = load(in.v + z + at);
      const V wx = load(in.w + at), wy = load(in.w + y + at), wz = load(in.w + z + at);
      ke[k] = ke[k] + hn::IfThenElseZero(in_range, m * (vx * vx + vy * vy + vz * vz));
      rot[k] = rot[k] + hn::IfThenElseZero(in_range, (wx * wx + wy * wy + wz * wz) * r * r * m);
    }
  }
  for (std::size_t k = 0; k < kSub; ++k) {
    store(translational + k * kN, ke[k]);
    store(rotational + k * kN, rot[k]);
  }
}

VectorKernels kernels() {
  return {&contacts, &sum_contributions, &first_half_only, &second_half, &second_and_first_half, &kinetic_sums};
}

}  // namespace HWY_NAMESPACE
}  // namespace granstack::refsim::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>
#include <cctype>
#include <mutex>
#include <stdexcept>

namespace granstack::refsim::detail {

HWY_EXPORT(kernels);

namespace {
// Highway's target names as granstack spells them: lower case, AVX3 as avx512.
std::string target_name(std::int64_t target) {
  if (target == HWY_AVX3) return "avx512";
  std::string name = hwy::TargetName(target);
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (name.rfind("avx3", 0) == 0) name.replace(0, 4, "avx512");
  return name;
}
}  // namespace

std::vector<std::string> vector_targets() {
  std::vector<std::string> names;
  for (const std::int64_t t : hwy::SupportedAndGeneratedTargets()) names.push_back(target_name(t));
  return names;
}

VectorKernels vector_kernels(const std::string& name) {
  for (const std::int64_t t : hwy::SupportedAndGeneratedTargets()) {
    if (!name.empty() && target_name(t) != name) continue;
    // Highway chooses through a process-wide setting: restricted to this target for the one
    // dispatch that hands out its functions, then given back.
    static std::mutex choosing;
    const std::lock_guard<std::mutex> lock(choosing);
    hwy::SetSupportedTargetsForTest(t);
    const VectorKernels k = HWY_DYNAMIC_DISPATCH(kernels)();
    hwy::SetSupportedTargetsForTest(0);
    return k;
  }
  throw std::invalid_argument("refsim: no vector kernels for " + name);
}

}  // namespace granstack::refsim::detail
#endif  // HWY_ONCE
