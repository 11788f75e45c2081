#pragma once
// Input-deck templates: text with {{name}} placeholders. Rendering fails loudly on a
// placeholder it has no value for, so a user's template cannot silently lose a setting.
#include <map>
#include <string>
#include <string_view>

namespace granstack::generator {

using TemplateVars = std::map<std::string, std::string, std::less<>>;

// Throws std::runtime_error naming the placeholder and its line (`source` names the template).
std::string render_template(std::string_view text, const TemplateVars& vars, std::string_view source);

// Whether the template uses the placeholder {{name}} (spaces allowed inside the braces).
bool uses_placeholder(std::string_view text, std::string_view name);

// The default deck template, templates/in.granstack.tmpl, embedded at build time.
std::string_view default_deck_template();

}  // namespace granstack::generator
