// The contact sub-models' table: each normal, tangential and rolling model's keyword, what the
// spec's help and reference say of it, and why LAMMPS cannot run it (where it cannot). The
// formulas are contact.cpp's; refsim's kernels are refsim/src/contact_models/.
#include <granstack/model/contact.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <type_traits>

namespace granstack::model {

namespace {

// In each enum's order (the normal models' rows are their laws', contact.cpp).
constexpr std::array<SubModelInfo, kTangentialModelCount> kTangential{{
    {"history", "history (a spring limited by Coulomb)", "", "", "", "mindlin"},
    {"no_history", "no_history (viscous)", "`no_history`: viscous, capped at `mu F_n`; no tangential force at all at e = 1",
     "tangential_model = 'no_history' is not mapped onto LAMMPS (its linear_nohistory damps with a constant, "
     "LIGGGHTS's with the Hertz overlap); use tangential_model = 'history'"},
    {"mindlin_rescale", "mindlin_rescale (LAMMPS's: history's spring, rescaled as the contact unloads)",
     "`mindlin_rescale` (LAMMPS's, not LIGGGHTS's): history's Mindlin spring, its displacement scaled down with the "
     "contact radius as the contact unloads ([physics](../physics.md#other-contact-models))",
     "", "tangential_model = 'mindlin_rescale' is LAMMPS's (pair_style granular); LIGGGHTS 3.8 has no counterpart: run "
     "it on LAMMPS or on refsim by LAMMPS's rules (run --engine lammps, run --engine refsim --contact-rules lammps, "
     "validate --engines lammps,refsim), or use tangential_model = 'history'",
     "mindlin_rescale"},
}};
constexpr std::array<SubModelInfo, kRollingModelCount> kRolling{{
    {"off", "off", "", ""},
    {"epsd2", "epsd2 (an elastic-plastic torque spring)", "`epsd2`: a torque spring capped at `mu_r R* F_n`",
     "rolling_model = 'epsd2' has no counterpart in this LAMMPS (its rolling sds is a spring without LIGGGHTS's "
     "plastic cap on R* |F_n|); use rolling_model = 'off'"},
    {"cdt", "cdt (a constant directional torque)",
     "`cdt`: a torque `mu_r R* k_n delta` against the relative rotation, whatever its speed (no spring)",
     "rolling_model = 'cdt' has no counterpart in LAMMPS (its rolling sds is a spring); use rolling_model = 'off'"},
}};

template <typename Model>
std::size_t count() {
  if constexpr (std::is_same_v<Model, NormalModel>) return kNormalModelCount;
  if constexpr (std::is_same_v<Model, TangentialModel>) return kTangential.size();
  if constexpr (std::is_same_v<Model, RollingModel>) return kRolling.size();
}

template <typename Model>
std::optional<Model> parse(std::string_view s) {
  for (std::size_t k = 0; k < count<Model>(); ++k) {
    if (info(static_cast<Model>(k)).keyword == s) return static_cast<Model>(k);
  }
  return std::nullopt;
}

}  // namespace

const SubModelInfo& info(NormalModel m) { return normal_law(m).info; }
const SubModelInfo& info(TangentialModel m) { return kTangential.at(static_cast<std::size_t>(m)); }
const SubModelInfo& info(RollingModel m) { return kRolling.at(static_cast<std::size_t>(m)); }

template <typename Model>
std::vector<Model> all_models() {
  std::vector<Model> out;
  for (std::size_t k = 0; k < count<Model>(); ++k) out.push_back(static_cast<Model>(k));
  return out;
}

template <typename Model>
std::string keyword_list(bool beyond_default) {
  const std::size_t rows = count<Model>();
  const std::size_t first = beyond_default ? 1 : 0;
  const std::string quote = beyond_default ? "" : "'";
  std::string out;
  for (std::size_t k = first; k < rows; ++k) {
    if (k > first) out += k + 1 == rows ? " or " : ", ";
    out += quote;
    out += info(static_cast<Model>(k)).keyword;
    out += quote;
  }
  return out;
}

template std::vector<NormalModel> all_models<NormalModel>();
template std::vector<TangentialModel> all_models<TangentialModel>();
template std::vector<RollingModel> all_models<RollingModel>();
template std::string keyword_list<NormalModel>(bool);
template std::string keyword_list<TangentialModel>(bool);
template std::string keyword_list<RollingModel>(bool);

std::string_view to_string(NormalModel m) { return info(m).keyword; }
std::string_view to_string(TangentialModel m) { return info(m).keyword; }
std::string_view to_string(RollingModel m) { return info(m).keyword; }

namespace {
// The first of m's sub-models' rows that has a refusal in `column`.
std::string_view first_refusal(const ContactModel& m, std::string_view SubModelInfo::*column) {
  for (const auto* row : {&info(m.normal), &info(m.tangential), &info(m.rolling)}) {
    if (!(row->*column).empty()) return row->*column;
  }
  return {};
}
}  // namespace

std::string_view lammps_refusal(const ContactModel& m) { return first_refusal(m, &SubModelInfo::lammps_refusal); }
std::string_view liggghts_refusal(const ContactModel& m) { return first_refusal(m, &SubModelInfo::liggghts_refusal); }
std::string_view refsim_liggghts_refusal(const ContactModel& m) {
  ContactModel probe = m;
  probe.normal = NormalModel::hertz;
  return liggghts_refusal(probe);
}
std::optional<NormalModel> parse_normal_model(std::string_view s) { return parse<NormalModel>(s); }
std::optional<TangentialModel> parse_tangential_model(std::string_view s) { return parse<TangentialModel>(s); }
std::optional<RollingModel> parse_rolling_model(std::string_view s) { return parse<RollingModel>(s); }

}  // namespace granstack::model
