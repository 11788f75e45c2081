// The contact kernel sixteen pairs at a time with AVX-512: contacts.cpp's pair_force with every
// branch turned into lane masks. Each lane does the reference's floating-point operations in the
// reference's order (IEEE addition, multiplication, division and square root are exactly
// rounded, and refsim is built without contraction into fused multiply-adds), so each lane gives
// the reference's bits. Work a branch would skip is skipped when no lane needs it.
#include "contacts.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define GRANSTACK_HAVE_AVX512_KERNEL 1
#include <immintrin.h>
#if !defined(__clang__)
// GCC 12's avx512fintrin.h makes its "undefined" vectors by self-initialisation, which its own
// -Wuninitialized reports wherever a gather or a conversion is inlined.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#endif

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace granstack::refsim::detail {

#ifdef GRANSTACK_HAVE_AVX512_KERNEL

bool avx512_available() { return __builtin_cpu_supports("avx512f"); }

#define GRANSTACK_AVX512 __attribute__((target("avx512f")))
#define GRANSTACK_AVX512_INLINE __attribute__((target("avx512f"), always_inline)) inline

namespace {

// Sixteen doubles in two registers. Every operation is issued for both halves side by side, so
// the two halves' chains of square roots and divisions (each some 23 cycles of latency) overlap.
using Z = __m512d;
struct V {
  Z lo, hi;
};
using M = std::uint32_t;  // bit k for lane k: lanes 0..7 in lo, 8..15 in hi

GRANSTACK_AVX512_INLINE V operator+(V a, V b) { return {a.lo + b.lo, a.hi + b.hi}; }
GRANSTACK_AVX512_INLINE V operator-(V a, V b) { return {a.lo - b.lo, a.hi - b.hi}; }
GRANSTACK_AVX512_INLINE V operator*(V a, V b) { return {a.lo * b.lo, a.hi * b.hi}; }
GRANSTACK_AVX512_INLINE V operator/(V a, V b) { return {a.lo / b.lo, a.hi / b.hi}; }
GRANSTACK_AVX512_INLINE V operator-(V a) { return {-a.lo, -a.hi}; }
GRANSTACK_AVX512_INLINE V broadcast(double a) { return {_mm512_set1_pd(a), _mm512_set1_pd(a)}; }
GRANSTACK_AVX512_INLINE V load(const double* p) { return {_mm512_loadu_pd(p), _mm512_loadu_pd(p + kLanes)}; }
GRANSTACK_AVX512_INLINE void store(double* p, V a) {
  _mm512_storeu_pd(p, a.lo);
  _mm512_storeu_pd(p + kLanes, a.hi);
}
GRANSTACK_AVX512_INLINE __mmask8 lo(M m) { return static_cast<__mmask8>(m); }
GRANSTACK_AVX512_INLINE __mmask8 hi(M m) { return static_cast<__mmask8>(m >> kLanes); }
GRANSTACK_AVX512_INLINE M join(__mmask8 l, __mmask8 h) { return static_cast<M>(l) | static_cast<M>(h) << kLanes; }
GRANSTACK_AVX512_INLINE V sqrt(V a) { return {_mm512_sqrt_pd(a.lo), _mm512_sqrt_pd(a.hi)}; }
GRANSTACK_AVX512_INLINE V abs(V a) { return {_mm512_abs_pd(a.lo), _mm512_abs_pd(a.hi)}; }
template <int Predicate>
GRANSTACK_AVX512_INLINE M compare(V a, V b) {
  return join(_mm512_cmp_pd_mask(a.lo, b.lo, Predicate), _mm512_cmp_pd_mask(a.hi, b.hi, Predicate));
}
GRANSTACK_AVX512_INLINE M less(V a, V b) { return compare<_CMP_LT_OQ>(a, b); }
GRANSTACK_AVX512_INLINE M greater(V a, V b) { return compare<_CMP_GT_OQ>(a, b); }
GRANSTACK_AVX512_INLINE M equal(V a, V b) { return compare<_CMP_EQ_OQ>(a, b); }
GRANSTACK_AVX512_INLINE M not_equal(V a, V b) { return compare<_CMP_NEQ_UQ>(a, b); }
// `yes` in the lanes of m, `no` elsewhere.
GRANSTACK_AVX512_INLINE V select(M m, V yes, V no) {
  return {_mm512_mask_blend_pd(lo(m), no.lo, yes.lo), _mm512_mask_blend_pd(hi(m), no.hi, yes.hi)};
}
GRANSTACK_AVX512_INLINE V zero_unless(M m, V a) { return {_mm512_maskz_mov_pd(lo(m), a.lo), _mm512_maskz_mov_pd(hi(m), a.hi)}; }
GRANSTACK_AVX512_INLINE void store_where(double* p, M m, V a) {
  _mm512_mask_storeu_pd(p, lo(m), a.lo);
  _mm512_mask_storeu_pd(p + kLanes, hi(m), a.hi);
}

struct Vec {
  V x, y, z;
};

// Where eight pairs find one side's particles: at base + their lane (one load), within a window
// of 16 from `base` (two loads and a permutation), or anywhere (a gather).
struct Side {
  Fetch how;
  std::int32_t base;
  __m512i lanes;  // index - base
  __m256i index;
};

GRANSTACK_AVX512_INLINE Side side(const AlignedVector<std::int32_t>& index, const std::vector<std::int32_t>& window,
                                  const AlignedVector<std::uint8_t>& lanes, const std::vector<Fetch>& how, std::size_t p) {
  const std::size_t g = p / kLanes;
  return {how[g], window[g],
          _mm512_cvtepu8_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&lanes[p]))),
          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&index[p]))};
}

GRANSTACK_AVX512_INLINE Z fetch(const double* component, const Side& s) {
  if (s.how == kRun) return _mm512_loadu_pd(component + s.base);
  if (s.how == kWindowed) {
    return _mm512_permutex2var_pd(_mm512_loadu_pd(component + s.base), s.lanes, _mm512_loadu_pd(component + s.base + 8));
  }
  return _mm512_i32gather_pd(s.index, component, 8);
}

struct Sides {
  Side lo, hi;
};

GRANSTACK_AVX512_INLINE V fetch(const double* component, const Sides& s) { return {fetch(component, s.lo), fetch(component, s.hi)}; }

GRANSTACK_AVX512_INLINE Vec fetch(const double* a, std::size_t stride, const Sides& s) {
  return {fetch(a, s), fetch(a + stride, s), fetch(a + 2 * stride, s)};
}

// Eight pairs' records: one broadcast when they share one, else gathered.
struct Record {
  const PairRecord* shared;
  const double* table;
  __m256i index;  // record x 9 doubles
  GRANSTACK_AVX512_INLINE Z field(std::size_t d) const {
    if (shared != nullptr) return _mm512_set1_pd(reinterpret_cast<const double*>(shared)[d]);
    return _mm512_i32gather_pd(index, table + d, 8);
  }
};

GRANSTACK_AVX512_INLINE Record record(const PairTable& t, std::size_t p) {
  static_assert(sizeof(PairRecord) == 9 * sizeof(double));
  const auto* table = reinterpret_cast<const double*>(t.records.data());
  const std::int32_t shared = t.shared_record[p / kLanes];
  if (shared >= 0) return {&t.records[static_cast<std::size_t>(shared)], table, _mm256_setzero_si256()};
  const __m256i r = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&t.record[p]));
  return {nullptr, table, _mm256_add_epi32(_mm256_slli_epi32(r, 3), r)};
}

struct Records {
  Record lo, hi;
  GRANSTACK_AVX512_INLINE V field(std::size_t offset) const {
    return {lo.field(offset / sizeof(double)), hi.field(offset / sizeof(double))};
  }
};

// Force on i (the sums subtract it from j's), zero where not touching.
GRANSTACK_AVX512_INLINE void store_forces(PairTable& t, std::size_t p, M touching, const Vec& f) {
  store(&t.fx[p], zero_unless(touching, f.x));
  store(&t.fy[p], zero_unless(touching, f.y));
  store(&t.fz[p], zero_unless(touching, f.z));
}

// Torques on i and on j, zero where not touching.
GRANSTACK_AVX512_INLINE void store_torques(PairTable& t, std::size_t p, M touching, const Vec& ti, const Vec& tj) {
  const std::size_t q = t.padded() + p;
  store(&t.tx[p], zero_unless(touching, ti.x));
  store(&t.ty[p], zero_unless(touching, ti.y));
  store(&t.tz[p], zero_unless(touching, ti.z));
  store(&t.tx[q], zero_unless(touching, tj.x));
  store(&t.ty[q], zero_unless(touching, tj.y));
  store(&t.tz[q], zero_unless(touching, tj.z));
}

// The touching flags of eight pairs: set where touching, cleared where only close.
GRANSTACK_AVX512_INLINE void update_flags(std::uint8_t* flags, __mmask8 touching, __mmask8 close) {
  __m512i f = _mm512_cvtepu8_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(flags)));
  f = _mm512_mask_mov_epi64(f, close, _mm512_setzero_si512());
  f = _mm512_mask_mov_epi64(f, touching, _mm512_set1_epi64(1));
  _mm_storel_epi64(reinterpret_cast<__m128i*>(flags), _mm512_cvtepi64_epi8(f));
}

// What both kernels find first of sixteen pairs from p: where their spheres are, their
// records, their separation and which of them touch.
struct Found {
  Sides si, sj;
  Records rec;
  V delx, dely, delz, rsq, radi, radj, radsum;
  M touching;
};

GRANSTACK_AVX512_INLINE Found find(const PairTable& t, const ContactStep& s, std::size_t p) {
  const std::size_t p8 = p + kLanes;
  const Sides si{side(t.i, t.window_i, t.lane_i, t.fetch_i, p), side(t.i, t.window_i, t.lane_i, t.fetch_i, p8)};
  const Sides sj{side(t.j, t.window_j, t.lane_j, t.fetch_j, p), side(t.j, t.window_j, t.lane_j, t.fetch_j, p8)};
  const Records rec{record(t, p), record(t, p8)};
  const Vec xi = fetch(s.x, s.stride, si), xj = fetch(s.x, s.stride, sj);
  const V delx = xi.x - xj.x;
  const V dely = xi.y - xj.y;
  const V delz = xi.z - xj.z;
  const V rsq = delx * delx + dely * dely + delz * delz;
  const V radi = rec.field(offsetof(PairRecord, radi)), radj = rec.field(offsetof(PairRecord, radj));
  const V radsum = radi + radj;
  return {si, sj, rec, delx, dely, delz, rsq, radi, radj, radsum, less(rsq, radsum * radsum)};
}

GRANSTACK_AVX512 void block(PairTable& t, const ContactStep& s, std::size_t p) {
  const std::size_t p8 = p + kLanes;
  const auto [si, sj, rec, delx, dely, delz, rsq, radi, radj, radsum, touching] = find(t, s, p);
  const V cdf = broadcast(s.contact_distance_factor);
  // Close but not touching: the history is reset (surfacesClose); farther: left alone.
  const M close = static_cast<M>(~touching & less(rsq, cdf * cdf * radsum * radsum));
  update_flags(&t.touching[p], lo(touching), lo(close));
  update_flags(&t.touching[p8], hi(touching), hi(close));
  const V zero = broadcast(0.0);
  if (touching == 0) {
    for (double* a : {&t.shear_x[p], &t.shear_y[p], &t.shear_z[p]}) store_where(a, close, zero);
    store_forces(t, p, touching, {zero, zero, zero});
    store_torques(t, p, touching, {zero, zero, zero}, {zero, zero, zero});
    return;
  }
  const V one = broadcast(1.0), half = broadcast(0.5);
  const V r = sqrt(rsq);
  const V rinv = one / r;
  const Vec en{delx * rinv, dely * rinv, delz * rinv};
  const V deltan = radsum - r;
  if (t.elastic_frictionless[p / kLanes] != 0 && t.elastic_frictionless[p8 / kLanes] != 0) {
    // kn delta n: the reference's -gamman vn and ft are +-0 here (PairRecord::elastic_frictionless).
    const V fn = rec.field(offsetof(PairRecord, kn_factor)) * sqrt(rec.field(offsetof(PairRecord, reff)) * deltan) * deltan;
    // The history never acts on such a pair; it is cleared where the reference's slide clears it.
    for (double* a : {&t.shear_x[p], &t.shear_y[p], &t.shear_z[p]}) {
      store_where(a, static_cast<M>(close | (s.update_history ? touching : 0U)), zero);
    }
    store_forces(t, p, touching, {fn * en.x, fn * en.y, fn * en.z});
    // The torque entries: zero since the table was built, unless other pairs may write them.
    if (!t.torque_free) store_torques(t, p, touching, {zero, zero, zero}, {zero, zero, zero});
    return;
  }

  // Relative velocity at the contact point; lever arms shortened by half the overlap.
  const Vec vi = fetch(s.v, s.stride, si), vj = fetch(s.v, s.stride, sj);
  const V vr1 = vi.x - vj.x, vr2 = vi.y - vj.y, vr3 = vi.z - vj.z;
  const V vn = vr1 * en.x + vr2 * en.y + vr3 * en.z;
  const V vt1 = vr1 - vn * en.x, vt2 = vr2 - vn * en.y, vt3 = vr3 - vn * en.z;
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
  const V sqrtval = sqrt(rec.field(offsetof(PairRecord, reff)) * deltan);
  const V kt = rec.field(offsetof(PairRecord, st_factor)) * sqrtval;
  const V kn = rec.field(offsetof(PairRecord, kn_factor)) * sqrtval;
  const M damped = static_cast<M>(touching & not_equal(damping, zero));
  V gamman = damping, gammat = s.tangential_damping ? damping : zero;
  if (damped != 0) {
    gamman = select(damped, damping * sqrt(rec.field(offsetof(PairRecord, sn_factor)) * sqrtval * meff), gamman);
    if (s.tangential_damping) gammat = select(damped, damping * sqrt(kt * meff), gammat);
  }
  const V fn = -gamman * vn + kn * deltan;

  // tangential_force
  Vec shear{load(&t.shear_x[p]), load(&t.shear_y[p]), load(&t.shear_z[p])};
  const Vec shear_before = shear;
  if (s.update_history) {
    const V dt = broadcast(s.dt);
    shear.x = shear.x + vtr.x * dt;
    shear.y = shear.y + vtr.y * dt;
    shear.z = shear.z + vtr.z * dt;
    const V rsht = shear.x * en.x + shear.y * en.y + shear.z * en.z;
    shear.x = shear.x - rsht * en.x;
    shear.y = shear.y - rsht * en.y;
    shear.z = shear.z - rsht * en.z;
  }
  const V shear_sq = shear.x * shear.x + shear.y * shear.y + shear.z * shear.z;
  Vec ft{-(kt * shear.x), -(kt * shear.y), -(kt * shear.z)};
  const V mu = rec.field(offsetof(PairRecord, friction));
  const M frictionless = equal(mu, zero);
  // Frictionless sliding leaves a zero force and a zero history (as the reference).
  const M zero_slide = static_cast<M>(touching & frictionless & greater(kt, zero) & greater(shear_sq, zero));
  // A frictionless pair that does not slide sticks: its kt |xi| is 0, not above mu |fn| = 0.
  const M coulomb = static_cast<M>(touching & ~frictionless);
  M sliding = 0;
  if (coulomb != 0) {
    const V shrmag = sqrt(shear_sq);
    const V ft_shear = kt * shrmag;
    const V ft_friction = mu * abs(fn);
    sliding = static_cast<M>(coulomb & greater(ft_shear, ft_friction));
    if (sliding != 0) {
      // Sliding: scaled down to the Coulomb limit, or zero if there is no displacement to scale.
      const M scaled = static_cast<M>(sliding & not_equal(shrmag, zero));
      const V ratio = ft_friction / ft_shear;
      ft = {select(scaled, ft.x * ratio, select(sliding, zero, ft.x)), select(scaled, ft.y * ratio, select(sliding, zero, ft.y)),
            select(scaled, ft.z * ratio, select(sliding, zero, ft.z))};
      if (s.update_history) {
        shear = {select(scaled, -ft.x / kt, shear.x), select(scaled, -ft.y / kt, shear.y), select(scaled, -ft.z / kt, shear.z)};
      }
    }
  }
  if (zero_slide != 0) {
    ft = {select(zero_slide, zero, ft.x), select(zero_slide, zero, ft.y), select(zero_slide, zero, ft.z)};
    if (s.update_history) {
      shear = {select(zero_slide, zero, shear.x), select(zero_slide, zero, shear.y), select(zero_slide, zero, shear.z)};
    }
  }
  const M sticking = static_cast<M>(touching & ~zero_slide & ~sliding);
  ft = {select(sticking, ft.x - gammat * vtr.x, ft.x), select(sticking, ft.y - gammat * vtr.y, ft.y),
        select(sticking, ft.z - gammat * vtr.z, ft.z)};
  const Vec tor{en.y * ft.z - en.z * ft.y, en.z * ft.x - en.x * ft.z, en.x * ft.y - en.y * ft.x};

  // The history: the new one where touching, zero where close, unchanged farther away.
  store(&t.shear_x[p], select(touching, shear.x, select(close, zero, shear_before.x)));
  store(&t.shear_y[p], select(touching, shear.y, select(close, zero, shear_before.y)));
  store(&t.shear_z[p], select(touching, shear.z, select(close, zero, shear_before.z)));
  store_forces(t, p, touching, {fn * en.x + ft.x, fn * en.y + ft.y, fn * en.z + ft.z});
  store_torques(t, p, touching, {-cri * tor.x, -cri * tor.y, -cri * tor.z}, {-crj * tor.x, -crj * tor.y, -crj * tor.z});
}

}  // namespace

// Lanes `in_lo` of the low register and `in_hi` of the high one, from a register holding the
// former in its lowest lanes and the latter in lanes `after_lo`; zero elsewhere.
GRANSTACK_AVX512_INLINE V unpack(Z packed, __mmask8 in_lo, __mmask8 in_hi, __mmask8 after_lo) {
  return {_mm512_maskz_expand_pd(in_lo, packed), _mm512_maskz_expand_pd(in_hi, _mm512_maskz_compress_pd(after_lo, packed))};
}

// Particles window .. window + 15 of Motion::position_changed, as bits 0 .. 15.
GRANSTACK_AVX512_INLINE std::uint32_t changed_in_window(const std::uint8_t* changed, std::int32_t window) {
  const auto w = static_cast<std::size_t>(window);
  std::uint32_t word;
  std::memcpy(&word, changed + w / 8, sizeof word);
  return word >> (w % 8);
}

// Whether no particle of the kLanes pairs from g * kLanes has a new position since they were
// last evaluated (as far as windows can tell; a gathered side is never still).
GRANSTACK_AVX512_INLINE bool still(const PairTable& t, const std::uint8_t* changed, std::size_t g) {
  return t.fetch_i[g] != kGather && t.fetch_j[g] != kGather &&
         (changed_in_window(changed, t.window_i[g]) & t.particles_i[g]) == 0 &&
         (changed_in_window(changed, t.window_j[g]) & t.particles_j[g]) == 0;
}

// block() for a table whose every pair is elastic and frictionless (PairTable::torque_free):
// the force kn delta n alone. The history of such a pair is +0 from its start to its end (no
// path of the model makes it anything else), so neither it nor the touching flags that decide
// which history survives a rebuild need to be written; the torque entries stay +0. The force
// is a function of the two positions alone, so a block none of whose spheres has a new
// position since its last evaluation keeps its entries: the stack at rest ahead of the wave,
// whose spheres' round-off forces are far too small to change a position's bits.
GRANSTACK_AVX512_INLINE void elastic_block(PairTable& t, const ContactStep& s, std::size_t p) {
  std::uint8_t& evaluated = t.evaluated[p / kPairBlock];
  if (evaluated != 0 && still(t, s.position_changed, p / kLanes) && still(t, s.position_changed, p / kLanes + 1)) return;
  evaluated = 1;
  const auto [si, sj, rec, delx, dely, delz, rsq, radi, radj, radsum, touching] = find(t, s, p);
  std::uint8_t& stored = t.forces_stored[p / kPairBlock];
  if (touching == 0) {
    if (stored != 0) {
      const V zero = broadcast(0.0);
      store_forces(t, p, touching, {zero, zero, zero});
      stored = 0;
    }
    return;
  }
  stored = 1;
  const Record& shared = rec.lo;
  if (__builtin_popcount(touching) <= static_cast<int>(kLanes) && shared.shared != nullptr && shared.shared == rec.hi.shared) {
    // At most eight touch, all of one record (the common case: about a third of the pairs
    // touch, by round-off at rest): their square roots and division, which share one unit of
    // some 17 cycles per register, in one register, not two. Lane for lane the same operations.
    const __mmask8 in_lo = lo(touching), in_hi = hi(touching);
    const auto after_lo = static_cast<__mmask8>(((1U << __builtin_popcount(in_hi)) - 1U) << __builtin_popcount(in_lo));
    const Z packed_rsq = _mm512_mask_expand_pd(_mm512_maskz_compress_pd(in_lo, rsq.lo), after_lo, _mm512_maskz_compress_pd(in_hi, rsq.hi));
    const Z r = _mm512_sqrt_pd(packed_rsq);
    const Z rinv = _mm512_set1_pd(1.0) / r;
    const Z deltan = radsum.lo - r;
    const Z fn = shared.field(offsetof(PairRecord, kn_factor) / sizeof(double)) *
                 _mm512_sqrt_pd(shared.field(offsetof(PairRecord, reff) / sizeof(double)) * deltan) * deltan;
    const V rinv_v = unpack(rinv, in_lo, in_hi, after_lo), fn_v = unpack(fn, in_lo, in_hi, after_lo);
    store_forces(t, p, touching, {fn_v * (delx * rinv_v), fn_v * (dely * rinv_v), fn_v * (delz * rinv_v)});
    return;
  }
  const V r = sqrt(rsq);
  const V rinv = broadcast(1.0) / r;
  const V deltan = radsum - r;
  const V fn = rec.field(offsetof(PairRecord, kn_factor)) * sqrt(rec.field(offsetof(PairRecord, reff)) * deltan) * deltan;
  store_forces(t, p, touching, {fn * (delx * rinv), fn * (dely * rinv), fn * (delz * rinv)});
}

GRANSTACK_AVX512 void contacts_avx512(PairTable& pairs, const ContactStep& s, std::size_t begin, std::size_t end) {
  if (pairs.torque_free) {
    for (std::size_t p = begin; p < end; p += kPairBlock) elastic_block(pairs, s, p);
    return;
  }
  for (std::size_t p = begin; p < end; p += kPairBlock) block(pairs, s, p);
}

// The plan's arrays as plain pointers, which the compiler keeps in registers.
struct PlanView {
  const std::size_t* first_round;
  const std::size_t* first_added;
  const std::uint8_t* lanes_in;
  const Fetch* fetch;
  const std::int32_t* window;
  const std::uint8_t* lane;
  const std::int32_t* entry;
};

// Component c's entries x into its sums, in the lanes of m: subtracted if Subtract and c is a
// force component, else added. The other lanes keep their sums, as adding the +0 of the
// reference's order would (no sum that starts at +0 is ever -0).
template <bool Subtract>
GRANSTACK_AVX512_INLINE void take(int c, Z& sum, __mmask8 m, Z x) {
  sum = Subtract && c < 3 ? _mm512_mask_sub_pd(sum, m, sum, x) : _mm512_mask_add_pd(sum, m, sum, x);
}

// Rounds [first, last) of a group over `Components` arrays (3: forces only, 6: and torques),
// into sums in registers: the forces added, or subtracted with the torques read `torque_side`
// entries on (the pairs' j side). A run or a window may read, for the lanes not in the round,
// entries of other pairs or the tables' padding: take() leaves those lanes alone.
template <int Components, bool Subtract>
GRANSTACK_AVX512_INLINE void sum_rounds(const PlanView& plan, std::size_t first, std::size_t last, const double* const* in,
                                        std::size_t torque_side, Z* sum) {
  for (std::size_t r = first; r < last; ++r) {
    const __mmask8 m = plan.lanes_in[r];
    if (plan.fetch[r] == kRun) {
      const std::size_t w = static_cast<std::size_t>(plan.window[r]);
      for (int c = 0; c < Components; ++c) take<Subtract>(c, sum[c], m, _mm512_loadu_pd(in[c] + w + (c < 3 ? 0 : torque_side)));
    } else if (plan.fetch[r] == kWindowed) {
      const __m512i lanes = _mm512_cvtepu8_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&plan.lane[r * kLanes])));
      const std::size_t w = static_cast<std::size_t>(plan.window[r]);
      for (int c = 0; c < Components; ++c) {
        const double* a = in[c] + w + (c < 3 ? 0 : torque_side);
        take<Subtract>(c, sum[c], m, _mm512_permutex2var_pd(_mm512_loadu_pd(a), lanes, _mm512_loadu_pd(a + kLanes)));
      }
    } else {
      const __m256i index = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&plan.entry[r * kLanes]));
      for (int c = 0; c < Components; ++c) {
        take<Subtract>(c, sum[c], m, _mm512_mask_i32gather_pd(_mm512_setzero_pd(), m, index, in[c] + (c < 3 ? 0 : torque_side), 8));
      }
    }
  }
}

// One group's sums: its rounds as the pairs' j, then as their i.
template <int Components>
GRANSTACK_AVX512_INLINE void sum_group(const PlanView& plan, std::size_t g, const double* const* in, std::size_t j_side,
                                       double* const* out) {
  Z sum[Components];
  for (auto& s : sum) s = _mm512_setzero_pd();
  sum_rounds<Components, true>(plan, plan.first_round[g], plan.first_added[g], in, j_side, sum);
  sum_rounds<Components, false>(plan, plan.first_added[g], plan.first_round[g + 1], in, 0, sum);
  for (int c = 0; c < Components; ++c) _mm512_storeu_pd(out[c] + g * kLanes, sum[c]);
}

GRANSTACK_AVX512 void sum_contributions_avx512(const PairTable& pairs, const SumPlan& plan, double* f, double* t,
                                               std::size_t stride, std::size_t group_begin, std::size_t group_end,
                                               bool zero_torques) {
  const double* in[6] = {pairs.fx.data(), pairs.fy.data(), pairs.fz.data(), pairs.tx.data(), pairs.ty.data(), pairs.tz.data()};
  double* out[6] = {f, f + stride, f + 2 * stride, t, t + stride, t + 2 * stride};
  const PlanView view{plan.first_round.data(), plan.first_added.data(), plan.lanes_in.data(), plan.fetch.data(),
                      plan.window.data(),      plan.lane.data(),        plan.entry.data()};
  const std::size_t j_side = pairs.padded();
  for (std::size_t g = group_begin; g < group_end; ++g) {
    if (pairs.torque_free) {
      // Without torques (PairTable::torque_free) every torque sum is 0 + +-0 + ... = +0.
      sum_group<3>(view, g, in, j_side, out);
      if (zero_torques) {
        for (int c = 3; c < 6; ++c) _mm512_storeu_pd(out[c] + g * kLanes, _mm512_setzero_pd());
      }
    } else {
      sum_group<6>(view, g, in, j_side, out);
    }
  }
}

// The first half (kick, drift, spin kick, rebuild check), after the previous step's second
// half (kick, spin kick) when SecondHalfFirst: each particle's operations in the reference's order.
template <bool SecondHalfFirst>
GRANSTACK_AVX512_INLINE bool first_half(const Motion& m, std::size_t begin, std::size_t end) {
  // The arrays do not overlap one another (nor the Motion), which the compiler cannot know.
  double* __restrict x = m.x;
  double* __restrict v = m.v;
  double* __restrict w = m.w;
  const double* __restrict f = m.f;
  const double* __restrict t = m.t;
  const double* __restrict kicks = m.kick;
  const double* __restrict spins = m.spin_kick;
  const double* __restrict x0 = m.x_at_build;
  std::uint8_t* __restrict changed = m.position_changed;
  const std::size_t stride = m.stride;
  const bool spin_on = m.spin;
  const Z dt = _mm512_set1_pd(m.dt), trigger = _mm512_set1_pd(m.trigger);
  __mmask8 moved = 0;
  for (std::size_t i = begin; i < end; i += kLanes) {
    const Z kick = _mm512_loadu_pd(&kicks[i]), spin = _mm512_loadu_pd(&spins[i]);
    Z dsq = _mm512_setzero_pd();
    __mmask8 new_position = 0;
#pragma GCC unroll 3
    for (std::size_t d = 0; d < 3; ++d) {
      const std::size_t e = i + d * stride;
      const Z fe = _mm512_loadu_pd(&f[e]);
      Z ve = _mm512_loadu_pd(&v[e]);
      if (SecondHalfFirst) ve = ve + kick * fe;
      ve = ve + kick * fe;
      const Z x_before = _mm512_loadu_pd(&x[e]);
      const Z xe = x_before + dt * ve;
      new_position = static_cast<__mmask8>(
          new_position | _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(xe), _mm512_castpd_si512(x_before)));
      _mm512_storeu_pd(&v[e], ve);
      _mm512_storeu_pd(&x[e], xe);
      if (spin_on) {
        const Z te = _mm512_loadu_pd(&t[e]);
        Z we = _mm512_loadu_pd(&w[e]);
        if (SecondHalfFirst) we = we + spin * te;
        _mm512_storeu_pd(&w[e], we + spin * te);
      }
      const Z de = xe - _mm512_loadu_pd(&x0[e]);
      dsq = dsq + de * de;  // dx^2, then + dy^2, then + dz^2: the reference's order
    }
    moved = static_cast<__mmask8>(moved | _mm512_cmp_pd_mask(dsq, trigger, _CMP_GT_OQ));
    changed[i / kLanes] = new_position;
  }
  return moved != 0;
}

GRANSTACK_AVX512 bool first_half_avx512(const Motion& m, std::size_t begin, std::size_t end) {
  return first_half<false>(m, begin, end);
}

GRANSTACK_AVX512 bool second_and_first_half_avx512(const Motion& m, std::size_t begin, std::size_t end) {
  return first_half<true>(m, begin, end);
}

GRANSTACK_AVX512 void second_half_avx512(const Motion& m, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; i += kLanes) {
    const Z kick = _mm512_loadu_pd(&m.kick[i]), spin = _mm512_loadu_pd(&m.spin_kick[i]);
    for (std::size_t e = i; e < i + 3 * m.stride; e += m.stride) {
      _mm512_storeu_pd(&m.v[e], _mm512_loadu_pd(&m.v[e]) + kick * _mm512_loadu_pd(&m.f[e]));
      if (m.spin) _mm512_storeu_pd(&m.w[e], _mm512_loadu_pd(&m.w[e]) + spin * _mm512_loadu_pd(&m.t[e]));
    }
  }
}

#else

bool avx512_available() { return false; }

[[noreturn]] void no_avx512() { throw std::logic_error("refsim: this build has no AVX-512 kernels"); }
void contacts_avx512(PairTable&, const ContactStep&, std::size_t, std::size_t) { no_avx512(); }
bool first_half_avx512(const Motion&, std::size_t, std::size_t) { no_avx512(); }
void sum_contributions_avx512(const PairTable&, const SumPlan&, double*, double*, std::size_t, std::size_t, std::size_t,
                              bool) {
  no_avx512();
}
void second_half_avx512(const Motion&, std::size_t, std::size_t) { no_avx512(); }
bool second_and_first_half_avx512(const Motion&, std::size_t, std::size_t) { no_avx512(); }

#endif

}  // namespace granstack::refsim::detail
