#include <granstack/design/objectives.hpp>
#include <granstack/design/store.hpp>
#include <granstack/model/spec_fields.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <algorithm>
#include <filesystem>

namespace granstack::design {

namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS evaluations (
  digest TEXT PRIMARY KEY, description TEXT NOT NULL, spec TEXT NOT NULL, blocks INTEGER NOT NULL,
  spheres INTEGER NOT NULL, feasible INTEGER NOT NULL, violations TEXT NOT NULL, areal_mass REAL NOT NULL, height REAL NOT NULL,
  seconds REAL NOT NULL, searched INTEGER NOT NULL, output_separated INTEGER NOT NULL, created TEXT NOT NULL DEFAULT (datetime('now')));
CREATE TABLE IF NOT EXISTS study_designs (name TEXT PRIMARY KEY, digest TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS elastic_twins (digest TEXT PRIMARY KEY, twin TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS generations (
  run INTEGER NOT NULL DEFAULT 0, generation INTEGER NOT NULL, population TEXT NOT NULL, digests TEXT NOT NULL,
  hypervolume REAL NOT NULL, evaluations INTEGER NOT NULL, finished TEXT NOT NULL DEFAULT (datetime('now')),
  PRIMARY KEY (run, generation));
CREATE TABLE IF NOT EXISTS joins (
  run INTEGER NOT NULL, position INTEGER NOT NULL, digest TEXT NOT NULL, PRIMARY KEY (run, position));
CREATE TABLE IF NOT EXISTS confirmations (
  digest TEXT PRIMARY KEY, case_dir TEXT NOT NULL, liggghts_output_fraction REAL NOT NULL,
  liggghts_peak_wall_force REAL, largest_difference REAL NOT NULL, objective_difference REAL NOT NULL,
  verdict TEXT NOT NULL);
)sql";

// A store from before several seeds: its generations table keyed by generation alone, made the
// first run's (run 0).
constexpr const char* kRunsMigration = R"sql(
BEGIN;
CREATE TABLE generations_by_run (
  run INTEGER NOT NULL DEFAULT 0, generation INTEGER NOT NULL, population TEXT NOT NULL, digests TEXT NOT NULL,
  hypervolume REAL NOT NULL, evaluations INTEGER NOT NULL, finished TEXT NOT NULL DEFAULT (datetime('now')),
  PRIMARY KEY (run, generation));
INSERT INTO generations_by_run (run, generation, population, digests, hypervolume, evaluations, finished)
  SELECT 0, generation, population, digests, hypervolume, evaluations, finished FROM generations;
DROP TABLE generations;
ALTER TABLE generations_by_run RENAME TO generations;
COMMIT;
)sql";

// A prepared statement, finalised when it goes.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s_, nullptr) != SQLITE_OK) fail("prepare");
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  Statement& bind(int i, const std::string& v) {
    sqlite3_bind_text(s_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Statement& bind(int i, double v) {
    sqlite3_bind_double(s_, i, v);
    return *this;
  }
  Statement& bind(int i, long v) {
    sqlite3_bind_int64(s_, i, v);
    return *this;
  }
  Statement& bind(int i, std::optional<double> v) {
    if (v) sqlite3_bind_double(s_, i, *v);
    else sqlite3_bind_null(s_, i);
    return *this;
  }
  bool step() {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) fail("step");
    return false;
  }
  std::string text(int c) const {
    const auto* t = sqlite3_column_text(s_, c);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  double real(int c) const { return sqlite3_column_double(s_, c); }
  long integer(int c) const { return static_cast<long>(sqlite3_column_int64(s_, c)); }
  std::optional<double> maybe(int c) const {
    if (sqlite3_column_type(s_, c) == SQLITE_NULL) return std::nullopt;
    return real(c);
  }

 private:
  [[noreturn]] void fail(const char* what) const { throw_store_error(db_, fmt::format("{} failed", what)); }
  sqlite3* db_;
  sqlite3_stmt* s_ = nullptr;
};

// The evaluations' fixed columns; each run measure of objective_table() has a REAL column of its
// own name after them (NULL where the design was not run or its bottom cannot measure it).
constexpr const char* kEvaluationColumns =
    "digest, description, spec, spheres, feasible, violations, areal_mass, height, seconds, searched, output_separated";
constexpr int kFixedColumns = 11;

// The columns a row of evaluations is read from: the fixed ones, each run measure's, the
// scenarios' runs (JSON; a store written before them reads as none) and the shortcut that settled
// the design and why (a store written before them: none).
std::string prefixed_columns(const std::string& prefix, const std::vector<std::string>& measures, bool scenarios, bool shortcuts) {
  std::string out;
  std::string_view rest = kEvaluationColumns;
  while (!rest.empty()) {
    const auto comma = rest.find(", ");
    out += (out.empty() ? "" : ", ") + prefix + std::string(rest.substr(0, comma));
    rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 2);
  }
  for (const auto& m : measures) out += ", " + prefix + m;
  out += scenarios ? ", " + prefix + "scenarios" : std::string(", '[]'");
  out += shortcuts ? fmt::format(", {0}shortcut, {0}shortcut_why", prefix) : std::string(", '', ''");
  return out;
}

nlohmann::json scenarios_json(const std::vector<ScenarioRun>& runs) {
  auto j = nlohmann::json::array();
  for (const auto& r : runs) {
    j.push_back({{"label", r.label}, {"spec", model::spec_json(r.spec)}, {"measures", r.measures}, {"not_final", r.not_final},
                 {"seconds", r.seconds}});
  }
  return j;
}

std::vector<ScenarioRun> scenarios_from(const std::string& text) {
  std::vector<ScenarioRun> out;
  for (const auto& r : nlohmann::json::parse(text)) {
    out.push_back({r.at("label").get<std::string>(), model::spec_from_json_fields(r.at("spec")),
                   r.at("measures").get<std::map<std::string, double>>(), r.at("not_final").get<std::string>(),
                   r.value("seconds", 0.0)});
  }
  return out;
}

// The evaluation in the columns from `from` of a row (prefixed_columns' order).
Evaluation evaluation_from(const Statement& q, const std::vector<std::string>& measures, int from = 0) {
  Evaluation e;
  e.digest = q.text(from);
  e.description = q.text(from + 1);
  e.spec = model::spec_from_json_fields(nlohmann::json::parse(q.text(from + 2)));
  e.spheres = q.integer(from + 3);
  e.feasible = q.integer(from + 4) != 0;
  e.violations = q.text(from + 5);
  e.areal_mass = q.real(from + 6);
  e.height = q.real(from + 7);
  e.seconds = q.real(from + 8);
  e.searched = q.integer(from + 9) != 0;
  e.output_separated = q.integer(from + 10) != 0;
  for (std::size_t k = 0; k < measures.size(); ++k) {
    if (const auto v = q.maybe(from + kFixedColumns + static_cast<int>(k))) e.measures.emplace(measures[k], *v);
  }
  const int tail = from + kFixedColumns + static_cast<int>(measures.size());
  e.scenarios = scenarios_from(q.text(tail));
  e.shortcut = q.text(tail + 1);
  e.shortcut_why = q.text(tail + 2);
  return e;
}

sqlite3* open_db(const std::string& path, int flags) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    const std::string why = db ? sqlite3_errmsg(db) : "out of memory";
    const int code = db ? sqlite3_errcode(db) & 0xff : SQLITE_NOMEM;
    sqlite3_close(db);
    const auto message = fmt::format("{}: cannot open the design store: {}", path, why);
    if (code == SQLITE_CANTOPEN || code == SQLITE_READONLY || code == SQLITE_IOERR) throw StoreIoError(message);
    throw StoreError(message);
  }
  sqlite3_busy_timeout(db, 10000);
  return db;
}
}  // namespace

void throw_store_error(sqlite3* db, const std::string& what) {
  const char* file = sqlite3_db_filename(db, "main");
  const int code = sqlite3_errcode(db) & 0xff;  // the primary code
  const auto message = fmt::format("design store {}: {}: {}", file != nullptr && *file != '\0' ? file : "(in memory)",
                                   what, sqlite3_errmsg(db));
  if (code == SQLITE_FULL || code == SQLITE_IOERR || code == SQLITE_READONLY || code == SQLITE_CANTOPEN) {
    throw StoreIoError(message + (code == SQLITE_FULL ? " (free some space and run it again: the store keeps what it "
                                                       "had)"
                                                     : ""));
  }
  throw StoreError(message);
}

Store::Store(sqlite3* db) : db_(db), mutex_(std::make_unique<std::mutex>()) {}
Store::Store(Store&& o) noexcept
    : db_(o.db_), measures_(std::move(o.measures_)), has_scenarios_(o.has_scenarios_), has_shortcuts_(o.has_shortcuts_),
      has_runs_(o.has_runs_), has_joins_(o.has_joins_), mutex_(std::move(o.mutex_)) {
  o.db_ = nullptr;
}
Store::~Store() { sqlite3_close(db_); }

void Store::exec(const std::string& sql) const {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    sqlite3_free(error);
    throw_store_error(db_, "a statement failed");
  }
}

Store Store::open(const std::string& path, const std::string& space_digest, const std::string& space_text) {
  Store s(open_db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE));
  s.exec(kSchema);
  s.require_measure_rules(path);
  // A measure added to the table since the store was written gets its column (NULL for the
  // designs evaluated before it).
  const auto present = s.columns("evaluations");
  for (const auto& m : run_measure_names()) {
    if (std::find(present.begin(), present.end(), m) == present.end()) s.exec(fmt::format("ALTER TABLE evaluations ADD COLUMN {} REAL", m));
  }
  if (std::find(present.begin(), present.end(), "scenarios") == present.end()) {
    s.exec("ALTER TABLE evaluations ADD COLUMN scenarios TEXT NOT NULL DEFAULT '[]'");
  }
  for (const char* c : {"shortcut", "shortcut_why"}) {
    if (std::find(present.begin(), present.end(), c) == present.end()) {
      s.exec(fmt::format("ALTER TABLE evaluations ADD COLUMN {} TEXT NOT NULL DEFAULT ''", c));
    }
  }
  if (const auto c = s.columns("confirmations"); std::find(c.begin(), c.end(), "longer_difference") == c.end()) {
    s.exec("ALTER TABLE confirmations ADD COLUMN longer_difference REAL");
  }
  if (const auto c = s.columns("confirmations"); std::find(c.begin(), c.end(), "variant") == c.end()) {
    s.exec("ALTER TABLE confirmations ADD COLUMN variant TEXT NOT NULL DEFAULT '{}'");
  }
  if (const auto c = s.columns("confirmations"); std::find(c.begin(), c.end(), "law") == c.end()) {
    s.exec("ALTER TABLE confirmations ADD COLUMN law TEXT NOT NULL DEFAULT '{}'");
  }
  if (const auto c = s.columns("generations"); std::find(c.begin(), c.end(), "run") == c.end()) s.exec(kRunsMigration);
  s.find_measures();
  if (const auto d = s.meta("space_digest")) {
    if (*d != space_digest) {
      throw StoreError(fmt::format("{} holds the search of another design space (digest {}, this one's is {}): give "
                                   "another --output, or the space it was written for (its text is in the store's meta "
                                   "table, key 'space')", path, d->substr(0, 12), space_digest.substr(0, 12)));
    }
  } else {
    s.set_meta("space_digest", space_digest);
    s.set_meta("space", space_text);
  }
  return s;
}

int Store::measure_rules() const {
  const auto rules = meta("measure_rules");
  return rules ? std::stoi(*rules) : 1;
}

void Store::require_measure_rules(const std::string& path) {
  Statement q(db_, "SELECT COUNT(*) FROM evaluations");
  const bool evaluated = q.step() && q.integer(0) > 0;
  if (evaluated && measure_rules() != kMeasureRules) {
    throw StoreError(fmt::format("{} holds designs measured by granstack's measure rules {}; this granstack measures by "
                                 "rules {} ({}), so its numbers and the store's would be mixed: search into a new folder "
                                 "(another --output; the old store stays as it is, and `design report` still reads it)",
                                 path, measure_rules(), kMeasureRules, measure_rules_changes()));
  }
  if (!evaluated) set_meta("measure_rules", std::to_string(kMeasureRules));
}

bool Store::unfinished(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  if (std::filesystem::file_size(path, ec) == 0) return !ec;
  try {
    Store s(open_db(path, SQLITE_OPEN_READONLY));
    if (s.meta("space_digest")) return false;
    Statement tables(s.db_, "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table' AND name = 'evaluations'");
    if (!tables.step() || tables.integer(0) == 0) return true;
    Statement q(s.db_, "SELECT COUNT(*) FROM evaluations");
    return q.step() && q.integer(0) == 0;
  } catch (const std::exception&) {
    return false;  // not SQLite: what it is, open_existing says
  }
}

Store Store::open_existing(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw StoreError(fmt::format("{}: no design store there; run 'granstack design run SPACE.toml -o DIR' first", path));
  }
  if (unfinished(path)) {
    throw StoreError(fmt::format("{}: its search's first write did not finish (a full disk, or a search stopped as it "
                                 "began): it holds no design; run 'granstack design run SPACE.toml -o {}' again, which "
                                 "begins it anew",
                                 path, std::filesystem::path(path).parent_path().string()));
  }
  Store s(open_db(path, SQLITE_OPEN_READONLY));
  if (!s.meta("space_digest")) throw StoreError(fmt::format("{}: not a granstack design store", path));
  s.find_measures();
  return s;
}

std::optional<std::string> Store::meta(const std::string& key) const {
  try {
    Statement q(db_, "SELECT value FROM meta WHERE key = ?");
    q.bind(1, key);
    if (q.step()) return q.text(0);
  } catch (const StoreError&) {
    return std::nullopt;  // no meta table: not a store
  }
  return std::nullopt;
}

void Store::set_meta(const std::string& key, const std::string& value) {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, "INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)");
  q.bind(1, key).bind(2, value).step();
}

std::optional<Evaluation> Store::find(const std::string& digest) const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, fmt::format("SELECT {} FROM evaluations WHERE digest = ?", prefixed_columns("", measures_, has_scenarios_, has_shortcuts_)));
  q.bind(1, digest);
  if (q.step()) return evaluation_from(q, measures_);
  return std::nullopt;
}

void Store::put(const Evaluation& e) {
  const std::lock_guard<std::mutex> lock(*mutex_);
  std::string marks = "?";
  for (int k = 1; k < kFixedColumns + static_cast<int>(measures_.size()) + 4; ++k) marks += ", ?";
  Statement q(db_, fmt::format("INSERT OR REPLACE INTO evaluations ({}, blocks) VALUES ({})", prefixed_columns("", measures_, has_scenarios_, has_shortcuts_), marks));
  q.bind(1, e.digest).bind(2, e.description).bind(3, model::spec_json(e.spec).dump()).bind(4, e.spheres);
  q.bind(5, static_cast<long>(e.feasible)).bind(6, e.violations).bind(7, e.areal_mass).bind(8, e.height).bind(9, e.seconds);
  q.bind(10, static_cast<long>(e.searched)).bind(11, static_cast<long>(e.output_separated));
  int at = kFixedColumns + 1;
  for (const auto& m : measures_) {
    const auto v = e.measures.find(m);
    q.bind(at++, v == e.measures.end() ? std::nullopt : std::optional<double>(v->second));
  }
  q.bind(at++, scenarios_json(e.scenarios).dump());
  q.bind(at++, e.shortcut);
  q.bind(at++, e.shortcut_why);
  q.bind(at, static_cast<long>(e.spec.blocks));
  q.step();
}

std::vector<std::string> Store::columns(const std::string& table) const {
  Statement q(db_, fmt::format("PRAGMA table_info({})", table));
  std::vector<std::string> out;
  while (q.step()) out.push_back(q.text(1));
  return out;
}

void Store::find_measures() {
  const auto present = columns("evaluations");
  has_scenarios_ = std::find(present.begin(), present.end(), "scenarios") != present.end();
  has_shortcuts_ = std::find(present.begin(), present.end(), "shortcut") != present.end();
  const auto gens = columns("generations");
  has_runs_ = std::find(gens.begin(), gens.end(), "run") != gens.end();
  has_joins_ = !columns("joins").empty();
  measures_.clear();
  for (const auto& m : run_measure_names()) {
    if (std::find(present.begin(), present.end(), m) != present.end()) measures_.push_back(m);
  }
}

std::vector<Evaluation> Store::evaluations() const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, fmt::format("SELECT {} FROM evaluations WHERE searched = 1 ORDER BY rowid", prefixed_columns("", measures_, has_scenarios_, has_shortcuts_)));
  std::vector<Evaluation> out;
  while (q.step()) out.push_back(evaluation_from(q, measures_));
  return out;
}

std::vector<std::pair<std::string, Evaluation>> Store::study_designs() const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, fmt::format("SELECT s.name, {} FROM study_designs s JOIN evaluations e ON e.digest = s.digest ORDER BY s.rowid",
                               prefixed_columns("e.", measures_, has_scenarios_, has_shortcuts_)));
  std::vector<std::pair<std::string, Evaluation>> out;
  while (q.step()) out.emplace_back(q.text(0), evaluation_from(q, measures_, 1));
  return out;
}

void Store::put_study_design(const std::string& name, const std::string& digest) {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, "INSERT OR REPLACE INTO study_designs (name, digest) VALUES (?, ?)");
  q.bind(1, name).bind(2, digest).step();
}

std::map<std::string, Evaluation> Store::elastic_twins() const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  if (columns("elastic_twins").empty()) return {};  // a store from before twins, read as it is
  Statement q(db_, fmt::format("SELECT t.digest, {} FROM elastic_twins t JOIN evaluations e ON e.digest = t.twin",
                               prefixed_columns("e.", measures_, has_scenarios_, has_shortcuts_)));
  std::map<std::string, Evaluation> out;
  while (q.step()) out.emplace(q.text(0), evaluation_from(q, measures_, 1));
  return out;
}

void Store::put_elastic_twin(const std::string& digest, const Evaluation& twin) {
  auto e = twin;
  e.searched = false;
  put(e);
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, "INSERT OR REPLACE INTO elastic_twins (digest, twin) VALUES (?, ?)");
  q.bind(1, digest).bind(2, twin.digest).step();
}

void Store::put_generation(const Generation& g) {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, "INSERT OR REPLACE INTO generations (run, generation, population, digests, hypervolume, evaluations) "
                   "VALUES (?, ?, ?, ?, ?, ?)");
  q.bind(1, static_cast<long>(g.run)).bind(2, static_cast<long>(g.index)).bind(3, nlohmann::json(g.population).dump());
  q.bind(4, nlohmann::json(g.digests).dump()).bind(5, g.hypervolume).bind(6, static_cast<long>(g.evaluations)).step();
}

namespace {
Generation generation_from(const Statement& q) {
  Generation g;
  g.run = static_cast<int>(q.integer(0));
  g.index = static_cast<int>(q.integer(1));
  g.population = nlohmann::json::parse(q.text(2)).get<std::vector<std::vector<double>>>();
  g.digests = nlohmann::json::parse(q.text(3)).get<std::vector<std::string>>();
  g.hypervolume = q.real(4);
  g.evaluations = static_cast<int>(q.integer(5));
  return g;
}
}  // namespace

std::string Store::generation_columns() const {
  return fmt::format("{}, generation, population, digests, hypervolume, evaluations", has_runs_ ? "run" : "0 AS run");
}

std::optional<Generation> Store::last_generation(int run) const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, fmt::format("SELECT {} FROM generations WHERE {} = ? ORDER BY generation DESC LIMIT 1", generation_columns(),
                               has_runs_ ? "run" : "0"));
  q.bind(1, static_cast<long>(run));
  if (q.step()) return generation_from(q);
  return std::nullopt;
}

std::vector<Generation> Store::generations() const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, fmt::format("SELECT {} FROM generations ORDER BY {}generation", generation_columns(), has_runs_ ? "run, " : ""));
  std::vector<Generation> out;
  while (q.step()) out.push_back(generation_from(q));
  return out;
}

std::vector<Generation> Store::generations(int run) const {
  auto all = generations();
  std::erase_if(all, [&](const Generation& g) { return g.run != run; });
  return all;
}

void Store::put_join(int run, long position, const std::string& digest) {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, "INSERT OR REPLACE INTO joins (run, position, digest) VALUES (?, ?, ?)");
  q.bind(1, static_cast<long>(run)).bind(2, position).bind(3, digest).step();
}

std::vector<std::string> Store::joins(int run) const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  std::vector<std::string> out;
  if (!has_joins_) return out;
  Statement q(db_, "SELECT digest FROM joins WHERE run = ? ORDER BY position");
  q.bind(1, static_cast<long>(run));
  while (q.step()) out.push_back(q.text(0));
  return out;
}

void Store::put_confirmation(const Confirmation& c) {
  const std::lock_guard<std::mutex> lock(*mutex_);
  Statement q(db_, "INSERT OR REPLACE INTO confirmations (digest, case_dir, liggghts_output_fraction, liggghts_peak_wall_force, "
                   "largest_difference, objective_difference, verdict, longer_difference, variant, law) VALUES (?, ?, ?, ?, ?, ?, "
                   "?, ?, ?, ?)");
  const nlohmann::json variant = c.variant.empty() ? nlohmann::json::object()
                                                   : nlohmann::json{{"label", c.variant},
                                                                    {"measures", c.variant_measures},
                                                                    {"not_final", c.variant_not_final}};
  q.bind(1, c.digest).bind(2, c.case_dir).bind(3, c.liggghts_output_fraction).bind(4, c.liggghts_peak_wall_force);
  q.bind(5, c.largest_difference).bind(6, c.objective_difference).bind(7, c.verdict).bind(8, c.longer_difference);
  nlohmann::json law = nlohmann::json::object();
  if (!c.law.empty()) law = {{"law", c.law}, {"spread", c.law_spread}};
  if (c.law_yield) law["yield_range"] = {c.law_yield->first, c.law_yield->second};
  if (!c.not_run.empty()) law["not_run"] = c.not_run;
  q.bind(9, variant.dump()).bind(10, law.dump()).step();
}

std::vector<Confirmation> Store::confirmations() const {
  const std::lock_guard<std::mutex> lock(*mutex_);
  const auto present = columns("confirmations");
  const bool longer = std::find(present.begin(), present.end(), "longer_difference") != present.end();
  const bool variant = std::find(present.begin(), present.end(), "variant") != present.end();
  const bool law = std::find(present.begin(), present.end(), "law") != present.end();
  Statement q(db_, fmt::format("SELECT digest, case_dir, liggghts_output_fraction, liggghts_peak_wall_force, largest_difference, "
                               "objective_difference, verdict, {}, {}, {} FROM confirmations",
                               longer ? "longer_difference" : "NULL", variant ? "variant" : "'{}'", law ? "law" : "'{}'"));
  std::vector<Confirmation> out;
  while (q.step()) {
    out.push_back({q.text(0), q.text(1), q.real(2), q.maybe(3), q.real(4), q.real(5), q.text(6), q.maybe(7), "", {}, "",
                   "", {}, std::nullopt, ""});
    const auto v = nlohmann::json::parse(q.text(8), nullptr, false);
    if (v.is_object() && v.contains("label")) {
      out.back().variant = v.value("label", "");
      out.back().variant_measures = v.value("measures", std::map<std::string, double>{});
      out.back().variant_not_final = v.value("not_final", "");
    }
    const auto l = nlohmann::json::parse(q.text(9), nullptr, false);
    if (l.is_object()) {
      out.back().law = l.value("law", "");
      out.back().law_spread = l.value("spread", std::map<std::string, double>{});
      out.back().not_run = l.value("not_run", "");
      if (const auto y = l.find("yield_range"); y != l.end() && y->is_array() && y->size() == 2) {
        out.back().law_yield = std::pair{(*y)[0].get<double>(), (*y)[1].get<double>()};
      }
    }
  }
  return out;
}

}  // namespace granstack::design
