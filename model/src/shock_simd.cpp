// The shock response spectrum's oscillators (shock_simd.hpp), written once with Google Highway and
// compiled for every instruction set it targets; the best one this CPU runs is chosen at run time.
// A lane is one natural frequency, so no lane reads another's and every target gives the scalar
// fallback's bits (the file is compiled without contraction into fused multiply-adds).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shock_simd.cpp"
#include <granstack/model/highway_targets.hpp>  // IWYU pragma: keep

#include "shock_simd.hpp"

HWY_BEFORE_NAMESPACE();
namespace granstack::model::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void oscillate(const Oscillators& o, const double* base, std::size_t n, double* z0, double* z1, double* peak) {
  const hn::CappedTag<double, kOscillatorLanes> d;
  const std::size_t lanes = hn::Lanes(d);
  for (std::size_t k = 0; k < o.count; k += lanes) {
    const auto p00 = hn::LoadU(d, &o.p00[k]), p01 = hn::LoadU(d, &o.p01[k]);
    const auto p10 = hn::LoadU(d, &o.p10[k]), p11 = hn::LoadU(d, &o.p11[k]);
    const auto c0 = hn::LoadU(d, &o.c0[k]), c1 = hn::LoadU(d, &o.c1[k]);
    const auto d0 = hn::LoadU(d, &o.d0[k]), d1 = hn::LoadU(d, &o.d1[k]);
    const auto o0 = hn::LoadU(d, &o.o0[k]), o1 = hn::LoadU(d, &o.o1[k]);
    auto x0 = hn::Zero(d), x1 = hn::Zero(d), top = hn::Zero(d);
    auto before = hn::Zero(d);  // the base's acceleration at the interval's start: 0 at t = 0
    for (std::size_t i = 0; i < n; ++i) {
      const auto after = hn::Set(d, base[i]);
      const auto y0 = hn::Add(hn::Add(hn::Add(hn::Mul(p00, x0), hn::Mul(p01, x1)), hn::Mul(c0, before)), hn::Mul(d0, after));
      const auto y1 = hn::Add(hn::Add(hn::Add(hn::Mul(p10, x0), hn::Mul(p11, x1)), hn::Mul(c1, before)), hn::Mul(d1, after));
      x0 = y0;
      x1 = y1;
      const auto a = hn::Abs(hn::Add(hn::Mul(o0, x0), hn::Mul(o1, x1)));
      top = hn::IfThenElse(hn::Lt(top, a), a, top);  // std::max(top, a): a NaN leaves it
      before = after;
    }
    hn::StoreU(x0, d, z0 + k);
    hn::StoreU(x1, d, z1 + k);
    hn::StoreU(top, d, peak + k);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace granstack::model::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace granstack::model::detail {

HWY_EXPORT(oscillate);

void run_oscillators(const Oscillators& o, const double* base, std::size_t n, double* z0, double* z1, double* peak) {
  HWY_DYNAMIC_DISPATCH(oscillate)(o, base, n, z0, z1, peak);
}

}  // namespace granstack::model::detail
#endif  // HWY_ONCE
