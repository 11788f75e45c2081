#include <granstack/generator/template.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace granstack::embedded {
std::string_view deck_template();
}

namespace granstack::generator {

std::string_view default_deck_template() { return embedded::deck_template(); }

namespace {
// A placeholder's name: what stands between its braces, less the spaces around it.
std::string_view placeholder_name(std::string_view inside) {
  while (!inside.empty() && inside.front() == ' ') inside.remove_prefix(1);
  while (!inside.empty() && inside.back() == ' ') inside.remove_suffix(1);
  return inside;
}
}  // namespace

bool uses_placeholder(std::string_view text, std::string_view name) {
  for (auto open = text.find("{{"); open != std::string_view::npos; open = text.find("{{", open + 2)) {
    const auto close = text.find("}}", open + 2);
    if (close == std::string_view::npos) return false;
    if (placeholder_name(text.substr(open + 2, close - open - 2)) == name) return true;
  }
  return false;
}

std::string render_template(std::string_view text, const TemplateVars& vars, std::string_view source) {
  std::string out;
  out.reserve(text.size() * 2);
  std::size_t pos = 0;
  while (pos < text.size()) {
    const auto open = text.find("{{", pos);
    if (open == std::string_view::npos) {
      out.append(text.substr(pos));
      break;
    }
    out.append(text.substr(pos, open - pos));
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(open), '\n');
    const auto close = text.find("}}", open + 2);
    if (close == std::string_view::npos) {
      throw std::runtime_error(fmt::format("{}:{}: '{{{{' without a closing '}}}}'", source, line));
    }
    const auto name = placeholder_name(text.substr(open + 2, close - open - 2));
    const auto it = vars.find(name);
    if (it == vars.end()) {
      std::string known;
      for (const auto& [k, v] : vars) known += (known.empty() ? "" : ", ") + k;
      throw std::runtime_error(
          fmt::format("{}:{}: unknown placeholder '{{{{{}}}}}'; the generator provides: {}", source, line, name, known));
    }
    out.append(it->second);
    pos = close + 2;
  }
  return out;
}

}  // namespace granstack::generator
