#pragma once
// A LIGGGHTS or LAMMPS run held to its case (formats/deck_rules.hpp): the deck's own lines before
// the run starts, and what the program executed, from its log, after it ends.
#include <granstack/formats/case.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace granstack::runner {

// Why the deck `deck` (its text, from the template `source`) cannot run the case, judged from its
// own lines against `reference` (the deck granstack's template gives); "" when nothing is wrong.
std::string deck_refusal(const formats::Case& c, std::string_view deck, const std::string& name,
                         const std::string& source, std::string_view reference);

// What the run wrote to its log (files.log), followed from files.deck and held to `reference`:
// record["executed"] says what ran (the commands counted, the input files read with their
// SHA-256, the log's XXH3-128, the spec's additions that ran). Returns why the run cannot be
// taken as the case's ("" when it can).
std::string hold_run(const formats::Case& c, const formats::CaseFiles& files, std::string_view reference,
                     const std::string& source, nlohmann::json& record);

}  // namespace granstack::runner
