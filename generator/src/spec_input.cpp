#include <granstack/formats/files.hpp>
#include <granstack/formats/line_reader.hpp>
#include <granstack/generator/spec_input.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <toml++/toml.h>

namespace granstack::generator {

using model::SpecError;
using model::SpecIssue;

const std::vector<std::string>& spec_fields() {
  static const std::vector<std::string> fields{
      "blocks",        "rows",          "top_columns",     "bottom_radius",     "radius_ratio",
      "materials",     "restitution",   "friction",        "striker_speed",     "striker_radius_ratio", "striker_material", "bottom",
      "sides",         "wall_material", "gravity",         "dt",                "duration",
      "dump_every",    "series_every",  "dump_format",     "dump_files",        "restitution_pairs",
      "friction_pairs", "custom_materials", "geometry", "panels", "impact_panel", "separator", "matrix_material",
      "normal_model", "tangential_model", "rolling_model", "rolling_friction", "rolling_friction_pairs",
      "characteristic_velocity"};
  return fields;
}

bool is_sweepable(const std::string& f) {
  return f == "blocks" || f == "rows" || f == "top_columns" || f == "bottom_radius" || f == "restitution" ||
         f == "friction" || f == "striker_speed" || f == "rolling_friction";
}

namespace {
bool is_pairs_field(const std::string& f) {
  return f == "restitution_pairs" || f == "friction_pairs" || f == "rolling_friction_pairs";
}
}  // namespace

std::vector<std::string> split_list(const std::string& value) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(value);
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    out.push_back(b == std::string::npos ? std::string() : item.substr(b, e - b + 1));
  }
  if (!value.empty() && value.back() == ',') out.emplace_back();
  return out;
}

namespace {

// A TOML scalar as text that parses back to exactly the same value.
bool scalar_text(const toml::node& node, std::string& out) {
  if (auto v = node.as_integer()) {
    out = fmt::format("{}", v->get());
  } else if (auto f = node.as_floating_point()) {
    out = fmt::format("{}", f->get());
  } else if (auto s = node.as_string()) {
    out = s->get();
  } else if (auto b = node.as_boolean()) {
    out = b->get() ? "true" : "false";
  } else {
    return false;
  }
  return true;
}

std::string where(const toml::node& node) {
  const auto& src = node.source();
  return fmt::format("line {}", src.begin.line);
}

}  // namespace

RawSpec parse_spec_toml(std::string_view text, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(fmt::format("{}:{}:{}: TOML syntax error: {}", source, e.source().begin.line,
                                         e.source().begin.column, e.description()));
  }
  RawSpec raw;
  std::vector<SpecIssue> issues;
  for (const auto& [key_, node] : root) {
    const std::string key(key_.str());
    const auto field_known = std::find(spec_fields().begin(), spec_fields().end(), key) != spec_fields().end();
    if (!field_known) {
      issues.push_back({key, fmt::format("unknown field in {} ({}); known fields: {}", source, where(node),
                                         fmt::join(spec_fields(), ", "))});
      continue;
    }
    auto& tokens = raw[key];
    if (is_pairs_field(key)) {
      const auto* t = node.as_table();
      if (t == nullptr) {
        issues.push_back({key, "must be a table of \"material_a:material_b\" = value"});
        continue;
      }
      for (const auto& [pair, v] : *t) {
        std::string value;
        if (!v.is_number() || !scalar_text(v, value)) {
          issues.push_back({fmt::format("{}.\"{}\"", key, pair.str()), "must be a number"});
          continue;
        }
        tokens.push_back(fmt::format("{}={}", pair.str(), value));
      }
    } else if (key == "custom_materials") {
      const auto* t = node.as_table();
      if (t == nullptr) {
        issues.push_back({key, "must hold tables [custom_materials.NAME] with density, youngs_modulus, poisson_ratio"});
        continue;
      }
      for (const auto& [name, m] : *t) {
        const auto* mt = m.as_table();
        std::string rho, y, nu;
        const auto field = fmt::format("custom_materials.{}", name.str());
        if (mt == nullptr) {
          issues.push_back({field, "must be a table with density, youngs_modulus, poisson_ratio"});
          continue;
        }
        for (const auto& [k, v] : *mt) {
          (void)v;
          if (k != "density" && k != "youngs_modulus" && k != "poisson_ratio") {
            issues.push_back({field + "." + std::string(k.str()),
                              "unknown field (known: density, youngs_modulus, poisson_ratio)"});
          }
        }
        auto num = [&](const char* k, std::string& out) {
          const auto* v = mt->get(k);
          if (v == nullptr || !v->is_number() || !scalar_text(*v, out)) {
            issues.push_back({field + "." + k, "missing, or not a number"});
          }
        };
        num("density", rho);
        num("youngs_modulus", y);
        num("poisson_ratio", nu);
        tokens.push_back(fmt::format("{}:{}:{}:{}", name.str(), rho, y, nu));
      }
    } else if (const auto* arr = node.as_array()) {
      for (const auto& item : *arr) {
        std::string value;
        if (!scalar_text(item, value)) {
          issues.push_back({key, "list items must be numbers or strings"});
          break;
        }
        tokens.push_back(value);
      }
      if (arr->empty()) issues.push_back({key, "an empty list gives no value"});
    } else {
      std::string value;
      if (!scalar_text(node, value)) {
        issues.push_back({key, "must be a number, a string, or a list of them"});
      } else {
        tokens.push_back(value);
      }
    }
  }
  if (!issues.empty()) throw SpecError(std::move(issues));
  return raw;
}

RawSpec read_spec_file(const std::string& path) { return parse_spec_toml(formats::read_file(path), path); }

namespace {

class Parser {
 public:
  explicit Parser(std::vector<SpecIssue>& issues) : issues_(issues) {}

  bool number(const std::string& field, const std::string& token, double& out) {
    if (formats::parse_double(token, out) && std::isfinite(out)) return true;
    bad(field, fmt::format("'{}' is not a number", token));
    return false;
  }
  bool whole(const std::string& field, const std::string& token, int& out) {
    double v = 0.0;
    if (!number(field, token, v)) return false;
    if (v != std::floor(v) || std::fabs(v) > 1e9) {
      bad(field, fmt::format("'{}' is not a whole number", token));
      return false;
    }
    out = static_cast<int>(v);
    return true;
  }
  void bad(const std::string& field, std::string message) { issues_.push_back({field, std::move(message)}); }

 private:
  std::vector<SpecIssue>& issues_;
};

bool is_whole_field(const std::string& f) { return f == "blocks" || f == "rows" || f == "top_columns"; }

void apply_axis_value(model::StackSpec& s, const std::string& field, double v) {
  if (field == "blocks") s.blocks = static_cast<int>(v);
  else if (field == "rows") s.rows = static_cast<int>(v);
  else if (field == "top_columns") s.top_columns = static_cast<int>(v);
  else if (field == "bottom_radius") s.bottom_radius = v;
  else if (field == "restitution") s.restitution.value = v;
  else if (field == "friction") s.friction.value = v;
  else if (field == "striker_speed") s.striker_speed = v;
  else if (field == "rolling_friction") s.rolling_friction.value = v;
}

std::string short_key(const std::string& field) {
  if (field == "blocks") return "nb";
  if (field == "rows") return "rows";
  if (field == "top_columns") return "cols";
  if (field == "bottom_radius") return "r";
  if (field == "restitution") return "e";
  if (field == "friction") return "mu";
  if (field == "rolling_friction") return "mur";
  return "v";  // striker_speed
}

void parse_contact_model(model::StackSpec& s, const std::string& field, const std::string& t, Parser& p) {
  if (field == "normal_model") {
    if (auto m = model::parse_normal_model(t)) s.normal_model = *m;
    else p.bad(field, fmt::format("'{}' is not 'hertz' or 'hooke'", t));
  } else if (field == "tangential_model") {
    if (auto m = model::parse_tangential_model(t)) s.tangential_model = *m;
    else p.bad(field, fmt::format("'{}' is not 'history' or 'no_history'", t));
  } else if (auto m = model::parse_rolling_model(t)) {
    s.rolling_model = *m;
  } else {
    p.bad(field, fmt::format("'{}' is not 'off' or 'epsd2'", t));
  }
}

}  // namespace

Sweep build_sweep(const RawSpec& raw) {
  std::vector<SpecIssue> issues;
  Parser p(issues);
  Sweep sweep;
  auto& s = sweep.base;
  for (const auto& [field, tokens] : raw) {
    if (std::find(spec_fields().begin(), spec_fields().end(), field) == spec_fields().end()) {
      p.bad(field, fmt::format("unknown field; known fields: {}", fmt::join(spec_fields(), ", ")));
      continue;
    }
    const bool repeatable = is_pairs_field(field) || field == "custom_materials";
    if ((tokens.empty() && !repeatable) || std::find(tokens.begin(), tokens.end(), std::string()) != tokens.end()) {
      p.bad(field, "an empty value: give a value (leave the field or flag out for its default)");
      continue;
    }
    auto single = [&]() -> const std::string* {
      if (tokens.size() == 1) return &tokens.front();
      p.bad(field, fmt::format("takes one value, {} given", tokens.size()));
      return nullptr;
    };
    auto optional_auto = [&](auto& target, bool whole) {
      const auto* t = single();
      if (t == nullptr || *t == "auto") return;
      if (whole) {
        int v = 0;
        if (p.whole(field, *t, v)) target = v;
      } else {
        double v = 0.0;
        if (p.number(field, *t, v)) target = v;
      }
    };
    if (is_sweepable(field)) {
      SweepAxis axis{field, {}};
      for (const auto& t : tokens) {
        double v = 0.0;
        if (is_whole_field(field)) {
          int w = 0;
          if (!p.whole(field, t, w)) continue;
          v = w;
        } else if (!p.number(field, t, v)) {
          continue;
        }
        if (std::find(axis.values.begin(), axis.values.end(), v) != axis.values.end()) {
          p.bad(field, fmt::format("the value {} is listed twice", t));
          continue;
        }
        axis.values.push_back(v);
      }
      if (axis.values.empty()) continue;
      apply_axis_value(s, field, axis.values.front());
      if (axis.values.size() > 1) sweep.axes.push_back(std::move(axis));
    } else if (field == "radius_ratio") {
      if (const auto* t = single()) p.whole(field, *t, s.radius_ratio);
    } else if (field == "materials") {
      s.materials = tokens;
    } else if (field == "geometry") {
      if (const auto* t = single()) {
        auto g = model::parse_geometry(*t);
        if (!g) p.bad(field, fmt::format("'{}' is not 'strip', 'nested3d' or 'panels'", *t));
        else s.geometry = *g;
      }
    } else if (field == "panels") {
      if (const auto* t = single()) p.whole(field, *t, s.panels);
    } else if (field == "impact_panel") {
      if (const auto* t = single()) {
        if (*t == "all") {
          s.impact_panel = model::kAllPanels;
        } else if (p.whole(field, *t, s.impact_panel) && s.impact_panel < 1) {
          // -1 and 0 are the model's codes for 'all' and the centre one: never a user's number.
          p.bad(field, fmt::format("{} is not a panel: give 1..panels (1 = smallest y), or 'all' (a striker on every "
                                   "panel); leave it out for the centre one", *t));
        }
      }
    } else if (field == "separator") {
      if (const auto* t = single()) {
        auto sep = model::parse_separator(*t);
        if (!sep) p.bad(field, fmt::format("'{}' is not 'matrix', 'walls' or 'none'", *t));
        else s.separator = *sep;
      }
    } else if (field == "matrix_material") {
      if (const auto* t = single()) s.matrix_material = *t;
    } else if (field == "bottom" || field == "sides") {
      if (const auto* t = single()) {
        auto b = model::parse_boundary(*t);
        if (!b) p.bad(field, fmt::format("'{}' is not 'free' or 'wall'", *t));
        else (field == "bottom" ? s.bottom : s.sides) = *b;
      }
    } else if (field == "wall_material") {
      if (const auto* t = single()) s.wall_material = *t;
    } else if (field == "striker_material") {
      if (const auto* t = single()) s.striker_material = *t;
    } else if (field == "striker_radius_ratio") {
      if (const auto* t = single()) p.number(field, *t, s.striker_radius_ratio);
    } else if (field == "gravity") {
      if (const auto* t = single()) {
        if (*t == "true") s.gravity = 9.80665;  // standard gravity
        else if (*t == "false") s.gravity = 0.0;
        else p.number(field, *t, s.gravity);
      }
    } else if (field == "dt") {
      optional_auto(s.dt, false);
    } else if (field == "duration") {
      optional_auto(s.duration, false);
    } else if (field == "dump_every") {
      optional_auto(s.dump_every, true);
    } else if (field == "series_every") {
      optional_auto(s.series_every, true);
    } else if (field == "dump_format") {
      if (const auto* t = single()) {
        auto f = model::parse_dump_format(*t);
        if (!f) p.bad(field, fmt::format("'{}' is not 'text' or 'binary'", *t));
        else s.dump_format = *f;
      }
    } else if (field == "dump_files") {
      if (const auto* t = single()) {
        auto f = model::parse_dump_files(*t);
        if (!f) p.bad(field, fmt::format("'{}' is not 'single', 'per_step' or 'per_rank'", *t));
        else s.dump_files = *f;
      }
    } else if (field == "normal_model" || field == "tangential_model" || field == "rolling_model") {
      if (const auto* t = single()) parse_contact_model(s, field, *t, p);
    } else if (field == "characteristic_velocity") {
      optional_auto(s.characteristic_velocity, false);
    } else if (is_pairs_field(field)) {
      auto& table = field == "restitution_pairs" ? s.restitution : field == "friction_pairs" ? s.friction : s.rolling_friction;
      for (const auto& t : tokens) {
        const auto colon = t.find(':');
        const auto eq = t.find('=');
        double v = 0.0;
        if (colon == std::string::npos || eq == std::string::npos || eq < colon) {
          p.bad(field, fmt::format("'{}' is not MATERIAL_A:MATERIAL_B=VALUE", t));
        } else if (p.number(field, t.substr(eq + 1), v)) {
          table.set(t.substr(0, colon), t.substr(colon + 1, eq - colon - 1), v);
        }
      }
    } else if (field == "custom_materials") {
      for (const auto& t : tokens) {
        const auto parts = split_list([&] {
          std::string c = t;
          std::replace(c.begin(), c.end(), ':', ',');
          return c;
        }());
        model::Material m;
        if (parts.size() != 4) {
          p.bad(field, fmt::format("'{}' is not NAME:DENSITY:YOUNGS_MODULUS:POISSON_RATIO", t));
          continue;
        }
        m.name = parts[0];
        const auto f = fmt::format("custom_materials.{}", m.name);
        if (p.number(f + ".density", parts[1], m.density) && p.number(f + ".youngs_modulus", parts[2], m.youngs_modulus) &&
            p.number(f + ".poisson_ratio", parts[3], m.poisson_ratio)) {
          s.custom_materials.push_back(m);
        }
      }
    }
  }
  if (!issues.empty()) throw SpecError(std::move(issues));
  // Case names list the swept fields in the documented order (blocks first, then e, mu, ...).
  auto rank = [](const SweepAxis& a) {
    return std::find(spec_fields().begin(), spec_fields().end(), a.field) - spec_fields().begin();
  };
  std::sort(sweep.axes.begin(), sweep.axes.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
  // Checks that do not depend on the swept values are reported once, here.
  if (sweep.axes.empty()) model::require_valid(s);
  return sweep;
}

std::vector<CaseSpec> expand(const Sweep& sweep) {
  std::vector<CaseSpec> cases;
  std::vector<std::size_t> index(sweep.axes.size(), 0);
  for (;;) {
    CaseSpec c{"", sweep.base};
    std::vector<std::string> parts;
    for (std::size_t a = 0; a < sweep.axes.size(); ++a) {
      const auto& axis = sweep.axes[a];
      const double v = axis.values[index[a]];
      apply_axis_value(c.spec, axis.field, v);
      parts.push_back(fmt::format("{}{}", short_key(axis.field), v));
    }
    c.name = parts.empty() ? "case" : fmt::format("{}", fmt::join(parts, "_"));
    auto issues = model::validate(c.spec);
    if (!issues.empty()) {
      for (auto& i : issues) i.message += fmt::format(" (in the sweep case {})", c.name);
      throw SpecError(std::move(issues));
    }
    cases.push_back(std::move(c));
    // Odometer increment, last axis fastest.
    std::size_t a = sweep.axes.size();
    while (a > 0) {
      --a;
      if (++index[a] < sweep.axes[a].values.size()) break;
      index[a] = 0;
      if (a == 0) return cases;
    }
    if (sweep.axes.empty()) return cases;
  }
}

}  // namespace granstack::generator
