#pragma once
// The study's output-fraction table: output fraction against N_B, one column per group of
// cases that differ only in N_B (e.g. per restitution), each with its decay fit.
#include <granstack/postproc/fit.hpp>
#include <granstack/postproc/reduce.hpp>

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

namespace granstack::postproc {

struct TableGroup {
  std::string label;                         // the fields that tell the groups apart, e.g. "e=0.9"
  double restitution = 1.0;                  // for the study's alpha * e
  std::vector<const CaseReduction*> cases;   // by increasing N_B
  std::optional<DecayFit> fit;
  std::string fit_note;                      // why there is no fit
};

struct OutputTable {
  std::vector<TableGroup> groups;
  std::vector<int> blocks;                   // every N_B present, increasing
};

// Groups cases by every spec field but `blocks`. Throws std::invalid_argument when one group
// has two cases with the same N_B (the table would be ambiguous).
OutputTable build_table(const std::vector<CaseReduction>& reductions);

std::string table_markdown(const OutputTable& t);
std::string table_csv(const OutputTable& t);      // one row per case
std::string fits_csv(const OutputTable& t);       // one row per group
nlohmann::json table_json(const OutputTable& t);

}  // namespace granstack::postproc
