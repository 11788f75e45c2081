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
#include <granstack/model/highway_targets.hpp>  // IWYU pragma: keep

#include "contacts.hpp"

#include <atomic>
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

template <class T>
struct Vec3 {
  T x, y, z;
};
using Vec = Vec3<V>;

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

// The contact model below is written once for kN pairs in one vector (V, M) and for 2 kN in
// two vectors side by side (W, WM: every operation issued for both halves, so that their chains
// of square roots and divisions overlap), through these names.
struct W {
  V a, b;
};
struct WM {
  M a, b;
};
HWY_INLINE W operator+(const W& x, const W& y) { return {x.a + y.a, x.b + y.b}; }
HWY_INLINE W operator-(const W& x, const W& y) { return {x.a - y.a, x.b - y.b}; }
HWY_INLINE W operator*(const W& x, const W& y) { return {x.a * y.a, x.b * y.b}; }
HWY_INLINE W operator/(const W& x, const W& y) { return {x.a / y.a, x.b / y.b}; }
HWY_INLINE V negate(V x) { return hn::Neg(x); }
HWY_INLINE W negate(const W& x) { return {hn::Neg(x.a), hn::Neg(x.b)}; }
HWY_INLINE V root(V x) { return hn::Sqrt(x); }
HWY_INLINE W root(const W& x) { return {hn::Sqrt(x.a), hn::Sqrt(x.b)}; }
HWY_INLINE V magnitude(V x) { return hn::Abs(x); }
HWY_INLINE W magnitude(const W& x) { return {hn::Abs(x.a), hn::Abs(x.b)}; }
HWY_INLINE M less(V x, V y) { return hn::Lt(x, y); }
HWY_INLINE WM less(const W& x, const W& y) { return {hn::Lt(x.a, y.a), hn::Lt(x.b, y.b)}; }
HWY_INLINE M greater(V x, V y) { return hn::Gt(x, y); }
HWY_INLINE WM greater(const W& x, const W& y) { return {hn::Gt(x.a, y.a), hn::Gt(x.b, y.b)}; }
HWY_INLINE M equal(V x, V y) { return hn::Eq(x, y); }
HWY_INLINE WM equal(const W& x, const W& y) { return {hn::Eq(x.a, y.a), hn::Eq(x.b, y.b)}; }
HWY_INLINE WM not_equal(const W& x, const W& y) { return {not_equal(x.a, y.a), not_equal(x.b, y.b)}; }
HWY_INLINE M both(M x, M y) { return hn::And(x, y); }
HWY_INLINE WM both(const WM& x, const WM& y) { return {hn::And(x.a, y.a), hn::And(x.b, y.b)}; }
HWY_INLINE M either(M x, M y) { return hn::Or(x, y); }
HWY_INLINE WM either(const WM& x, const WM& y) { return {hn::Or(x.a, y.a), hn::Or(x.b, y.b)}; }
HWY_INLINE M but_not(M no, M x) { return hn::AndNot(no, x); }  // x and not `no`
HWY_INLINE WM but_not(const WM& no, const WM& x) { return {hn::AndNot(no.a, x.a), hn::AndNot(no.b, x.b)}; }
HWY_INLINE bool none(M m) { return hn::AllFalse(D(), m); }
HWY_INLINE bool none(const WM& m) { return hn::AllFalse(D(), m.a) && hn::AllFalse(D(), m.b); }
HWY_INLINE V pick(M m, V yes, V no) { return hn::IfThenElse(m, yes, no); }
HWY_INLINE W pick(const WM& m, const W& yes, const W& no) { return {hn::IfThenElse(m.a, yes.a, no.a), hn::IfThenElse(m.b, yes.b, no.b)}; }
HWY_INLINE V zero_unless(M m, V x) { return hn::IfThenElseZero(m, x); }
HWY_INLINE W zero_unless(const WM& m, const W& x) { return {hn::IfThenElseZero(m.a, x.a), hn::IfThenElseZero(m.b, x.b)}; }

// Per lane type: how many pairs, constants, masks, and the table's memory at entry p.
template <class T>
struct Lanes;
template <>
struct Lanes<V> {
  using Mask = M;
  static constexpr std::size_t kCount = kN;
  static V filled(double v) { return broadcast(v); }
  static M nothing() { return hn::FirstN(D(), 0); }
  static V at(const double* p) { return load(p); }
  static void put(double* p, V x) { store(p, x); }
  static void put_where(double* p, M m, V x) { hn::BlendedStore(x, m, D(), p); }
};
template <>
struct Lanes<W> {
  using Mask = WM;
  static constexpr std::size_t kCount = 2 * kN;
  static W filled(double v) { return {broadcast(v), broadcast(v)}; }
  static WM nothing() { return {hn::FirstN(D(), 0), hn::FirstN(D(), 0)}; }
  static W at(const double* p) { return {load(p), load(p + kN)}; }
  static void put(double* p, const W& x) {
    store(p, x.a);
    store(p + kN, x.b);
  }
  static void put_where(double* p, const WM& m, const W& x) {
    hn::BlendedStore(x.a, m.a, D(), p);
    hn::BlendedStore(x.b, m.b, D(), p + kN);
  }
};

template <class T, class TM>
HWY_INLINE Vec3<T> select(const TM& m, const Vec3<T>& yes, const Vec3<T>& no) {
  return {pick(m, yes.x, no.x), pick(m, yes.y, no.y), pick(m, yes.z, no.z)};
}

// Force on i (the sums subtract it from j's), zero where not touching.
template <class T, class TM>
HWY_INLINE void store_forces(PairTable& t, std::size_t p, const TM& touching, const Vec3<T>& f) {
  Lanes<T>::put(&t.fx[p], zero_unless(touching, f.x));
  Lanes<T>::put(&t.fy[p], zero_unless(touching, f.y));
  Lanes<T>::put(&t.fz[p], zero_unless(touching, f.z));
}

// Torques on i and on j, zero where not touching.
template <class T, class TM>
HWY_INLINE void store_torques(PairTable& t, std::size_t p, const TM& touching, const Vec3<T>& ti, const Vec3<T>& tj) {
  const std::size_t q = t.padded() + p;
  Lanes<T>::put(&t.tx[p], zero_unless(touching, ti.x));
  Lanes<T>::put(&t.ty[p], zero_unless(touching, ti.y));
  Lanes<T>::put(&t.tz[p], zero_unless(touching, ti.z));
  Lanes<T>::put(&t.tx[q], zero_unless(touching, tj.x));
  Lanes<T>::put(&t.ty[q], zero_unless(touching, tj.y));
  Lanes<T>::put(&t.tz[q], zero_unless(touching, tj.z));
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
HWY_INLINE void update_flags(std::uint8_t* flags, const WM& touching, const WM& close) {
  update_flags(flags, touching.a, close.a);
  update_flags(flags + kN, touching.b, close.b);
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

// find() of the pairs from p in T's lanes, and what else the model reads of their spheres and
// records.
template <class T>
struct Pairs;
template <>
struct Pairs<V> {
  Found f;
  Pairs(const PairTable& t, const ContactStep& s, std::size_t p) : f(find(t, s, p)) {}
  V delx() const { return f.delx; }
  V dely() const { return f.dely; }
  V delz() const { return f.delz; }
  V rsq() const { return f.rsq; }
  V radi() const { return f.radi; }
  V radj() const { return f.radj; }
  V radsum() const { return f.radsum; }
  M touching() const { return f.touching; }
  V field(std::size_t offset) const { return f.rec.field(offset); }
  Vec3<V> i(const double* a, std::size_t stride) const { return fetch(a, stride, f.si); }
  Vec3<V> j(const double* a, std::size_t stride) const { return fetch(a, stride, f.sj); }
};
template <>
struct Pairs<W> {
  Found a, b;
  Pairs(const PairTable& t, const ContactStep& s, std::size_t p) : a(find(t, s, p)), b(find(t, s, p + kN)) {}
  W delx() const { return {a.delx, b.delx}; }
  W dely() const { return {a.dely, b.dely}; }
  W delz() const { return {a.delz, b.delz}; }
  W rsq() const { return {a.rsq, b.rsq}; }
  W radi() const { return {a.radi, b.radi}; }
  W radj() const { return {a.radj, b.radj}; }
  W radsum() const { return {a.radsum, b.radsum}; }
  WM touching() const { return {a.touching, b.touching}; }
  W field(std::size_t offset) const { return {a.rec.field(offset), b.rec.field(offset)}; }
  static Vec3<W> join(const Vec& x, const Vec& y) { return {{x.x, y.x}, {x.y, y.y}, {x.z, y.z}}; }
  Vec3<W> i(const double* p, std::size_t stride) const { return join(fetch(p, stride, a.si), fetch(p, stride, b.si)); }
  Vec3<W> j(const double* p, std::size_t stride) const { return join(fetch(p, stride, a.sj), fetch(p, stride, b.sj)); }
};

template <class T>
HWY_INLINE void store_history(PairTable& t, std::size_t p, const Vec3<T>& h) {
  Lanes<T>::put(&t.history[0][p], h.x);
  Lanes<T>::put(&t.history[1][p], h.y);
  Lanes<T>::put(&t.history[2][p], h.z);
}

template <class T, class TM>
HWY_INLINE void clear_history_where(PairTable& t, std::size_t p, const TM& m) {
  const T zero = Lanes<T>::filled(0.0);
  for (double* a : {&t.history[0][p], &t.history[1][p], &t.history[2][p]}) Lanes<T>::put_where(a, m, zero);
}

// The tangential history spring of tangential_force (contacts.cpp) on T's pairs: increment,
// projection, Coulomb truncation or the frictionless slide, then the damping of sticking pairs.
// Returns the tangential force on i; `shear` becomes the new history where touching.
template <class T, class TM>
HWY_INLINE Vec3<T> tangential(Vec3<T>& shear, const Vec3<T>& en, const Vec3<T>& vtr, const T& kt, const T& gammat, const T& fn,
                              const T& mu, const TM& touching, const ContactStep& s) {
  const T zero = Lanes<T>::filled(0.0);
  if (s.update_history) {
    const T dt = Lanes<T>::filled(s.dt);
    shear = {shear.x + vtr.x * dt, shear.y + vtr.y * dt, shear.z + vtr.z * dt};
    const T rsht = shear.x * en.x + shear.y * en.y + shear.z * en.z;
    shear = {shear.x - rsht * en.x, shear.y - rsht * en.y, shear.z - rsht * en.z};
  }
  const T shear_sq = shear.x * shear.x + shear.y * shear.y + shear.z * shear.z;
  Vec3<T> ft{negate(kt * shear.x), negate(kt * shear.y), negate(kt * shear.z)};
  const TM frictionless = equal(mu, zero);
  // Frictionless sliding leaves a zero force and a zero history (as the reference).
  const TM zero_slide = both(both(touching, frictionless), both(greater(kt, zero), greater(shear_sq, zero)));
  // A frictionless pair that does not slide sticks: its kt |xi| is 0, not above mu |fn| = 0.
  const TM coulomb = but_not(frictionless, touching);
  TM sliding = Lanes<T>::nothing();
  const Vec3<T> zeros{zero, zero, zero};
  if (!none(coulomb)) {
    const T shrmag = root(shear_sq);
    const T ft_shear = kt * shrmag;
    const T ft_friction = mu * magnitude(fn);
    sliding = both(coulomb, greater(ft_shear, ft_friction));
    if (!none(sliding)) {
      // Sliding: scaled down to the Coulomb limit, or zero if there is no displacement to scale.
      const TM scaled = both(sliding, not_equal(shrmag, zero));
      const T ratio = ft_friction / ft_shear;
      ft = select(scaled, Vec3<T>{ft.x * ratio, ft.y * ratio, ft.z * ratio}, select(sliding, zeros, ft));
      if (s.update_history) {
        shear = select(scaled, Vec3<T>{negate(ft.x) / kt, negate(ft.y) / kt, negate(ft.z) / kt}, shear);
      }
    }
  }
  if (!none(zero_slide)) {
    ft = select(zero_slide, zeros, ft);
    if (s.update_history) shear = select(zero_slide, zeros, shear);
  }
  const TM sticking = but_not(either(zero_slide, sliding), touching);
  return select(sticking, Vec3<T>{ft.x - gammat * vtr.x, ft.y - gammat * vtr.y, ft.z - gammat * vtr.z}, ft);
}

// contacts.cpp's pair_force on the pairs from p in T's lanes (kN, or 2 kN side by side).
template <class T>
HWY_INLINE void pair_block(PairTable& t, const ContactStep& s, std::size_t p) {
  using L = Lanes<T>;
  using TM = typename L::Mask;
  const Pairs<T> pairs(t, s, p);
  const T delx = pairs.delx(), dely = pairs.dely(), delz = pairs.delz(), radsum = pairs.radsum();
  const TM touching = pairs.touching();
  const T cdf = L::filled(s.contact_distance_factor);
  // Close but not touching: the history is reset (surfacesClose); farther: left alone.
  const TM close = but_not(touching, less(pairs.rsq(), cdf * cdf * radsum * radsum));
  update_flags(&t.touching[p], touching, close);
  const T zero = L::filled(0.0);
  const Vec3<T> zeros{zero, zero, zero};
  if (none(touching)) {
    clear_history_where<T>(t, p, close);
    store_forces(t, p, touching, zeros);
    store_torques(t, p, touching, zeros, zeros);
    return;
  }
  const T r = root(pairs.rsq());
  const T rinv = L::filled(1.0) / r;
  const Vec3<T> en{delx * rinv, dely * rinv, delz * rinv};
  const T deltan = radsum - r;
  bool elastic = true;
  for (std::size_t g = p / kLanes; g * kLanes < p + L::kCount; ++g) elastic = elastic && t.elastic_frictionless[g] != 0;
  if (elastic) {
    // kn delta n: the reference's -gamman vn and ft are +-0 here (PairRecord::elastic_frictionless).
    const T fn = pairs.field(offsetof(PairRecord, kn_factor)) * root(pairs.field(offsetof(PairRecord, reff)) * deltan) * deltan;
    // The history never acts on such a pair; it is cleared where the reference's slide clears it.
    clear_history_where<T>(t, p, s.update_history ? either(close, touching) : close);
    store_forces(t, p, touching, Vec3<T>{fn * en.x, fn * en.y, fn * en.z});
    // The torque entries: zero since the table was built, unless other pairs may write them.
    if (!t.torque_free) store_torques(t, p, touching, zeros, zeros);
    return;
  }

  // Relative velocity at the contact point; lever arms shortened by half the overlap.
  const Vec3<T> vi = pairs.i(s.v, s.stride), vj = pairs.j(s.v, s.stride);
  const T vr1 = vi.x - vj.x, vr2 = vi.y - vj.y, vr3 = vi.z - vj.z;
  const T vn = vr1 * en.x + vr2 * en.y + vr3 * en.z;
  const T vt1 = vr1 - vn * en.x, vt2 = vr2 - vn * en.y, vt3 = vr3 - vn * en.z;
  const T half = L::filled(0.5);
  const T cri = pairs.radi() - half * deltan;
  const T crj = pairs.radj() - half * deltan;
  const Vec3<T> wi = pairs.i(s.w, s.stride), wj = pairs.j(s.w, s.stride);
  const T wr1 = (cri * wi.x + crj * wj.x) * rinv;
  const T wr2 = (cri * wi.y + crj * wj.y) * rinv;
  const T wr3 = (cri * wi.z + crj * wj.z) * rinv;
  const Vec3<T> vtr{vt1 - (delz * wr2 - dely * wr3), vt2 - (delx * wr3 - delz * wr1), vt3 - (dely * wr1 - delx * wr2)};

  // hertz_normal
  const T meff = pairs.field(offsetof(PairRecord, meff));
  const T damping = pairs.field(offsetof(PairRecord, damping_factor));
  const T sqrtval = root(pairs.field(offsetof(PairRecord, reff)) * deltan);
  const T kt = pairs.field(offsetof(PairRecord, st_factor)) * sqrtval;
  const T kn = pairs.field(offsetof(PairRecord, kn_factor)) * sqrtval;
  const TM damped = both(touching, not_equal(damping, zero));
  T gamman = damping, gammat = s.tangential_damping ? damping : zero;
  if (!none(damped)) {
    gamman = pick(damped, damping * root(pairs.field(offsetof(PairRecord, sn_factor)) * sqrtval * meff), gamman);
    if (s.tangential_damping) gammat = pick(damped, damping * root(kt * meff), gammat);
  }
  const T fn = negate(gamman) * vn + kn * deltan;

  const Vec3<T> shear_before{L::at(&t.history[0][p]), L::at(&t.history[1][p]), L::at(&t.history[2][p])};
  Vec3<T> shear = shear_before;
  const Vec3<T> ft = tangential(shear, en, vtr, kt, gammat, fn, pairs.field(offsetof(PairRecord, friction)), touching, s);
  const Vec3<T> tor{en.y * ft.z - en.z * ft.y, en.z * ft.x - en.x * ft.z, en.x * ft.y - en.y * ft.x};

  // The history: the new one where touching, zero where close, unchanged farther away.
  store_history(t, p, select(touching, shear, select(close, zeros, shear_before)));
  store_forces(t, p, touching, Vec3<T>{fn * en.x + ft.x, fn * en.y + ft.y, fn * en.z + ft.z});
  store_torques(t, p, touching, Vec3<T>{negate(cri) * tor.x, negate(cri) * tor.y, negate(cri) * tor.z},
                Vec3<T>{negate(crj) * tor.x, negate(crj) * tor.y, negate(crj) * tor.z});
}

// Particles window .. window + 15 of Motion::position_changed, as bits 0 .. 15.
HWY_INLINE std::uint32_t changed_in_window(const std::uint8_t* changed, std::int32_t window) {
  const auto w = static_cast<std::size_t>(window);
  std::uint32_t word;
  std::memcpy(&word, changed + w / 8, sizeof word);
  return word >> (w % 8);
}

// Whether none of one side's particles of the kLanes pairs from g * kLanes has a new position
// since they were last evaluated: by its window, or particle by particle for a gathered side
// (the pairs between blocks, whose particles lie far apart).
HWY_INLINE bool side_still(const std::uint8_t* changed, Fetch how, std::int32_t window, std::uint16_t particles,
                           const std::int32_t* index) {
  if (how != kGather) return (changed_in_window(changed, window) & particles) == 0;
  for (std::size_t k = 0; k < kLanes; ++k) {
    const auto i = static_cast<std::size_t>(index[k]);
    if ((changed[i / 8] >> (i % 8) & 1U) != 0) return false;
  }
  return true;
}

HWY_INLINE bool still(const PairTable& t, const std::uint8_t* changed, std::size_t g) {
  return side_still(changed, t.fetch_i[g], t.window_i[g], t.particles_i[g], &t.i[g * kLanes]) &&
         side_still(changed, t.fetch_j[g], t.window_j[g], t.particles_j[g], &t.j[g * kLanes]);
}

// The groups of both spheres of every pair of the block from p are due for their sums.
HWY_INLINE void mark_sums_due(const PairTable& t, const ContactStep& s, std::size_t p) {
  if (s.sums_due == nullptr) return;
  // Other threads may mark the same groups (with the same value): relaxed atomic stores.
  for (std::size_t q = p; q < p + kPairBlock; ++q) {
    for (const std::int32_t k : {t.i[q], t.j[q]}) {
      std::atomic_ref<std::uint8_t>(s.sums_due[static_cast<std::size_t>(k) / kLanes]).store(1, std::memory_order_relaxed);
    }
  }
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
  mark_sums_due(t, s, p);
  std::uint8_t& stored = t.forces_stored[p / kPairBlock];  // else every entry of the block is +0
  bool any = false;
  for (std::size_t q = p; q < p + kPairBlock; q += kN) {
    const auto [si, sj, rec, delx, dely, delz, rsq, radi, radj, radsum, touching] = find(t, s, q);
    if (hn::AllFalse(D(), touching)) {
      if (stored != 0) {
        const V zero = hn::Zero(D());
        store_forces(t, q, touching, Vec{zero, zero, zero});
      }
      continue;
    }
    any = true;
    const V r = hn::Sqrt(rsq);
    const V rinv = broadcast(1.0) / r;
    const V deltan = radsum - r;
    const V fn = rec.field(offsetof(PairRecord, kn_factor)) * hn::Sqrt(rec.field(offsetof(PairRecord, reff)) * deltan) * deltan;
    store_forces(t, q, touching, Vec{fn * (delx * rinv), fn * (dely * rinv), fn * (delz * rinv)});
  }
  stored = any ? 1 : 0;
}

void still_reference(PairTable& t, const ContactStep& s, std::size_t begin, std::size_t end) {
  for (std::size_t p = begin; p < end; p += kPairBlock) {
    std::uint8_t& evaluated = t.evaluated[p / kPairBlock];
    if (evaluated != 0 && still(t, s.position_changed, p / kLanes) && still(t, s.position_changed, p / kLanes + 1)) continue;
    evaluated = 1;
    mark_sums_due(t, s, p);
    contacts_reference(t, s, p, p + kPairBlock);
  }
}

// Thornton's law of kN pairs (model::ThorntonLaw, the record's law values: E*, R*, p_y, d_y, F_y,
// pi p_y R*): one broadcast where their group shares a record, else gathered.
struct ThorntonLanes {
  V y_star, r_star, d_y, f_y, slope;
};
HWY_INLINE ThorntonLanes thornton_law(const PairTable& t, std::size_t q) {
  static_assert(sizeof(ModelRecord) == (1 + kLawValues) * sizeof(double));
  const auto* table = reinterpret_cast<const double*>(t.model_records.data());
  const std::int32_t shared = t.shared_record[q / kLanes];
  const VI base = shared >= 0 ? hn::Zero(DI()) : hn::Mul(indices(&t.record[q]), hn::Set(DI(), 1 + kLawValues));
  const auto law = [&](std::size_t k) {
    const double* at = table + 1 + k;  // law[k], past rolling_friction
    return shared >= 0 ? broadcast(at[static_cast<std::size_t>(shared) * (1 + kLawValues)]) : hn::GatherIndex(D(), at, base);
  };
  return {law(0), law(1), law(3), law(4), law(5)};
}

// model::thornton_force at overlap d > 0 after the largest overlap dmax >= d, in its operations.
HWY_INLINE V thornton_force(const ThorntonLanes& l, V d, V dmax, M touching) {
  const V four_thirds = broadcast(4.0 / 3.0);
  const V elastic = four_thirds * l.y_star * root(l.r_star) * d * root(d);
  const M yielded = both(touching, greater(dmax, l.d_y));
  if (none(yielded)) return elastic;
  const V loading = l.f_y + l.slope * (d - l.d_y);
  const V f_max = l.f_y + l.slope * (dmax - l.d_y);
  const V a_p = root(l.r_star * dmax);
  const V r_p = broadcast(4.0) * l.y_star * a_p * a_p * a_p / (broadcast(3.0) * f_max);
  const V w = d - (dmax - l.r_star * dmax / r_p);
  const V unloading = zero_unless(greater(w, hn::Zero(D())), four_thirds * l.y_star * root(r_p) * w * root(w));
  return pick(yielded, pick(less(d, dmax), unloading, loading), elastic);
}

// pair_force (contacts.cpp) with thornton_normal on kN pairs from q of a torque_free table: the
// flags, the largest overlap (history slot `slot`), the force kept, and a contact that opens
// forgotten (its work banked first, lane by lane: a contact opens rarely; a padding lane, record 0,
// repeats a pair of its block and is flagged as it is, but has no law and banks nothing).
HWY_INLINE void thornton_lanes(PairTable& t, const ContactStep& s, std::size_t q, std::size_t slot) {
  const Found f = find(t, s, q);
  const V cdf = broadcast(s.contact_distance_factor);
  const M close = but_not(f.touching, less(f.rsq, cdf * cdf * f.radsum * f.radsum));
  const V zero = hn::Zero(D());
  if (!none(close)) {
    const unsigned forget = bits(close);
    for (std::size_t k = 0; k < kN; ++k) {
      if ((forget >> k & 1U) != 0 && t.touching[q + k] != 0 && t.record[q + k] != 0 && s.banked != nullptr) {
        bank_opened(t, s.banked, q + k);
      }
    }
    for (auto& h : t.history) hn::BlendedStore(zero, close, D(), &h[q]);
  }
  update_flags(&t.touching[q], f.touching, close);
  if (none(f.touching)) {
    store_forces(t, q, f.touching, Vec{zero, zero, zero});
    return;
  }
  const V r = root(f.rsq);
  const V rinv = broadcast(1.0) / r;
  const V deltan = f.radsum - r;
  const V before = load(&t.history[slot][q]);
  const V dmax = pick(greater(deltan, before), deltan, before);
  hn::BlendedStore(dmax, f.touching, D(), &t.history[slot][q]);
  const V fn = thornton_force(thornton_law(t, q), deltan, dmax, f.touching);
  store_forces(t, q, f.touching, Vec{fn * (f.delx * rinv), fn * (f.dely * rinv), fn * (f.delz * rinv)});
}

void thornton(PairTable& t, const ContactStep& s, std::size_t begin, std::size_t end) {
  const std::size_t slot = t.history.size() - 1;  // the normal model's one value, last (history_layout)
  for (std::size_t p = begin; p < end; p += kPairBlock) {
    std::uint8_t& evaluated = t.evaluated[p / kPairBlock];
    if (evaluated != 0 && still(t, s.position_changed, p / kLanes) && still(t, s.position_changed, p / kLanes + 1)) continue;
    evaluated = 1;
    mark_sums_due(t, s, p);
    for (std::size_t q = p; q < p + kPairBlock; q += kN) thornton_lanes(t, s, q, slot);
  }
}

void contacts(PairTable& t, const ContactStep& s, std::size_t begin, std::size_t end) {
  if (t.torque_free) {
    for (std::size_t p = begin; p < end; p += kPairBlock) elastic_block(t, s, p);
    return;
  }
  // Two vectors side by side where a vector holds at least four pairs (their sixteen registers
  // and more hold both halves; with two or one pairs a vector, one at a time).
  if constexpr (kN >= 4) {
    for (std::size_t p = begin; p < end; p += 2 * kN) pair_block<W>(t, s, p);
  } else {
    for (std::size_t p = begin; p < end; p += kN) pair_block<V>(t, s, p);
  }
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
  return {&contacts,     &sum_contributions, &first_half_only, &second_half, &second_and_first_half,
          &kinetic_sums, &still_reference,   &thornton};
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
