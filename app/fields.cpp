// granstack fields: every spec field (model/spec_fields.hpp) with its type, default and
// meaning; --markdown gives the reference table the documentation site shows.
#include "commands.hpp"

#include <granstack/model/spec_fields.hpp>

#include <fmt/format.h>

#include <memory>

namespace granstack::app {

namespace {

int list_fields(bool markdown) {
  if (markdown) {
    fmt::print("{}", model::spec_fields_markdown());
    return kOk;
  }
  for (const auto& f : model::spec_fields()) {
    fmt::print("{:<24} {}{}\n", f.name, f.type, f.sweepable() ? ", sweepable" : "");
    fmt::print("{:<24} {} [default: {}]\n", "", f.help, f.default_text);
  }
  return kOk;
}

}  // namespace

Command add_fields(CLI::App& app) {
  auto markdown = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("fields", "List every spec field: its type, default and meaning (spec files, generate's flags)");
  cmd->add_flag("--markdown", *markdown, "As the reference's markdown table");
  return {cmd, [markdown] { return list_fields(*markdown); }};
}

}  // namespace granstack::app
