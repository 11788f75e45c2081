#include "deck_check.hpp"

#include <granstack/formats/deck_rules.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/executed.hpp>
#include <granstack/formats/files.hpp>

#include <fmt/format.h>

namespace granstack::runner {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
// A deck is held to the one granstack's own template gives for the case, plus what the spec lists.
std::string refusal(const formats::DeckVerdict& v, const std::string& what) {
  return fmt::format("{} (a deck runs what granstack's own template gives for its case, and what the spec's "
                     "deck_additions lists):{}",
                     what, v.summary());
}
}  // namespace

std::string deck_refusal(const formats::Case& c, std::string_view deck, const std::string& name,
                         const std::string& source, std::string_view reference) {
  const auto verdict = formats::hold_literal(c, deck, name, reference);
  return verdict.ok() ? "" : refusal(verdict, fmt::format("{} (from {}) does not run its case as the spec says", name, source));
}

std::string hold_run(const formats::Case& c, const formats::CaseFiles& files, std::string_view reference,
                     const std::string& source, json& record) {
  const fs::path dir(c.dir());
  std::string log;
  try {
    log = formats::read_file(dir / files.log);
  } catch (const std::exception& e) {
    return fmt::format("its log cannot be read to see what it executed: {}", e.what());
  }
  const auto ran = formats::follow_log(dir, files.deck, log);
  const auto verdict = formats::hold_executed(c, ran, reference);
  json inputs = json::object();
  for (const auto& f : ran.files) {
    std::error_code ec;
    if (fs::is_regular_file(dir / f, ec)) inputs[f] = formats::sha256_file((dir / f).string());
  }
  auto& e = record["executed"];
  e = {{"log", files.log}, {"log_xxh3_128", formats::xxh128_content(dir / files.log)}, {"commands", ran.commands.size()},
       {"inputs", inputs}, {"held_to", source}};
  if (!verdict.additions.empty()) e["additions"] = verdict.additions;
  if (verdict.ok()) return "";
  e["problems"] = json::array();
  for (const auto& p : verdict.problems) e["problems"].push_back(p.text());
  return refusal(verdict, fmt::format("the run did not execute its case as the spec says (its log, {}, shows what it ran)",
                                      files.log));
}

}  // namespace granstack::runner
