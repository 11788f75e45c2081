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

#include <cmath>
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

Normal thornton_ning_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool,
                            double* history) {
  double reff = c.reff;
  const double meff = c.meff;
  const double e = r.law[0];  // Yeff
  const double gamma_s = 0.0;
  double fc = gamma_s * reff * M_PI * (3. / 2.);
  const double delta = c.deltan;
  const double a_yield = r.law[1];
  const double yield_stress = ((2. * e * a_yield) / (M_PI * reff)) - std::sqrt(2. * gamma_s * e / (M_PI * a_yield));
  const double limit_yield_stress = std::pow(2. * e * e * gamma_s / (M_PI * M_PI * reff), (1. / 3.));
  const int plastic_from_start = yield_stress < limit_yield_stress ? 1 : 0;
  if (yield_stress <= 0) throw std::invalid_argument("Invalid yield stress, please check surface energy and yield ratio!");

  int virgin_loading_flag = static_cast<int>(history[0]);
  double delta_old = history[1], delta_max = history[2], force_old = history[3], force_max = history[4];
  int adhesion_flag = static_cast<int>(history[5]);
  double detaching_delta = history[6];
  int detaching_flag = static_cast<int>(history[7]);
  double detaching_force = history[8];
  int yielding_flag = static_cast<int>(history[9]);

  const double sqrtval = std::sqrt(reff * c.deltan);
  const double k_t = k.st_factor * sqrtval;
  const double gammat = -k.damping_factor * std::sqrt(k_t * meff);  // 2 sqrt(5/6) beta sqrt(k_t m*)
  if (virgin_loading_flag != 1) {
    force_old = -(8. / 9.) * fc;
    delta_old = 0;
    virgin_loading_flag = 1;
    force_max = force_old;
    delta_max = 0;
    adhesion_flag = 0;
    detaching_delta = 0;
    detaching_flag = 0;
    detaching_force = -(5. / 9.) * fc;
    yielding_flag = 0;
  }
  double f = 0.0, df = 0.0;
  bool loaded = true;
  if (detaching_flag == 1) {
    if (delta >= detaching_delta) {
      detaching_flag = 0;
      delta_old = detaching_delta;
      force_old = detaching_force;
    } else {
      loaded = false;
    }
  }
  if (loaded) {
    const double dn = delta - delta_old;
    if (delta >= delta_max) {
      delta_max = delta;
      const double fl = calculate_fl(force_old, fc, 0);
      const double a = calculate_a(fl, e, reff, delta, gamma_s);
      if (yielding_flag == 0 && a >= a_yield) yielding_flag = 1;
      if (plastic_from_start == 1 || yielding_flag == 1) {
        df = plastic_differential(a_yield, e, fl, fc, yield_stress, reff) * dn;
        f = force_old + df;
      } else {
        f = elastic_step(force_old, fc, adhesion_flag, e, reff, delta, dn, gamma_s, df);
      }
    } else if (yielding_flag == 0) {
      f = elastic_step(force_old, fc, adhesion_flag, e, reff, delta, dn, gamma_s, df);
    } else {
      const double fl_max = calculate_fl(force_max, fc, 0);
      reff = reff * fl_max / (force_max + std::sqrt(4 * fc * fl_max));
      fc = (3. / 2.) * M_PI * gamma_s * reff;
      f = elastic_step(force_old, fc, adhesion_flag, e, reff, delta, dn, gamma_s, df);
    }
    if (gamma_s == 0 && f < 0) {  // no cohesion
      f = 0;
      detaching_flag = 1;
      detaching_delta = delta;
      detaching_force = 0;
    }
    if (f < -fc) {
      adhesion_flag = 1 - adhesion_flag;
      f = elastic_step(force_old, fc, adhesion_flag, e, reff, delta, dn, gamma_s, df);
    }
    if (adhesion_flag == 1 && f + 3 * df >= -(5. / 9.) * fc) {
      f = 0;
      detaching_flag = 1;
      detaching_delta = delta_old;
      detaching_force = force_old;
    }
  }
  force_max = (f > force_max) ? f : force_max;
  history[0] = virgin_loading_flag;
  history[1] = delta;
  history[2] = delta_max;
  history[3] = f;
  history[4] = force_max;
  history[5] = adhesion_flag;
  history[6] = detaching_delta;
  history[7] = detaching_flag;
  history[8] = detaching_force;
  history[9] = yielding_flag;
  // k_n: LIGGGHTS's law sets none (rolling cdt is refused with it).
  return {f, k_t, gammat, 0.0};
}

}  // namespace granstack::refsim::detail
