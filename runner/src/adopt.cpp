// granstack adopt: a case whose deck a user ran with LIGGGHTS by hand (`liggghts -in in.stack` in
// the case) or by scripts of their own, taken as the case's run once its outputs are shown to be
// that deck's: the deck as generated, its log's executed commands held to the case
// (deck_check.hpp), a whole run in the log, the dump's frames and the series' rows where the
// deck writes them. Then run.json records the run, with its digests, as `run` would.
#include "deck_check.hpp"

#include <granstack/formats/deck.hpp>
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/log.hpp>
#include <granstack/formats/run_digests.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/model/version.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>

namespace granstack::runner {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// What the log says of the run: a LIGGGHTS that ran the case's steps to the end. Fills `record`.
void check_log(const formats::Case& c, const std::string& path, json& record) {
  const auto log = formats::read_log(path);
  const auto& d = c.derived();
  if (log.version().find("LIGGGHTS") == std::string::npos) {
    throw formats::FormatError(path, 1, "is not a LIGGGHTS log (no LIGGGHTS banner on its first line): adopt takes "
                                        "the log LIGGGHTS writes where it runs the case's deck (log.liggghts)");
  }
  if (!log.errors().empty()) throw formats::FormatError(path, 0, "the run stopped with " + log.errors().front());
  if (log.lost_atoms()) throw formats::FormatError(path, 0, "LIGGGHTS lost atoms in this run");
  if (log.stopped_by_signal()) throw formats::FormatError(path, 0, "LIGGGHTS was stopped by a signal before the end");
  const auto& loop = log.loop_time();
  const bool blow_end = c.spec().stop == model::StopRule::blow_end;
  if (!loop || (blow_end ? loop->steps > d.steps || loop->steps % d.dump_every != 0 : loop->steps != d.steps)) {
    throw formats::FormatError(path, 0, fmt::format("the log holds {} steps, where the case runs {}{}: the run did not "
                                                    "finish, or the log is another run's",
                                                    loop ? std::to_string(loop->steps) : "no finished run of",
                                                    blow_end ? "at most " : "", d.steps));
  }
  record["liggghts_version"] = log.version();
  record["steps"] = loop->steps;
  record["atoms"] = loop->atoms;
  record["procs"] = loop->procs;
  record["loop_seconds"] = loop->seconds;
  if (!log.warnings().empty()) record["warnings"] = log.warnings();
}

// The dump holds a frame every dump_every steps from 0 to the run's last step, and nothing else.
void check_dump(const formats::Case& c, long steps) {
  const auto path = formats::find_dump(c.dir(), c.files().dump);
  const auto reader = formats::open_dump(path, c.spec().dump_format == model::DumpFormat::binary, c.files().dump_columns);
  formats::DumpFrame frame;
  long expected = 0;
  while (reader->next(frame)) {
    if (expected > steps) {
      throw formats::FormatError(path, 0, fmt::format("holds a frame of step {}, after the run's last step ({}): the "
                                                      "dump is not this run's",
                                                      frame.step, steps));
    }
    if (frame.step != expected) {
      throw formats::FormatError(path, 0, fmt::format("holds a frame of step {} where the deck writes step {}: the dump "
                                                      "is not this run's whole dump",
                                                      frame.step, expected));
    }
    expected += c.derived().dump_every;
  }
  if (expected <= steps) {
    throw formats::FormatError(path, 0, fmt::format("ends before step {}, which the run reached: the dump is cut short",
                                                    expected));
  }
}

// The series holds a row every series_every steps to the run's last step.
void check_series(const formats::Case& c, long steps) {
  const auto path = formats::find_dump(c.dir(), c.files().series);
  const auto series = formats::read_series(path);
  const long every = c.derived().series_every;
  if (static_cast<long>(series.rows.size()) != steps / every) {
    throw formats::FormatError(path, 0, fmt::format("has {} rows where the run writes {} (every {} steps to step {}): "
                                                    "the series is not this run's whole series",
                                                    series.rows.size(), steps / every, every, steps));
  }
  for (std::size_t i = 0; i < series.rows.size(); ++i) {
    if (series.rows[i].empty() || series.rows[i][0] != static_cast<double>((static_cast<long>(i) + 1) * every)) {
      throw formats::FormatError(path, 0, fmt::format("row {} is not step {}", i + 1, (static_cast<long>(i) + 1) * every));
    }
  }
}

RunOutcome adopt_one(const std::string& dir, bool force) {
  RunOutcome out;
  out.case_dir = dir;
  try {
    const auto c = formats::Case::open(dir);
    const auto lock = c.lock("granstack adopt");
    const auto earlier = c.run_record();
    if (earlier.done() && !force) {
      out.status = RunStatus::skipped;
      out.message = "it has a finished run (run.json says done); pass --force to adopt its outputs anew";
      return out;
    }
    formats::check_rendered_files(c.dir(), c.manifest());
    const auto& files = c.files();
    const auto log = c.path(files.log);
    if (!fs::exists(log)) {
      throw formats::FormatError(log.string(), 0, fmt::format("missing: run the deck in the case's folder with "
                                                              "'liggghts -in {}' (LIGGGHTS writes its log there), then "
                                                              "adopt it",
                                                              files.deck));
    }
    json record{{"status", "done"}, {"engine", "liggghts"}, {"run_by", "hand"}, {"adopted", formats::utc_timestamp()},
                {"granstack_version", std::string(version())}};
    check_log(c, log.string(), record);
    if (const auto why = hold_run(c, files, generator::default_deck(c.manifest()), "templates/in.granstack.tmpl", record);
        !why.empty()) {
      throw formats::FormatError(log.string(), 0, why);
    }
    const long steps = record.at("steps").get<long>();
    check_dump(c, steps);
    check_series(c, steps);
    record["digests"] = formats::run_digests(c);
    record["finished"] = record["adopted"];
    c.write_run_record(record);
    out.status = RunStatus::done;
    out.loop_seconds = record.value("loop_seconds", 0.0);
  } catch (const std::exception& e) {
    out.status = RunStatus::failed;
    out.message = e.what();
  }
  return out;
}

}  // namespace

std::vector<RunOutcome> adopt_cases(const std::vector<std::string>& case_dirs, bool force) {
  std::vector<RunOutcome> outcomes;
  for (const auto& d : case_dirs) outcomes.push_back(adopt_one(d, force));
  return outcomes;
}

}  // namespace granstack::runner
