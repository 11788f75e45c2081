#pragma once
// What a case's input deck will make LIGGGHTS do, read back from the deck itself: its time
// step and step count must be the manifest's, which every reader of the results relies on.
#include <granstack/formats/case.hpp>
#include <granstack/formats/manifest.hpp>

#include <set>
#include <string>
#include <string_view>

namespace granstack::formats {

// Throws FormatError naming the file when the deck or the data file is not what generate
// rendered (its SHA-256 differs from the manifest's `rendered`): the run's physics would be
// labelled with a spec it does not have. Then (naming the deck, the line and both values) when
// a `timestep` line of the deck differs from the manifest's dt, or its last `run` from the
// manifest's steps, or either is missing; or when its pair_style or a wall/gran names another
// contact model than the manifest.
void check_deck_matches_manifest(const Case& c);

// The first half of the above: the deck's and data file's digests alone.
void check_rendered_files(const std::string& case_dir, const Manifest& manifest);

}  // namespace granstack::formats
