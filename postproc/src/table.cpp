#include <granstack/formats/manifest.hpp>
#include <granstack/postproc/table.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

namespace granstack::postproc {

using nlohmann::json;

namespace {
std::string short_name(const std::string& field) {
  static const std::map<std::string, std::string> names{{"restitution", "e"},   {"friction", "mu"},
                                                        {"striker_speed", "v"}, {"top_columns", "cols"},
                                                        {"bottom_radius", "r"}, {"radius_ratio", "ratio"},
                                                        {"deck_additions", "additions"}};
  const auto it = names.find(field);
  return it == names.end() ? field : it->second;
}

std::string value_text(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::vector<std::string> parts;
    for (const auto& e : v) parts.push_back(value_text(e));
    return fmt::format("{}", fmt::join(parts, "/"));
  }
  if (v.is_number_float()) return fmt::format("{}", v.get<double>());
  return v.dump();
}

std::string with_error(double value, const std::optional<double>& error) {
  return error ? fmt::format("{:.4g} ± {:.2g}", value, *error) : fmt::format("{:.4g}", value);
}
}  // namespace

OutputTable build_table(const std::vector<CaseReduction>& reductions) {
  std::map<std::string, std::vector<const CaseReduction*>> by_key;
  std::map<std::string, json> keys;
  for (const auto& r : reductions) {
    auto key = formats::spec_to_json(r.spec);
    key.erase("blocks");
    key["engine"] = r.engine;  // the same spec on two engines is two groups, each named by its engine
    const auto text = key.dump();
    by_key[text].push_back(&r);
    keys[text] = key;
  }
  // The fields whose values differ between groups name them; a custom material's constants
  // by material and constant (`matrix.youngs_modulus`), where two groups define one name apart.
  std::set<std::string> differing;
  const auto constant = [&](const json& key, const std::string& path) {
    return key.value(json::json_pointer("/custom_materials/" + path), json());
  };
  std::set<std::string> constants;  // "NAME/constant" of every custom material of any group
  std::set<std::string> fields;  // a field written only where it is given (deck_additions) is in some keys alone
  for (const auto& [text, key] : keys) {
    for (const auto& [field, value] : key.items()) fields.insert(field);
  }
  for (const auto& field : fields) {
    for (const auto& [text, key] : keys) {
      if (keys.begin()->second.value(field, json()) != key.value(field, json())) differing.insert(field);
    }
  }
  for (const auto& [text, key] : keys) {
    const json custom = key.value("custom_materials", json::object());
    for (const auto& [name, m] : custom.items()) {
      for (const auto& [c, v] : m.items()) constants.insert(name + "/" + c);
    }
  }
  std::set<std::string> differing_constants;  // between groups that both define the material
  for (const auto& path : constants) {
    std::set<std::string> values;
    for (const auto& [text, key] : keys) {
      if (const auto v = constant(key, path); !v.is_null()) values.insert(v.dump());
    }
    if (values.size() > 1) differing_constants.insert(path);
  }
  OutputTable t;
  std::set<int> all_blocks;
  std::vector<json> sort_keys;  // per group: the differing fields' values, compared as values
  for (auto& [text, all_cases] : by_key) {
    std::stable_sort(all_cases.begin(), all_cases.end(), [](auto* a, auto* b) { return a->spec.blocks < b->spec.blocks; });
    // The same case run twice (a reproduction runs one spec in two experiments) is one row when
    // the two gave the same output to the bit; two outputs for one case are refused.
    std::vector<const CaseReduction*> cases;
    for (const auto* c : all_cases) {
      if (!cases.empty() && cases.back()->spec.blocks == c->spec.blocks) {
        if (cases.back()->output_fraction == c->output_fraction) continue;
        throw std::invalid_argument(fmt::format("cases {} and {} differ in nothing but their directory, yet their outputs "
                                                "differ ({:.17g} and {:.17g}): give each (group, N_B) once",
                                                cases.back()->case_dir, c->case_dir, cases.back()->output_fraction,
                                                c->output_fraction));
      }
      cases.push_back(c);
    }
    TableGroup g;
    g.cases = cases;
    g.restitution = cases.front()->spec.restitution.value;
    std::vector<std::string> parts;
    json sort_key = json::array();
    for (const auto& field : differing) {
      const auto v = keys[text].value(field, json());
      sort_key.push_back(v);
      if (field == "custom_materials") continue;  // named constant by constant below
      const auto value = v.is_null() ? std::string() : value_text(v);
      parts.push_back(short_name(field) + "=" + (!value.empty() ? value : field == "deck_additions" ? "none" : "default"));
    }
    for (const auto& path : differing_constants) {
      const auto v = constant(keys[text], path);
      sort_key.push_back(v);
      auto name = path;
      name[name.find('/')] = '.';
      if (!v.is_null()) parts.push_back(name + "=" + value_text(v));
    }
    sort_keys.push_back(std::move(sort_key));
    g.label = parts.empty() ? fmt::format("e={}", g.restitution) : fmt::format("{}", fmt::join(parts, ", "));
    std::vector<int> nb;
    std::vector<double> f;
    for (const auto* c : cases) {
      nb.push_back(c->spec.blocks);
      f.push_back(c->output_fraction);
      all_blocks.insert(c->spec.blocks);
    }
    try {
      g.fit = fit_decay(nb, f);
    } catch (const std::invalid_argument& e) {
      g.fit_note = nb.size() < 2 ? "one N_B only" : e.what();
    }
    t.groups.push_back(std::move(g));
  }
  // Highest restitution first (the study's order), then by the values of the fields that tell
  // the groups apart, as numbers where they are numbers (rows=8 before rows=10).
  std::vector<std::size_t> order(t.groups.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (t.groups[a].restitution != t.groups[b].restitution) return t.groups[a].restitution > t.groups[b].restitution;
    return sort_keys[a] < sort_keys[b];
  });
  std::vector<TableGroup> sorted;
  for (const auto i : order) sorted.push_back(std::move(t.groups[i]));
  t.groups = std::move(sorted);
  t.blocks.assign(all_blocks.begin(), all_blocks.end());
  return t;
}

std::string table_markdown(const OutputTable& t) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, "Output fraction E_out/E_in (the output sphere) against the number of blocks\n\n| N_B |");
  for (const auto& g : t.groups) fmt::format_to(out, " {} |", g.label);
  fmt::format_to(out, "\n|---|");
  for (std::size_t k = 0; k < t.groups.size(); ++k) fmt::format_to(out, "---|");
  fmt::format_to(out, "\n");
  for (const int nb : t.blocks) {
    fmt::format_to(out, "| {} |", nb);
    for (const auto& g : t.groups) {
      const auto it = std::find_if(g.cases.begin(), g.cases.end(), [&](auto* c) { return c->spec.blocks == nb; });
      if (it == g.cases.end()) {
        fmt::format_to(out, "  |");
      } else {
        fmt::format_to(out, " {:.6g}{} |", (*it)->output_fraction, (*it)->output_separated ? "" : " (not separated)");
      }
    }
    fmt::format_to(out, "\n");
  }
  fmt::format_to(out, "\nFit E_out/E_in = A exp(-alpha N_B), least squares on the logarithm (± standard error)\n\n");
  fmt::format_to(out, "| group | points | A | alpha | alpha with A = 1 | alpha * e |\n|---|---|---|---|---|---|\n");
  for (const auto& g : t.groups) {
    if (!g.fit) {
      fmt::format_to(out, "| {} | {} | no fit: {} | | | |\n", g.label, g.cases.size(), g.fit_note);
      continue;
    }
    const auto& f = *g.fit;
    fmt::format_to(out, "| {} | {} | {} | {} | {} | {} |\n", g.label, f.points, with_error(f.prefactor, f.prefactor_error),
                   with_error(f.alpha, f.alpha_error), with_error(f.alpha_origin, f.alpha_origin_error),
                   with_error(f.alpha * g.restitution,
                              f.alpha_error ? std::optional<double>(*f.alpha_error * g.restitution) : std::nullopt));
  }
  return fmt::to_string(b);
}

std::string table_csv(const OutputTable& t) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  fmt::format_to(out, "group,restitution,friction,striker_speed,blocks,output_fraction,output_fraction_bottom_row,"
                      "output_fraction_bottom_row_per_sphere,output_separated,case_dir\n");
  for (const auto& g : t.groups) {
    for (const auto* c : g.cases) {
      fmt::format_to(out, "\"{}\",{},{},{},{},{},{},{},{},\"{}\"\n", g.label, c->spec.restitution.value, c->spec.friction.value,
                     c->spec.striker_speed, c->spec.blocks, c->output_fraction, c->output_fraction_bottom_row,
                     c->output_fraction_bottom_row_per_sphere, c->output_separated ? 1 : 0, c->case_dir);
    }
  }
  return fmt::to_string(b);
}

std::string fits_csv(const OutputTable& t) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  auto opt = [](const std::optional<double>& v) { return v ? fmt::format("{}", *v) : std::string(); };
  fmt::format_to(out, "group,restitution,points,prefactor,prefactor_error,alpha,alpha_error,cov_ln_prefactor_alpha,"
                      "alpha_origin,alpha_origin_error,alpha_times_e\n");
  for (const auto& g : t.groups) {
    if (!g.fit) continue;
    const auto& f = *g.fit;
    fmt::format_to(out, "\"{}\",{},{},{},{},{},{},{},{},{},{}\n", g.label, g.restitution, f.points, f.prefactor,
                   opt(f.prefactor_error), f.alpha, opt(f.alpha_error), opt(f.covariance_ln_prefactor_alpha),
                   f.alpha_origin, opt(f.alpha_origin_error), f.alpha * g.restitution);
  }
  return fmt::to_string(b);
}

json table_json(const OutputTable& t) {
  json groups = json::array();
  auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  for (const auto& g : t.groups) {
    json cases = json::array();
    for (const auto* c : g.cases) {
      cases.push_back({{"blocks", c->spec.blocks}, {"output_fraction", c->output_fraction}, {"case_dir", c->case_dir}});
    }
    json fit = nullptr;
    if (g.fit) {
      fit = {{"points", g.fit->points},         {"prefactor", g.fit->prefactor},
             {"prefactor_error", opt(g.fit->prefactor_error)}, {"alpha", g.fit->alpha},
             {"alpha_error", opt(g.fit->alpha_error)},
             {"covariance_ln_prefactor_alpha", opt(g.fit->covariance_ln_prefactor_alpha)},
             {"alpha_origin", g.fit->alpha_origin},
             {"alpha_origin_error", opt(g.fit->alpha_origin_error)}, {"alpha_times_e", g.fit->alpha * g.restitution}};
    }
    groups.push_back({{"group", g.label}, {"restitution", g.restitution}, {"cases", cases}, {"fit", fit}});
  }
  return {{"groups", groups}};
}

}  // namespace granstack::postproc
