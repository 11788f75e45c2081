#include <granstack/formats/files.hpp>
#include <granstack/generator/spec_input.hpp>
#include <granstack/model/spec_fields.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <granstack/model/toml_input.hpp>

namespace granstack::generator {

using model::SpecError;
using model::SpecIssue;

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


}  // namespace

RawSpec parse_spec_toml(std::string_view text, const std::string& source) {
  const auto root = model::parse_toml(text, source);
  RawSpec raw;
  std::vector<SpecIssue> issues;
  for (const auto& [key_, node] : root) {
    const std::string key(key_.str());
    const auto* field = model::find_spec_field(key);
    if (field == nullptr) {
      issues.push_back({key, fmt::format("unknown field in {} ({}); {}", source, model::toml_line(node),
                                         model::unknown_field_hint(key))});
      continue;
    }
    auto& tokens = raw[key];
    if (field->shape == model::FieldShape::pair_entries) {
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
    } else if (field->shape == model::FieldShape::material_entries) {
      const auto* t = node.as_table();
      if (t == nullptr) {
        issues.push_back({key, "must hold tables [custom_materials.NAME] with density, youngs_modulus, poisson_ratio"});
        continue;
      }
      for (const auto& [name, m] : *t) {
        const auto* mt = m.as_table();
        std::string rho, y, nu;
        const auto entry = fmt::format("custom_materials.{}", name.str());
        if (mt == nullptr) {
          issues.push_back({entry, "must be a table with density, youngs_modulus, poisson_ratio"});
          continue;
        }
        for (const auto& [k, v] : *mt) {
          (void)v;
          if (k != "density" && k != "youngs_modulus" && k != "poisson_ratio" && k != "yield_strength") {
            issues.push_back({entry + "." + std::string(k.str()),
                              "unknown entry (known: density, youngs_modulus, poisson_ratio, yield_strength)"});
          }
        }
        auto num = [&](const char* k, std::string& out) {
          const auto* v = mt->get(k);
          if (v == nullptr || !v->is_number() || !scalar_text(*v, out)) {
            issues.push_back({entry + "." + k, "missing, or not a number"});
          }
        };
        num("density", rho);
        num("youngs_modulus", y);
        num("poisson_ratio", nu);
        std::string yield;
        if (mt->contains("yield_strength")) num("yield_strength", yield);
        tokens.push_back(fmt::format("{}:{}:{}:{}{}{}", name.str(), rho, y, nu, yield.empty() ? "" : ":", yield));
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

// A sweepable field's values: numbers (whole ones where the field is), each once.
std::optional<SweepAxis> sweep_axis(const model::SpecField& f, const std::vector<std::string>& tokens,
                                    std::vector<SpecIssue>& issues) {
  SweepAxis axis{f.name, {}};
  for (const auto& t : tokens) {
    double v = 0.0;
    if (!model::parse_sweep_value(f, t, v, issues)) continue;
    if (std::find(axis.values.begin(), axis.values.end(), v) != axis.values.end()) {
      issues.push_back({f.name, fmt::format("the value {} is listed twice", t)});
      continue;
    }
    axis.values.push_back(v);
  }
  if (axis.values.empty()) return std::nullopt;
  return axis;
}

bool repeatable(const model::SpecField& f) {
  return f.shape == model::FieldShape::pair_entries || f.shape == model::FieldShape::material_entries;
}

}  // namespace

Sweep build_sweep(const RawSpec& raw) {
  std::vector<SpecIssue> issues;
  Sweep sweep;
  auto& s = sweep.base;
  for (const auto& [name, tokens] : raw) {
    const auto* f = model::find_spec_field(name);
    if (f == nullptr) {
      issues.push_back({name, fmt::format("unknown field; {}", model::unknown_field_hint(name))});
      continue;
    }
    if ((tokens.empty() && !repeatable(*f)) || std::find(tokens.begin(), tokens.end(), std::string()) != tokens.end()) {
      issues.push_back({name, "an empty value: give a value (leave the field or flag out for its default)"});
      continue;
    }
    if (!f->conflicts_with.empty() && raw.count(f->conflicts_with) != 0) {
      issues.push_back({name, fmt::format("give {} or {}, not both", f->conflicts_with, name)});
      continue;
    }
    if (!f->sweepable()) {
      f->parse(s, tokens, issues);
      continue;
    }
    auto axis = sweep_axis(*f, tokens, issues);
    if (!axis) continue;
    f->set_number(s, axis->values.front());
    if (axis->values.size() > 1) sweep.axes.push_back(std::move(*axis));
  }
  if (!issues.empty()) throw SpecError(std::move(issues));
  for (const auto& [name, tokens] : raw) sweep.given.insert(name);
  // Case names list the swept fields in the table's order (blocks first, then e, mu, ...).
  auto rank = [](const SweepAxis& a) {
    const auto& all = model::spec_fields();
    return std::find_if(all.begin(), all.end(), [&](const auto& f) { return f.name == a.field; }) - all.begin();
  };
  std::sort(sweep.axes.begin(), sweep.axes.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
  // Checks that do not depend on the swept values are reported once, here.
  if (sweep.axes.empty()) {
    model::require_valid(s);
    if (auto ignored = ignored_fields(s, sweep.given); !ignored.empty()) throw SpecError(std::move(ignored));
  }
  return sweep;
}

std::vector<SpecIssue> ignored_fields(const model::StackSpec& s, const std::set<std::string>& given) {
  std::vector<SpecIssue> issues;
  const auto named = [&](const char* field) { return given.count(field) != 0; };
  if (s.geometry != model::Geometry::panels) {
    for (const char* f : {"panels", "impact_panel", "separator", "matrix_material"}) {
      if (named(f)) {
        issues.push_back({f, fmt::format("applies to geometry = panels only (this spec's geometry is {}): remove it, or "
                                         "set geometry = panels",
                                         model::to_string(s.geometry))});
      }
    }
  }
  if (named("wall_material") && !s.has_walls()) {
    issues.push_back({"wall_material", "this stack has no wall (bottom and sides are free): remove it, or set bottom = "
                                       "\"wall\" or sides = \"wall\""});
  }
  const auto all_zero = [](const model::PairTable& t) {
    return t.value == 0.0 && std::all_of(t.pairs.begin(), t.pairs.end(), [](const auto& p) { return p.second == 0.0; });
  };
  if (s.rolling_model != model::RollingModel::off && all_zero(s.rolling_friction)) {
    issues.push_back({"rolling_model", fmt::format("{} with rolling_friction 0 everywhere exerts no torque: give "
                                                   "rolling_friction > 0 (0..1), or leave rolling_model off",
                                                   model::to_string(s.rolling_model))});
  }
  if (s.tangential_model == model::TangentialModel::mindlin_rescale && all_zero(s.friction)) {
    issues.push_back({"tangential_model", "mindlin_rescale with friction 0 everywhere exerts no tangential force (LAMMPS "
                                          "applies none without friction): give friction > 0, or leave tangential_model "
                                          "at history"});
  }
  const bool elastic = s.restitution.value == 1.0 &&
                       std::all_of(s.restitution.pairs.begin(), s.restitution.pairs.end(),
                                   [](const auto& p) { return p.second == 1.0; });
  if (s.tangential_model == model::TangentialModel::no_history && !all_zero(s.friction) && elastic) {
    issues.push_back({"friction", "with tangential_model = no_history the tangential force is viscous, made with the "
                                  "normal damping, which e = 1 makes zero: this friction would do nothing; use "
                                  "tangential_model = history, or e < 1"});
  }
  return issues;
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
      const auto* f = model::find_spec_field(axis.field);
      f->set_number(c.spec, v);
      parts.push_back(fmt::format("{}{}", f->short_key, v));
    }
    c.name = parts.empty() ? "case" : fmt::format("{}", fmt::join(parts, "_"));
    auto issues = model::validate(c.spec);
    if (issues.empty()) issues = ignored_fields(c.spec, sweep.given);
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
