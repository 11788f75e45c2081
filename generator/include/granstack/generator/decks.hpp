#pragma once
// The input decks of a case: LIGGGHTS's (granstack's template, liggghts_deck.cpp) and LAMMPS's
// (lammps_deck.cpp), from the same stack, resolution and files.
#include <granstack/formats/manifest.hpp>
#include <granstack/generator/template.hpp>
#include <granstack/model/lammps.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>

#include <string>
#include <string_view>

namespace granstack::generator {

// The variables the deck template is rendered with.
TemplateVars deck_variables(const model::Stack& stack, const model::Resolution& res, const formats::CaseFiles& files,
                            const std::string& case_name);
// The deck granstack's own template gives for a case, from its manifest alone (with the
// granstack version and commit the manifest records). generate writes exactly this unless
// given --template; refsim runs only cases whose deck is this, so the two engines cannot be
// handed different physics.
std::string default_deck(const formats::Manifest& manifest);
// Whether the deck in `case_dir` is exactly default_deck(manifest).
bool has_default_deck(const std::string& case_dir, const formats::Manifest& manifest);
// The LAMMPS deck of a case (`granstack run --engine lammps` writes it as in.lammps): `tmpl`
// (default_lammps_template(), templates/in.lammps.tmpl, or a user's; `source` names it in
// errors) rendered for the case's stack, resolution and files, its contacts mapped as
// model/lammps.hpp says for a LAMMPS of the family `rules`. The caller checks
// model::lammps_unmappable first.
std::string_view default_lammps_template();
std::string lammps_deck(const model::Stack& stack, const model::Resolution& res, const formats::CaseFiles& files,
                        const std::string& case_name, std::string_view tmpl, std::string_view source,
                        const model::LammpsRules& rules);

}  // namespace granstack::generator
