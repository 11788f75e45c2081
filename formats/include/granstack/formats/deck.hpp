#pragma once
// What a case's input deck will make LIGGGHTS do, read back from the deck itself: its time
// step and step count must be the manifest's, which every reader of the results relies on.
#include <granstack/formats/manifest.hpp>

#include <string>

namespace granstack::formats {

// Throws FormatError (naming the deck, the line and both values) when a `timestep` line of the
// deck differs from the manifest's dt, or its last `run` from the manifest's steps, or either
// is missing.
void check_deck_matches_manifest(const std::string& case_dir, const Manifest& manifest);

}  // namespace granstack::formats
