#include "records.hpp"

#include <granstack/formats/files.hpp>

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

namespace granstack::cluster {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path records_path(const std::string& target) { return fs::path(target) / "slurm" / "submissions.json"; }

RecordedSubmission from_json(const json& e) {
  RecordedSubmission s;
  s.directory = e.at("directory").get<std::string>();
  for (const auto& a : e.at("arrays")) {
    s.arrays.push_back({a.at("job_id").get<std::string>(), a.at("first_case").get<int>(), a.at("tasks").get<int>()});
  }
  s.gather_job_id = e.value("gather_job_id", std::string());
  int tasks = 0;
  for (const auto& a : s.arrays) tasks += a.tasks;
  // Records written before cases_per_task was kept: the cases over the tasks, rounded up.
  const int cases = e.value("cases", 0);
  s.cases_per_task = e.value("cases_per_task", tasks > 0 ? (cases + tasks - 1) / tasks : 1);
  return s;
}

}  // namespace

std::vector<std::string> RecordedSubmission::cases() const {
  std::vector<std::string> out;
  std::ifstream in(fs::path(directory) / "cases.txt");
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> RecordedSubmission::case_tasks(std::size_t count) const {
  std::vector<std::pair<std::string, std::string>> out(count);
  for (const auto& a : arrays) {
    for (int t = 0; t < a.tasks; ++t) {
      for (int k = 0; k < cases_per_task; ++k) {
        const auto i = static_cast<std::size_t>(a.first_case + t * cases_per_task + k);
        if (i < out.size()) out[i] = {a.job_id, std::to_string(t)};
      }
    }
  }
  return out;
}

Records read_records(const std::string& target) {
  Records r;
  const auto path = records_path(target);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return r;
  try {
    const auto all = json::parse(formats::read_file(path));
    if (!all.is_array()) throw std::runtime_error("not a list of submissions");
    for (const auto& e : all) r.submissions.push_back(from_json(e));
  } catch (const std::exception& e) {
    r.submissions.clear();
    r.damage = fmt::format("{} is damaged ({})", path.string(), e.what());
  }
  return r;
}

std::vector<std::string> record_submission(const std::vector<std::string>& targets, const json& entry) {
  std::vector<std::string> moved;
  for (const auto& t : targets) {
    const auto path = records_path(t);
    json all = json::array();
    if (const auto existing = read_records(t); !existing.damage.empty()) {
      const auto aside = fs::path(path.string() + ".damaged-" + formats::utc_timestamp());
      fs::rename(path, aside);
      moved.push_back(fmt::format("{}; moved aside to {}, a new record begun", existing.damage, aside.string()));
    } else if (fs::exists(path)) {
      all = json::parse(formats::read_file(path));
    }
    bool replaced = false;
    for (auto& e : all) {
      if (e.value("directory", std::string()) == entry.at("directory").get<std::string>()) {
        e = entry;
        replaced = true;
      }
    }
    if (!replaced) all.push_back(entry);
    fs::create_directories(path.parent_path());
    formats::write_file_atomically(path, all.dump(2) + "\n");
  }
  return moved;
}

}  // namespace granstack::cluster
