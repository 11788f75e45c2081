#include <granstack/generator/spec_input.hpp>
#include <granstack/postproc/waves.hpp>
#include <granstack/study/catalogue.hpp>

#include <fmt/format.h>
#include <granstack/model/toml_input.hpp>

#include <algorithm>
#include <sstream>

namespace granstack::embedded {
std::string_view catalogue();
}

namespace granstack::study {

namespace {

std::string text(const toml::table& t, const char* key, const std::string& where, bool required = true) {
  if (const auto* v = t.get_as<std::string>(key)) return v->get();
  if (required) throw CatalogueError(fmt::format("{}: '{}' is missing or not a string", where, key));
  return {};
}

std::vector<std::string> strings(const toml::node* n, const std::string& where) {
  std::vector<std::string> out;
  if (n == nullptr) return out;
  if (const auto* s = n->as_string()) return {s->get()};
  const auto* a = n->as_array();
  if (a == nullptr) throw CatalogueError(where + ": a string or a list of strings");
  for (const auto& e : *a) {
    const auto* s = e.as_string();
    if (s == nullptr) throw CatalogueError(where + ": a string or a list of strings");
    out.push_back(s->get());
  }
  return out;
}

double number(const toml::node* n, const std::string& where) {
  if (n != nullptr) {
    if (const auto v = n->value<double>()) return *v;
  }
  throw CatalogueError(where + ": a number is needed");
}

// The cases of one [experiment.cases.NAME] table: a spec, or a sweep of specs.
void add_cases(const std::string& name, toml::table spec, const std::string& where, std::vector<CaseEntry>& out) {
  bool quick = true, full = false;
  if (const auto* q = spec.get_as<bool>("quick")) quick = q->get();
  if (const auto* f = spec.get_as<bool>("full")) full = f->get();
  std::string engine;
  if (const auto* en = spec.get("engine")) {
    if (en->value<std::string>() != "refsim") {
      throw CatalogueError(where + ": engine = \"refsim\" (a case that runs on refsim whatever the reproduction's engine), or none");
    }
    engine = "refsim";
  }
  spec.erase("quick");
  spec.erase("full");
  spec.erase("engine");
  std::ostringstream os;
  os << spec;
  try {
    const auto sweep = generator::build_sweep(generator::parse_spec_toml(os.str(), where));
    for (auto& c : generator::expand(sweep)) {
      const bool single = sweep.axes.empty();
      std::string case_name = single ? name : name == "sweep" ? c.name : name + "_" + c.name;
      out.push_back({std::move(case_name), std::move(c.spec), quick, full, engine});
    }
  } catch (const model::SpecError& e) {
    throw CatalogueError(fmt::format("{}: {}", where, e.what()));
  }
}

// A record's first values (fixed = { date, commit, FIELD = "value", ... }) and its changes
// ([[...change]]): every value is text, as recorded_fields and geometry_text write it.
Record parse_record(const toml::table& t, const std::string& where, const std::vector<std::string>& fields) {
  Record r;
  const auto* fixed = t.get_as<toml::table>("fixed");
  if (fixed == nullptr) return r;
  r.date = text(*fixed, "date", where + ".fixed");
  r.commit = text(*fixed, "commit", where + ".fixed", false);
  for (const auto& [key, node] : *fixed) {
    const std::string k(key.str());
    if (k == "date" || k == "commit") continue;
    if (k == "results_known" && node.is_boolean()) {
      r.fixed_with_results = node.as_boolean()->get();
      continue;
    }
    if (std::find(fields.begin(), fields.end(), k) == fields.end() || !node.is_string()) {
      throw CatalogueError(fmt::format("{}.fixed: '{}' is not a recorded field (recorded: {}; and results_known, true or "
                                       "false), or its value is not text",
                                       where, k, fmt::join(fields, ", ")));
    }
    r.fixed[k] = node.as_string()->get();
  }
  if (const auto* changes = t.get_as<toml::array>("change")) {
    for (const auto& node : *changes) {
      const auto* c = node.as_table();
      if (c == nullptr) throw CatalogueError(where + ": [[...change]] entries are tables");
      const auto w = where + ".change";
      Change ch{text(*c, "date", w), text(*c, "commit", w, false), text(*c, "field", w), text(*c, "before", w), text(*c, "after", w),
                text(*c, "why", w), false};
      if (const auto* known = c->get_as<bool>("results_known")) ch.results_known = known->get();
      if (std::find(fields.begin(), fields.end(), ch.field) == fields.end()) {
        throw CatalogueError(fmt::format("{}: field '{}' is not recorded (recorded: {})", w, ch.field, fmt::join(fields, ", ")));
      }
      r.changes.push_back(std::move(ch));
    }
  }
  return r;
}

const std::vector<std::string> kClaimFields{"statement", "quantity", "band", "paper", "scope", "timing"};
const std::vector<std::string> kScopes{"paper", "granstack", "model check", "arithmetic"};

// The problems of one record against the current values (unrecorded_changes).
void check_record(const Record& r, const std::map<std::string, std::string>& now, const std::string& who,
                  const std::string& table, std::vector<std::string>& out) {
  if (r.date.empty()) {
    out.push_back(fmt::format("{}: no record: add fixed = {{ date = \"YYYY-MM-DD\", ... }} with its values", who));
    return;
  }
  // A change dated after the record was first fixed came after the first run: its results were known.
  for (const auto& c : r.changes) {
    if (c.date > r.date && !c.results_known && c.before != "not recorded") {
      out.push_back(fmt::format("{}: its change of {} on {} came after it was first fixed and run ({}): say "
                                "results_known = true",
                                who, c.field, c.date, r.date));
    }
  }
  for (const auto& [field, current] : now) {
    const auto it = r.fixed.find(field);
    // Fields recorded since the record began start as "not recorded" (a change records their value).
    const bool later_field = field == "physics" || field == "timing";
    std::string v = it != r.fixed.end() ? it->second : field == "scope" ? "paper" : later_field ? "not recorded" : "";
    if (it == r.fixed.end() && field != "scope" && !later_field) {
      out.push_back(fmt::format("{}: its record's fixed values lack '{}'", who, field));
      continue;
    }
    for (const auto& c : r.changes) {
      if (c.field != field) continue;
      if (c.before != v) {
        out.push_back(fmt::format("{}: the change of {} on {} says before = \"{}\", but the record had \"{}\"", who, field,
                                  c.date, c.before, v));
      }
      v = c.after;
    }
    if (v != current) {
      out.push_back(fmt::format("{}: its {} is \"{}\" but its record gives \"{}\": add a [[{}.change]] with date, field = "
                                "\"{}\", before = \"{}\", after = \"{}\" and why",
                                who, field, current, v, table, field, v, current));
    }
  }
}

Claim parse_claim(const toml::table& t, const std::string& experiment, std::size_t index) {
  Claim c;
  c.id = fmt::format("{}.{}", experiment, index);
  const auto where = fmt::format("claim {}", c.id);
  c.statement = text(t, "statement", where);
  const auto* quantity = t.get("quantity");
  if (quantity == nullptr || !quantity->is_string()) {
    throw CatalogueError(where + ": 'quantity' is the one primary reading, a string (other readings go in 'sensitivity')");
  }
  c.quantity = quantity->as_string()->get();
  c.sensitivity = strings(t.get("sensitivity"), where + ".sensitivity");
  c.context = strings(t.get("context"), where + ".context");
  if (t.contains("paper")) c.paper = number(t.get("paper"), where + ".paper");
  const auto* band = t.get_as<toml::array>("band");
  if (band == nullptr || band->size() != 2) throw CatalogueError(where + ": 'band' is [low, high]");
  c.low = number(band->get(0), where + ".band");
  c.high = number(band->get(1), where + ".band");
  if (!(c.low <= c.high)) throw CatalogueError(where + ": the band's low end is above its high end");
  c.band_reason = text(t, "band_reason", where);
  c.expect = text(t, "expect", where);
  if (c.expect != "within" && c.expect != "outside") throw CatalogueError(where + ": 'expect' is \"within\" or \"outside\"");
  if (t.contains("scope")) c.scope = text(t, "scope", where);
  if (std::find(kScopes.begin(), kScopes.end(), c.scope) == kScopes.end()) {
    throw CatalogueError(fmt::format("{}: 'scope' is one of {}", where, fmt::join(kScopes, ", ")));
  }
  c.scope_reason = text(t, "scope_reason", where, c.scope != "paper");
  c.record = parse_record(t, where, kClaimFields);
  return c;
}

Experiment parse_experiment(const toml::table& t) {
  Experiment e;
  e.name = text(t, "name", "an experiment");
  const auto where = fmt::format("experiment {}", e.name);
  e.title = text(t, "title", where);
  e.source = text(t, "source", where);
  e.analysis = text(t, "analysis", where);
  e.explanation = text(t, "explanation", where, false);
  e.main = text(t, "main", where, false);
  e.needs = strings(t.get("needs"), where + ".needs");
  if (const auto* q = t.get_as<bool>("quick")) e.quick = q->get();
  if (const auto* f = t.get_as<bool>("full")) e.full = f->get();
  if (const auto* b = t.get_as<bool>("beyond")) e.beyond = b->get();
  if (const auto* cases = t.get_as<toml::table>("cases")) {
    for (const auto& [key, node] : *cases) {
      const auto* spec = node.as_table();
      if (spec == nullptr) throw CatalogueError(fmt::format("{}: cases.{} is a table of spec fields", where, key.str()));
      add_cases(std::string(key.str()), *spec, fmt::format("{} case {}", where, key.str()), e.cases);
    }
  }
  if (!e.main.empty() && std::none_of(e.cases.begin(), e.cases.end(), [&](const CaseEntry& c) { return c.name == e.main; })) {
    throw CatalogueError(fmt::format("{}: main = \"{}\" is not one of its cases", where, e.main));
  }
  if (e.main.empty() && !e.cases.empty()) e.main = e.cases.front().name;
  e.record = parse_record(t, where, {"geometry", "physics"});
  if (const auto* claims = t.get_as<toml::array>("claim")) {
    std::size_t n = 0;
    for (const auto& node : *claims) {
      const auto* c = node.as_table();
      if (c == nullptr) throw CatalogueError(where + ": [[experiment.claim]] entries are tables");
      e.claims.push_back(parse_claim(*c, e.name, ++n));
    }
  }
  return e;
}

}  // namespace

bool reads_wave_timing(std::string_view quantity) { return quantity.substr(0, 5) == "speed"; }

std::map<std::string, std::string> recorded_fields(const Claim& c) {
  std::map<std::string, std::string> out{{"statement", c.statement},
                                         {"quantity", c.quantity},
                                         {"band", fmt::format("[{:g}, {:g}]", c.low, c.high)},
                                         {"paper", c.paper ? fmt::format("{:g}", *c.paper) : "none"},
                                         {"scope", c.scope}};
  if (reads_wave_timing(c.quantity)) out["timing"] = postproc::leading_pulse_rule();
  return out;
}

std::string geometry_text(const model::StackSpec& s) {
  std::vector<std::string> rows, ratios, materials;
  for (int k = 1; k <= s.blocks; ++k) {
    rows.push_back(std::to_string(s.rows_of(k)));
    materials.push_back(s.block_material(k));
    if (k < s.blocks) ratios.push_back(std::to_string(s.ratio_below(k)));
  }
  const bool one_height = std::all_of(rows.begin(), rows.end(), [&](const std::string& r) { return r == rows.front(); });
  const bool one_ratio = std::all_of(ratios.begin(), ratios.end(), [&](const std::string& r) { return r == ratios.front(); });
  return fmt::format("{}{} block{} of {} rows, {} top columns{}, {}, bottom {}, sides {}, stop {}",
                     s.geometry == model::Geometry::strip ? "" : fmt::format("{}: ", model::to_string(s.geometry)), s.blocks,
                     s.blocks == 1 ? "" : "s",
                     one_height ? rows.front() : fmt::format("{}", fmt::join(rows, "/")), s.top_columns,
                     ratios.empty() ? "" : ", ratio " + (one_ratio ? ratios.front() : fmt::format("{}", fmt::join(ratios, "/"))),
                     fmt::join(materials, "/"),
                     model::to_string(s.bottom), model::to_string(s.sides), model::to_string(s.stop));
}

namespace {
std::string pair_values(const model::PairTable& v, const char* name) {
  std::string out = fmt::format("{} = {:g}", name, v.value);
  for (const auto& [pair, x] : v.pairs) out += fmt::format(", {} {}-{} = {:g}", name, pair.first, pair.second, x);
  return out;
}
}  // namespace

std::string physics_text(const model::StackSpec& s) {
  auto out = fmt::format("{}, {}, striker {:g} m/s, radius {:g} R_1, {}, bottom radius {:g} m, {}", pair_values(s.restitution, "e"),
                         pair_values(s.friction, "mu"), s.striker_speed, s.striker_radius_ratio, s.effective_striker_material(),
                         s.bottom_radius, model::liggghts_model_words(s.contact_model()));
  if (s.impact_offset != 0) out += fmt::format(", impact offset {}", s.impact_offset);
  if (s.gravity > 0.0) out += fmt::format(", gravity {:g} m/s^2", s.gravity);
  if (s.has_walls()) out += fmt::format(", walls of {}", s.effective_wall_material());
  for (const auto& m : s.custom_materials) {
    out += fmt::format(", {}: rho {:g}, E {:g}, nu {:g}", m.name, m.density, m.youngs_modulus, m.poisson_ratio);
  }
  if (s.dt) out += fmt::format(", dt {:g} s", *s.dt);
  if (s.duration) out += fmt::format(", duration {:g} s", *s.duration);
  return out;
}

std::vector<std::string> unrecorded_changes(const Experiment& e) {
  std::vector<std::string> out;
  for (const auto& c : e.claims) check_record(c.record, recorded_fields(c), "claim " + c.id, "experiment.claim", out);
  for (const auto& c : e.cases) {
    if (c.name == e.main) {
      check_record(e.record, {{"geometry", geometry_text(c.spec)}, {"physics", physics_text(c.spec)}}, "experiment " + e.name,
                   "experiment", out);
    }
  }
  return out;
}

const Experiment* Catalogue::find(std::string_view name) const {
  for (const auto& e : experiments) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

std::vector<std::string> Catalogue::names() const {
  std::vector<std::string> out;
  for (const auto& e : experiments) out.push_back(e.name);
  return out;
}

Catalogue parse_catalogue(std::string_view toml_text, const std::string& source) {
  const auto root = model::parse_toml<CatalogueError>(toml_text, source);
  Catalogue c;
  const auto* list = root.get_as<toml::array>("experiment");
  if (list == nullptr) throw CatalogueError(source + ": no [[experiment]]");
  for (const auto& node : *list) {
    const auto* t = node.as_table();
    if (t == nullptr) throw CatalogueError(source + ": [[experiment]] entries are tables");
    c.experiments.push_back(parse_experiment(*t));
  }
  if (const auto* out = root.get_as<toml::array>("out_of_scope")) {
    for (const auto& node : *out) {
      const auto* t = node.as_table();
      if (t == nullptr) throw CatalogueError(source + ": [[out_of_scope]] entries are tables");
      c.out_of_scope.push_back({text(*t, "statement", "out_of_scope"), text(*t, "why", "out_of_scope")});
    }
  }
  for (const auto& e : c.experiments) {
    for (const auto& n : e.needs) {
      if (c.find(n) == nullptr) throw CatalogueError(fmt::format("experiment {} needs '{}', which is not in the catalogue", e.name, n));
    }
  }
  return c;
}

const Catalogue& builtin_catalogue() {
  static const Catalogue c = parse_catalogue(embedded::catalogue(), "study/data/catalogue.toml");
  return c;
}

std::vector<const Experiment*> select(const Catalogue& c, const std::vector<std::string>& names, bool quick, bool full) {
  std::vector<std::string> wanted;
  for (const auto& n : names) {
    if (c.find(n) == nullptr) {
      throw UnknownExperiment(fmt::format("unknown experiment '{}'; known: {}", n, fmt::join(c.names(), ", ")));
    }
    wanted.push_back(n);
  }
  if (wanted.empty()) {
    for (const auto& e : c.experiments) {
      if ((!quick || e.quick) && (full || !e.full)) wanted.push_back(e.name);
    }
  }
  // The experiments they need, and theirs.
  for (std::size_t i = 0; i < wanted.size(); ++i) {
    for (const auto& n : c.find(wanted[i])->needs) {
      if (std::find(wanted.begin(), wanted.end(), n) == wanted.end()) wanted.push_back(n);
    }
  }
  std::vector<const Experiment*> out;
  for (const auto& e : c.experiments) {
    if (std::find(wanted.begin(), wanted.end(), e.name) != wanted.end()) out.push_back(&e);
  }
  return out;
}

}  // namespace granstack::study
