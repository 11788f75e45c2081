#include "slurm_commands.hpp"

#include <granstack/cluster/slurm.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/os/process.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/runner/runner.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace granstack::cluster {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A word for a bash script: single-quoted, its own quotes escaped. Newlines cannot be carried.
std::string sh_quote(const std::string& s) {
  if (s.find('\n') != std::string::npos || s.find('\r') != std::string::npos) {
    throw SubmitError(fmt::format("'{}' holds a line break, which an sbatch script cannot carry; rename it", s));
  }
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// An #SBATCH value: one line, no spaces that would end it.
std::string sbatch_value(const std::string& what, const std::string& v) {
  if (v.empty() || v.find_first_of(" \t\r\n") != std::string::npos) {
    throw SubmitError(fmt::format("{} '{}' cannot stand in an #SBATCH line (empty, or with blanks)", what, v));
  }
  return v;
}

std::vector<std::string> pending_cases(const std::vector<std::string>& targets, bool force) {
  std::vector<std::string> out;
  for (const auto& d : formats::expand_case_dirs(targets)) {
    formats::read_manifest(d);  // a case, or FormatError naming what is wrong
    if (force || runner::recorded_status(d) != "done") out.push_back(fs::absolute(d).lexically_normal().string());
  }
  return out;
}

}  // namespace

std::optional<long> parse_slurm_time(const std::string& text) {
  std::vector<long> parts;
  long days = 0;
  std::string rest = text;
  if (const auto dash = text.find('-'); dash != std::string::npos) {
    if (dash == 0 || text.find_first_not_of("0123456789") != dash) return std::nullopt;
    days = std::stol(text.substr(0, dash));
    rest = text.substr(dash + 1);
  }
  std::size_t at = 0;
  for (;;) {
    const auto colon = rest.find(':', at);
    const auto field = rest.substr(at, colon == std::string::npos ? std::string::npos : colon - at);
    if (field.empty() || field.size() > 7 || field.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    parts.push_back(std::stol(field));
    if (colon == std::string::npos) break;
    at = colon + 1;
  }
  if (parts.size() > 3) return std::nullopt;
  long seconds = 0;
  if (text.find('-') != std::string::npos) {  // D-HH[:MM[:SS]]
    const long units[] = {3600, 60, 1};
    for (std::size_t i = 0; i < parts.size(); ++i) seconds += parts[i] * units[i];
  } else if (parts.size() == 1) {  // minutes
    seconds = parts[0] * 60;
  } else if (parts.size() == 2) {  // MM:SS
    seconds = parts[0] * 60 + parts[1];
  } else {
    seconds = parts[0] * 3600 + parts[1] * 60 + parts[2];
  }
  seconds += days * 86400;
  if (seconds <= 0 || seconds > 366L * 86400) return std::nullopt;
  return seconds;
}

namespace {

long max_array_size(const SubmitOptions& o, std::string& note) {
  // A dry run asks briefly: with no controller, scontrol waits (9 s and more) for nothing.
  const auto r = run_slurm({o.scontrol, "show", "config"}, o.dry_run ? 3.0 : 30.0);
  if (o.dry_run && (!r.started || r.code != 0)) {  // no cluster here: SLURM's default
    note = fmt::format("no SLURM answered ({}): assuming MaxArraySize = {}, SLURM's default", r.output.substr(0, 120),
                       kDefaultMaxArraySize);
    return kDefaultMaxArraySize;
  }
  if (!r.started) {
    throw SubmitError(fmt::format("{}; SLURM's client commands come with the Debian package slurm-client", r.output));
  }
  if (r.code != 0) throw SubmitError(fmt::format("scontrol show config failed: {}", r.output));
  for (const auto& line : lines(r.output)) {
    if (line.rfind("MaxArraySize", 0) == 0) {
      const auto eq = line.find('=');
      if (eq != std::string::npos) return std::stol(line.substr(eq + 1));
    }
  }
  return kDefaultMaxArraySize;
}

fs::path next_submission_dir(const std::string& first_target) {
  const auto base = fs::path(first_target) / "slurm";
  for (int n = 1;; ++n) {
    const auto d = base / fmt::format("submit-{}", n);
    if (!fs::exists(d)) return d;
  }
}

std::string hms(double seconds) {
  const long s = static_cast<long>(std::ceil(seconds));
  return fmt::format("{:02}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
}

std::string array_script(const Submission& sub, const ArrayJob& a, std::size_t index, const SubmitOptions& o) {
  std::string head = fmt::format("#!/bin/bash\n#SBATCH --job-name=granstack-{}\n#SBATCH --array=0-{}{}\n"
                                 "#SBATCH --ntasks={}\n#SBATCH --cpus-per-task=1\n#SBATCH --time={}\n"
                                 "#SBATCH --output={}/task-%A_%a.out\n",
                                 fs::path(sub.directory).filename().string(), a.tasks - 1,
                                 o.max_parallel > 0 ? fmt::format("%{}", o.max_parallel) : "", o.ranks,
                                 sbatch_value("--time", sub.time), sbatch_value("the submission directory", sub.directory));
  if (!o.partition.empty()) head += fmt::format("#SBATCH --partition={}\n", sbatch_value("--partition", o.partition));
  if (!o.account.empty()) head += fmt::format("#SBATCH --account={}\n", sbatch_value("--account", o.account));
  if (o.mem_mb) head += fmt::format("#SBATCH --mem={}\n", *o.mem_mb);
  std::string run = fmt::format("exec {} run --engine {} --np {}{}", sh_quote(o.granstack), o.engine, o.ranks, o.force ? " --force" : "");
  return head + fmt::format(
                    "# granstack submit: array {} of {}: task i runs lines {} + i*{} + 1 .. {} + (i+1)*{} of cases.txt,\n"
                    "# with `granstack run`, so each case is locked and gets its run.json as on a laptop.\n"
                    "set -euo pipefail\n"
                    "first=$(( {} + SLURM_ARRAY_TASK_ID * {} + 1 ))\n"
                    "last=$(( first + {} - 1 ))\n"
                    "mapfile -t cases < <(sed -n \"${{first}},${{last}}p\" {})\n"
                    "{} \"${{cases[@]}}\"\n",
                    index + 1, sub.directory, a.first_case, o.cases_per_task, a.first_case, o.cases_per_task, a.first_case,
                    o.cases_per_task, o.cases_per_task, sh_quote(sub.directory + "/cases.txt"), run);
}

std::string gather_script(const Submission& sub, const std::vector<std::string>& targets, const SubmitOptions& o) {
  std::string words;
  for (const auto& t : targets) {
    words += ' ';
    words += sh_quote(fs::absolute(t).lexically_normal().string());
  }
  return fmt::format("#!/bin/bash\n#SBATCH --job-name=granstack-{}-gather\n#SBATCH --ntasks=1\n#SBATCH --time=01:00:00\n"
                     "#SBATCH --output={}/gather.out\n{}{}"
                     "# granstack submit --gather: once the arrays have ended, the table of the targets.\n"
                     "exec {} table{} -o {}\n",
                     fs::path(sub.directory).filename().string(), sub.directory,
                     o.partition.empty() ? "" : fmt::format("#SBATCH --partition={}\n", o.partition),
                     o.account.empty() ? "" : fmt::format("#SBATCH --account={}\n", o.account), sh_quote(o.granstack), words,
                     sh_quote(sub.directory + "/table"));
}

// sbatch --parsable; returns the job id.
std::string sbatch(const std::string& script, const std::vector<std::string>& extra, const SubmitOptions& o) {
  std::vector<std::string> argv{o.sbatch, "--parsable"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  argv.insert(argv.end(), o.sbatch_args.begin(), o.sbatch_args.end());
  argv.push_back(script);
  const auto r = run_slurm(argv);
  if (!r.started) throw SubmitError(fmt::format("{}; sbatch comes with the Debian package slurm-client", r.output));
  const auto out = lines(r.output);
  if (r.code != 0 || out.empty()) throw SubmitError(fmt::format("sbatch refused {}: {}", script, r.output));
  return out.back().substr(0, out.back().find(';'));
}

json record(const Submission& s) {
  json arrays = json::array();
  for (const auto& a : s.arrays) arrays.push_back({{"script", a.script}, {"job_id", a.job_id}, {"first_case", a.first_case}, {"tasks", a.tasks}});
  return {{"directory", s.directory}, {"submitted", formats::utc_timestamp()}, {"cases", s.cases.size()},
          {"arrays", arrays}, {"gather_job_id", s.gather_job_id}, {"time", s.time}, {"max_array_size", s.max_array_size}};
}

void append_record(const std::string& target, const json& entry) {
  const auto path = fs::path(target) / "slurm" / "submissions.json";
  json all = json::array();
  if (fs::exists(path)) all = json::parse(formats::read_file(path));
  all.push_back(entry);
  fs::create_directories(path.parent_path());
  formats::write_file_atomically(path, all.dump(2) + "\n");
}

}  // namespace

std::string estimate_task_time(const std::vector<std::string>& case_dirs, int ranks) {
  double seconds = 0.0;
  for (const auto& d : case_dirs) {
    const auto stack = model::Stack::build(formats::read_manifest(d).spec);
    seconds += model::estimate_cost(stack, model::resolve(stack)).liggghts_seconds;
  }
  return hms(std::max(kMinTaskSeconds, kTimeSafety * seconds / std::max(1, ranks)));
}

Submission submit(const std::vector<std::string>& targets, const SubmitOptions& o) {
  if (targets.empty()) throw SubmitError("name the cases or sweeps to submit");
  if (o.cases_per_task < 1) throw SubmitError("--cases-per-task must be at least 1");
  Submission sub;
  sub.cases = pending_cases(targets, o.force);
  if (sub.cases.empty()) return sub;
  if (!o.dry_run && !os::find_program(o.sbatch)) {
    throw SubmitError(fmt::format("{} is not on PATH: install SLURM's client commands (Debian package slurm-client) or "
                                  "submit from a machine that has them; --dry-run writes the scripts without submitting",
                                  o.sbatch));
  }
  sub.max_array_size = max_array_size(o, sub.note);
  const long tasks = (static_cast<long>(sub.cases.size()) + o.cases_per_task - 1) / o.cases_per_task;
  for (long first_task = 0; first_task < tasks; first_task += sub.max_array_size) {
    const long n = std::min(sub.max_array_size, tasks - first_task);
    sub.arrays.push_back({"", "", static_cast<int>(first_task * o.cases_per_task), static_cast<int>(n)});
  }
  std::vector<std::string> first_task_cases(sub.cases.begin(),
                                            sub.cases.begin() + std::min<long>(o.cases_per_task, static_cast<long>(sub.cases.size())));
  sub.time = o.time.empty() ? estimate_task_time(first_task_cases, o.ranks) : o.time;
  const auto dir = next_submission_dir(fs::absolute(targets.front()).lexically_normal().string());
  sub.directory = dir.string();
  // Everything is written (and every path checked for the scripts) before anything is submitted.
  std::vector<std::pair<fs::path, std::string>> files;
  std::string list;
  for (const auto& c : sub.cases) {
    sh_quote(c);  // a case list line holds no line break either
    list += c + "\n";
  }
  files.emplace_back(dir / "cases.txt", list);
  for (std::size_t i = 0; i < sub.arrays.size(); ++i) {
    sub.arrays[i].script = (dir / fmt::format("array-{}.sbatch", i + 1)).string();
    files.emplace_back(sub.arrays[i].script, array_script(sub, sub.arrays[i], i, o));
  }
  if (o.gather) {
    sub.gather_script = (dir / "gather.sbatch").string();
    files.emplace_back(sub.gather_script, gather_script(sub, targets, o));
  }
  fs::create_directories(dir);
  for (const auto& [path, text] : files) formats::write_file_atomically(path, text);
  if (o.dry_run) return sub;
  std::vector<std::string> ids;
  for (auto& a : sub.arrays) {
    a.job_id = sbatch(a.script, {}, o);
    ids.push_back(a.job_id);
  }
  if (o.gather) sub.gather_job_id = sbatch(sub.gather_script, {fmt::format("--dependency=afterany:{}", fmt::join(ids, ":"))}, o);
  const auto entry = record(sub);
  formats::write_file_atomically(dir / "submission.json", entry.dump(2) + "\n");
  for (const auto& t : targets) append_record(t, entry);
  return sub;
}

}  // namespace granstack::cluster
