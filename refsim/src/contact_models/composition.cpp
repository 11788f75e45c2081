// The one composition of the sub-models (sub_models.hpp), for sphere-sphere contacts
// (contacts.cpp) and walls (walls.cpp), by LIGGGHTS's rules and by LAMMPS's; and the choice of
// sub-models each engine's rules make of the spec's model.
#include "sub_models.hpp"

#include <fmt/format.h>

#include <array>
#include <iterator>
#include <stdexcept>
#include <string>

namespace granstack::refsim::detail {

// The normal models' kernels (each its file in this folder) and their per-pair records.
// LIGGGHTS's hertz with restitution damping (normal_model_hertz.h).
Normal hertz_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool tangential_damping,
                    double* history);
// LIGGGHTS's hooke (normal_model_hooke.h): k_n and gamma_n of the pair (of its R* and m*), k_t = k_n.
Normal hooke_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool tangential_damping,
                    double* history);
void hooke_record(const ModelConstants& k, double radi, double reff, double meff, ModelRecord& r);
// Thornton (1997) (model::thornton_force): history[0] the largest overlap; k_t = 8 G* sqrt(R* d).
Normal thornton_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool tangential_damping,
                       double* history);
void thornton_record(const ModelConstants& k, double radi, double reff, double meff, ModelRecord& r);
// LIGGGHTS's thornton_ning (normal_model_thornton_ning.h), its kThorntonNingHistory values in its order.
Normal thornton_ning_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c,
                            bool tangential_damping, double* history);
void thornton_ning_record(const ModelConstants& k, double radi, double reff, double meff, ModelRecord& r);
// LAMMPS's hertz/material with tsuji damping (pair_granular, fix wall/gran granular), and the
// stiffness and damping of its mindlin spring; tsuji's coefficient alpha(e') of the type pair's
// restitution and mindlin's eta_t / eta_n.
Normal tsuji_normal(const PairConstants& k, const ModelRecord& r, const ContactPoint& c, bool tangential_damping,
                    double* history);
void tsuji_record(const ModelConstants& k, double radi, double reff, double meff, ModelRecord& r);

namespace {
// A kernel and how many history values it keeps per contact.
template <typename Kernel>
struct Row {
  Kernel kernel;
  std::size_t history;
};
// The rolling models' kernels, by model::RollingModel (none for off): a new rolling model is its
// file in this folder and its line here.
constexpr Row<RollingTorque> kRolling[] = {
    {nullptr, 0},        // off
    {rolling_epsd2, 3},  // epsd2: the torque spring's history
    {rolling_cdt, 0},    // cdt
};
// Each frame's tangential kernels, by model::TangentialModel; none where that engine has no
// counterpart (its row's refusal in model/src/contact_models.cpp says why). A new tangential
// model is its file in this folder and its line in each table.
constexpr Row<TangentialForce> kLiggghtsTangential[] = {
    {tangential_history, kTangentialHistory},  // history
    {tangential_no_history, 0},                // no_history
    {nullptr, 0},                              // mindlin_rescale: LAMMPS's
};
constexpr Row<TangentialForce> kLammpsTangential[] = {
    {tangential_mindlin, kTangentialHistory},                  // history: LAMMPS's Hertz-Mindlin
    {nullptr, 0},                                              // no_history: not mapped
    {tangential_mindlin_rescale, kMindlinRescaleHistory},      // mindlin_rescale
};
// The normal models' kernels by LIGGGHTS's rules, by model::NormalModel (one row per model, the
// compiler checks the count): the force, the per-pair record, the history it keeps, the
// contact's energy where the law keeps it with its history (model::NormalLaw::series_energy), and
// whether, undamped, its force and history are functions of the positions alone (unchanged
// positions give unchanged bits: positional_force). A new normal model is its file in this folder
// and its row here; none where refsim has no kernel for it.
struct NormalRow {
  NormalForce force;
  NormalRecord record;
  std::size_t history;
  NormalEnergy energy;
  bool positional;
};
constexpr auto kLiggghtsNormal = std::to_array<NormalRow>({
    {hertz_normal, nullptr, 0, nullptr, true},                                           // hertz
    {hooke_normal, hooke_record, 0, nullptr, true},                                      // hooke
    {thornton_normal, thornton_record, 1, thornton_energy, true},                        // thornton: d_max
    {thornton_ning_normal, thornton_ning_record, kThorntonNingHistory, nullptr, false},  // thornton_ning: incremental
});
static_assert(kLiggghtsNormal.size() == model::kNormalModelCount, "one row per model::NormalModel");
// LAMMPS's rules run hertz/material with tsuji damping for the spec's hertz, nothing else.
constexpr NormalRow kLammpsNormal{tsuji_normal, tsuji_record, 0, nullptr, false};

const NormalRow& normal_row(const SubModels& s) {
  return s.frame == Frame::lammps ? kLammpsNormal : kLiggghtsNormal[static_cast<std::size_t>(s.normal)];
}

const Row<TangentialForce>& tangential_row(Frame f, model::TangentialModel m) {
  static constexpr Row<TangentialForce> none{nullptr, 0};
  const auto k = static_cast<std::size_t>(m);
  if (f == Frame::lammps) return k < std::size(kLammpsTangential) ? kLammpsTangential[k] : none;
  return k < std::size(kLiggghtsTangential) ? kLiggghtsTangential[k] : none;
}

// The choice `s` runs: every sub-model has its kernel in the frame (a table short of one is a
// defect of this file, not of the spec).
SubModels checked(const SubModels& s) {
  if (tangential_row(s.frame, s.tangential).kernel == nullptr) {
    throw std::logic_error(fmt::format("refsim has no kernel for tangential_model = '{}' by {}'s rules "
                                       "(contact_models/composition.cpp)",
                                       model::to_string(s.tangential), s.frame == Frame::lammps ? "LAMMPS" : "LIGGGHTS"));
  }
  if (static_cast<std::size_t>(s.rolling) >= std::size(kRolling)) {
    throw std::logic_error(fmt::format("refsim has no kernel for rolling_model = '{}' (contact_models/composition.cpp)",
                                       model::to_string(s.rolling)));
  }
  if (history_layout(s).size > kMaxHistory) throw std::logic_error("refsim: a contact's history exceeds kMaxHistory");
  return s;
}
}  // namespace

HistoryLayout history_layout(const SubModels& s) {
  HistoryLayout h;
  h.tangential = 0;
  h.rolling = tangential_row(s.frame, s.tangential).history;
  h.normal = h.rolling + kRolling[static_cast<std::size_t>(s.rolling)].history;
  h.size = h.normal + normal_row(s).history;
  return h;
}

bool has_contact_energy(const SubModels& m) { return normal_row(m).energy != nullptr; }

bool positional_force(const SubModels& m) { return normal_row(m).positional; }

ContactEnergy contact_energy(const SubModels& m, const ModelRecord& mr, double overlap, const double* history) {
  const NormalEnergy energy = normal_row(m).energy;
  return energy ? energy(mr, overlap, history + history_layout(m).normal) : ContactEnergy{};
}

ModelRecord model_record(const SubModels& m, const ModelConstants& k, double radi, double reff, double meff) {
  ModelRecord r;
  r.rolling_friction = m.rolling == model::RollingModel::off ? 0.0 : k.rolling_friction;
  if (const NormalRecord record = normal_row(m).record) record(k, radi, reff, meff, r);
  return r;
}

SubModels liggghts_rules(const model::ContactModel& m) {
  if (const auto why = model::refsim_liggghts_refusal(m); !why.empty()) {
    throw std::invalid_argument("LIGGGHTS's contact rules (--contact-rules liggghts, the default): " + std::string(why));
  }
  SubModels s;
  s.frame = Frame::liggghts;
  s.normal = m.normal;
  s.tangential = m.tangential;
  s.rolling = m.rolling;
  return checked(s);
}

SubModels lammps_rules(const model::ContactModel& m) {
  if (const auto why = model::lammps_refusal(m); !why.empty()) {
    throw std::invalid_argument("--contact-rules lammps: " + std::string(why));
  }
  return checked({Frame::lammps, m.normal, m.tangential, model::RollingModel::off});
}

PairPoint pair_point(Frame f, const PairTable& t, const ContactStep& s, std::size_t p) {
  return f == Frame::lammps ? lammps_pair_point(t, s, p) : liggghts_pair_point(t, s, p);
}

bool wall_touches(Frame f, double wall_position, double position, double radius) {
  return f == Frame::lammps ? lammps_wall_touches(wall_position, position, radius)
                            : liggghts_wall_gap(wall_position, position, radius) <= 0.0;
}

WallPoint wall_point(Frame f, int axis, double wall_position, double position, double radius, double mass,
                     const double v[3], const double w[3]) {
  return f == Frame::lammps ? lammps_wall_point(axis, wall_position, position, radius, mass, v, w)
                            : liggghts_wall_point(axis, wall_position, position, radius, mass, v, w);
}

void wall_force(Frame f, double fn, const double en[3], const double ft[3], double force[3]) {
  if (f == Frame::lammps) {
    lammps_wall_force(fn, en, ft, force);
  } else {
    liggghts_wall_force(fn, en, ft, force);
  }
}

double kept_wall_force(Frame f, double before, double after, double force) {
  return f == Frame::lammps ? force : after - before;
}

ContactPoint pair_contact_point(const PairGeometry& g, const ContactFrame& f, const ContactStep& s) {
  const PairRecord& rec = *g.rec;
  const std::size_t i = g.i, j = g.j, y = s.stride, z = 2 * s.stride;
  ContactPoint c{};
  for (int d = 0; d < 3; ++d) c.en[d] = f.en[d];
  c.vn = f.vn;
  c.reff = rec.reff;
  c.meff = rec.meff;
  c.rolling_reff = rec.radi * rec.radj / (rec.radi + rec.radj);
  c.wr[0] = s.w[i] - s.w[j];
  c.wr[1] = s.w[y + i] - s.w[y + j];
  c.wr[2] = s.w[z + i] - s.w[z + j];
  c.wall = false;
  return c;
}

ContactForces contact(const SubModels& m, const PairConstants& k, const ModelRecord& mr, const ContactPoint& c,
                      double* history, bool update_history, bool tangential_damping, double dt) {
  const HistoryLayout h = history_layout(m);
  ContactForces out;
  out.n = normal_row(m).force(k, mr, c, tangential_damping, history + h.normal);
  tangential_row(m.frame, m.tangential).kernel(history + h.tangential, c, out.n, k.friction, update_history, dt, out.ft);
  const double* en = c.en;
  out.tor[0] = en[1] * out.ft[2] - en[2] * out.ft[1];
  out.tor[1] = en[2] * out.ft[0] - en[0] * out.ft[2];
  out.tor[2] = en[0] * out.ft[1] - en[1] * out.ft[0];
  if (const RollingTorque kernel = kRolling[static_cast<std::size_t>(m.rolling)].kernel) {
    out.rolling = true;
    kernel(history + h.rolling, c, out.n, mr.rolling_friction, update_history, dt, out.rt);
  }
  return out;
}

}  // namespace granstack::refsim::detail
