// LIGGGHTS 3.8's normal model thornton_ning (normal_model_thornton_ning.h, Thornton and Ning 1998),
// with surfaceEnergy 0 as granstack writes it, operation by operation so that refsim gives
// LIGGGHTS's doubles: the force built step by step, F_n = F_(n-1) + k (d_n - d_(n-1)), with k =
// 2 E* sqrt(R* d) while elastic or unloading and 2 E* a_y on a plastic loading step; yield when
// sqrt(R* d) reaches a_y = r_i * coefficientYieldRatio[type_i] (the first body's alone); a force
// that would fall below zero is zero and the contact "detaches" at that overlap, reloading from
// there. No normal damping; the tangential damping 2 sqrt(5/6) beta sqrt(k_t m*) (sign as LIGGGHTS
// has it; zero at restitution 1, which the spec requires of this law). Its ten history values, in
// LIGGGHTS's order: virgin flag, d_old, d_max, F_old, F_max, adhesion flag, detaching overlap,
// detaching flag, detaching force, yielding flag.
#include "sub_models.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace granstack::refsim::detail {


void thornton_ning_record(const ModelConstants& k, double radi, double, double, ModelRecord& r) {
  r.law[0] = k.y_star;
  r.law[1] = radi * k.yield_ratio;  // a_yield = ri * yield_ratio[itype]
}

namespace {
double calculate_fl(double force_old, double fc, int adhesion_flag) {
  return adhesion_flag == 1 ? force_old + 2 * (fc - std::sqrt(fc * (force_old + fc)))
                            : force_old + 2 * (fc + std::sqrt(fc * (force_old + fc)));
}
double calculate_a(double fl, double e, double r, double delta, double gamma_s) {
  return gamma_s == 0 ? std::sqrt(r * delta) : std::pow((3. * r * fl) / (4. * e), (1. / 3.));
}
double elastic_differential(double a, double e, double fl, double fc) {
  if (fc == 0) return 2 * e * a;
  return 2 * e * a * (3 * std::sqrt(fl) - 3 * std::sqrt(fc)) / (3 * std::sqrt(fl) - std::sqrt(fc));
}
double plastic_differential(double a_yield, double e, double fl, double fc, double yield_stress, double r) {
  if (fc == 0) return 2 * e * a_yield;
  return (3 * M_PI * r * yield_stress * std::sqrt(fl) - 2 * a_yield * e * std::sqrt(fc)) /
         (3 * std::sqrt(fl) - std::sqrt(fc));
}
// branch_2_force_calc: the elastic (unloading or reloading) step; df out.
double elastic_step(double force_old, double fc, int adhesion_flag, double e, double rp, double delta, double dn,
                    double gamma_s, double& df) {
  const double fl_r = calculate_fl(force_old, fc, adhesion_flag);
  const double a = calculate_a(fl_r, e, rp, delta, gamma_s);
  df = elastic_differential(a, e, fl_r, fc) * dn;
  return force_old + df;
}
}  // namespace

namespace {
// The contact's ten history values, unpacked as LIGGGHTS reads them (ints where it keeps flags).
struct NingHistory {
  int virgin_loading_flag;
  double delta_old, delta_max, force_old, force_max;
  int adhesion_flag;
  double detaching_delta;
  int detaching_flag;
  double detaching_force;
  int yielding_flag;
};
NingHistory unpack(const double* h) {
  return {static_cast<int>(h[0]), h[1], h[2], h[3], h[4], static_cast<int>(h[5]), h[6], static_cast<int>(h[7]), h[8],
          static_cast<int>(h[9])};
}
// The contact's first evaluation: a virgin loading from zero force (fc = 0: no adhesion).
void start_virgin(NingHistory& h, double fc) {
  h = {1, 0, 0, -(8. / 9.) * fc, -(8. / 9.) * fc, 0, 0, 0, -(5. / 9.) * fc, 0};
}
// The law's constants of one evaluation (surfaceEnergy 0 as granstack writes it).
struct NingLaw {
  double e, reff, a_yield, yield_stress, gamma_s, fc;
  bool plastic_from_start;
};
// The force of a contact in touch (UNLOADING_RELOADING and what follows it in LIGGGHTS's code).
double contact_force(NingHistory& h, NingLaw law, double delta) {
  double f = 0.0, df = 0.0;
  const double dn = delta - h.delta_old;
  if (delta >= h.delta_max) {  // loading
    h.delta_max = delta;
    const double fl = calculate_fl(h.force_old, law.fc, 0);
    const double a = calculate_a(fl, law.e, law.reff, delta, law.gamma_s);
    if (h.yielding_flag == 0 && a >= law.a_yield) h.yielding_flag = 1;
    if (law.plastic_from_start || h.yielding_flag == 1) {
      df = plastic_differential(law.a_yield, law.e, fl, law.fc, law.yield_stress, law.reff) * dn;
      f = h.force_old + df;
    } else {
      f = elastic_step(h.force_old, law.fc, h.adhesion_flag, law.e, law.reff, delta, dn, law.gamma_s, df);
    }
  } else if (h.yielding_flag == 0) {  // unloading or reloading, never yielded
    f = elastic_step(h.force_old, law.fc, h.adhesion_flag, law.e, law.reff, delta, dn, law.gamma_s, df);
  } else {  // ... yielded: about the modified radius (R* itself without adhesion)
    const double fl_max = calculate_fl(h.force_max, law.fc, 0);
    law.reff = law.reff * fl_max / (h.force_max + std::sqrt(4 * law.fc * fl_max));
    law.fc = (3. / 2.) * M_PI * law.gamma_s * law.reff;
    f = elastic_step(h.force_old, law.fc, h.adhesion_flag, law.e, law.reff, delta, dn, law.gamma_s, df);
  }
  if (law.gamma_s == 0 && f < 0) {  // no cohesion: detach here
    f = 0;
    h.detaching_flag = 1;
    h.detaching_delta = delta;
    h.detaching_force = 0;
  }
  if (f < -law.fc) {
    h.adhesion_flag = 1 - h.adhesion_flag;
    f = elastic_step(h.force_old, law.fc, h.adhesion_flag, law.e, law.reff, delta, dn, law.gamma_s, df);
  }
  if (h.adhesion_flag == 1 && f + 3 * df >= -(5. / 9.) * law.fc) {
    f = 0;
    h.detaching_flag = 1;
    h.detaching_delta = h.delta_old;
    h.detaching_force = h.force_old;
  }
  return f;
}
}  // namespace

Normal thornton_ning_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool,
                            double* history) {
  const double reff = c.reff, e = r.law[0], a_yield = r.law[1], gamma_s = 0.0;  // Yeff, ri * yield_ratio[itype]
  const double fc = gamma_s * reff * M_PI * (3. / 2.);
  const double delta = c.deltan;
  const double yield_stress = ((2. * e * a_yield) / (M_PI * reff)) - std::sqrt(2. * gamma_s * e / (M_PI * a_yield));
  const double limit_yield_stress = std::pow(2. * e * e * gamma_s / (M_PI * M_PI * reff), (1. / 3.));
  if (yield_stress <= 0) throw std::invalid_argument("Invalid yield stress, please check surface energy and yield ratio!");
  const double sqrtval = std::sqrt(reff * c.deltan);
  const double k_t = k.st_factor * sqrtval;
  const double gammat = -k.damping_factor * std::sqrt(k_t * c.meff);  // 2 sqrt(5/6) beta sqrt(k_t m*)
  NingHistory h = unpack(history);
  if (h.virgin_loading_flag != 1) start_virgin(h, fc);
  bool in_touch = true;
  if (h.detaching_flag == 1) {  // detached: reloads from where it left once it reaches there
    in_touch = delta >= h.detaching_delta;
    if (in_touch) {
      h.detaching_flag = 0;
      h.delta_old = h.detaching_delta;
      h.force_old = h.detaching_force;
    }
  }
  const double f = in_touch ? contact_force(h, {e, reff, a_yield, yield_stress, gamma_s, fc,
                                                yield_stress < limit_yield_stress}, delta)
                            : 0.0;
  h.force_max = (f > h.force_max) ? f : h.force_max;
  const double values[kThorntonNingHistory] = {
      static_cast<double>(h.virgin_loading_flag), delta, h.delta_max, f, h.force_max,
      static_cast<double>(h.adhesion_flag), h.detaching_delta, static_cast<double>(h.detaching_flag),
      h.detaching_force, static_cast<double>(h.yielding_flag)};
  std::copy(std::begin(values), std::end(values), history);
  // k_n: LIGGGHTS's law sets none (rolling cdt is refused with it).
  return {f, k_t, gammat, 0.0};
}

}  // namespace granstack::refsim::detail
