#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>

#include <fmt/compile.h>
#include <fmt/format.h>

#include <cerrno>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <cstdint>
#include <cstring>
#include <unistd.h>

namespace granstack::formats {

int DumpFrame::column(std::string_view name) const {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<std::string> dump_files_matching(const std::string& pattern) {
  namespace fs = std::filesystem;
  const fs::path p(pattern);
  const std::string name = p.filename().string();
  const auto wild = name.find_first_of("*%");
  if (wild == std::string::npos) return {pattern};
  const std::string prefix = name.substr(0, wild), suffix = name.substr(wild + 1);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::vector<std::pair<long, std::string>> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::string file = entry.path().filename().string();
    for (const char* packed : {".gz", ".zst"}) {
      const std::string ext(packed);
      if (file.size() > ext.size() && file.compare(file.size() - ext.size(), ext.size(), ext) == 0) {
        file.resize(file.size() - ext.size());
      }
    }
    if (file.size() <= prefix.size() + suffix.size() || file.compare(0, prefix.size(), prefix) != 0 ||
        file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    const std::string number = file.substr(prefix.size(), file.size() - prefix.size() - suffix.size());
    long n = 0;
    if (!parse_long(number, n) || n < 0) continue;
    found.emplace_back(n, entry.path().string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (auto& [n, path] : found) out.push_back(std::move(path));
  return out;
}

MultiFileDumpReader::MultiFileDumpReader(const std::string& pattern, bool binary, std::vector<std::string> columns)
    : pattern_(pattern), binary_(binary), per_rank_(std::filesystem::path(pattern).filename().string().find('%') !=
                                                    std::string::npos),
      columns_(std::move(columns)), files_(dump_files_matching(pattern)) {
  if (files_.empty()) {
    throw FormatError(pattern, 0, "no file matches this dump name ('*' stands for a step, '%' for an MPI rank)");
  }
  auto open_one = [&](const std::string& f) -> std::unique_ptr<DumpReader> {
    if (binary_) return std::make_unique<BinaryDumpReader>(f, columns_);
    return std::make_unique<TextDumpReader>(f);
  };
  if (per_rank_) {
    for (const auto& f : files_) open_.push_back(open_one(f));
  } else {
    open_.push_back(open_one(files_.front()));
  }
}

bool MultiFileDumpReader::next(DumpFrame& f) {
  if (!per_rank_) {
    // File after file, in step order.
    for (;;) {
      if (open_.front()->next(f)) break;
      if (++current_ == files_.size()) return false;
      open_.front() = binary_ ? std::unique_ptr<DumpReader>(std::make_unique<BinaryDumpReader>(files_[current_], columns_))
                              : std::unique_ptr<DumpReader>(std::make_unique<TextDumpReader>(files_[current_]));
    }
    if (f.step < last_step_) {
      throw FormatError(open_.front()->path(), 0,
                        fmt::format("timestep {} comes after {}: timesteps go backwards", f.step, last_step_));
    }
    last_step_ = f.step;
    ++frames_;
    return true;
  }
  // Every rank's piece of the next step, merged.
  if (!open_.front()->next(f)) {
    for (std::size_t k = 1; k < open_.size(); ++k) {
      if (open_[k]->next(piece_)) {
        throw TruncatedError(files_.front(), 0,
                             fmt::format("ends before {}, which still has a frame at step {}", files_[k], piece_.step));
      }
    }
    return false;
  }
  for (std::size_t k = 1; k < open_.size(); ++k) {
    if (!open_[k]->next(piece_)) {
      throw TruncatedError(files_[k], 0, fmt::format("ends before its piece of the frame at step {}", f.step));
    }
    if (piece_.step != f.step || piece_.columns != f.columns) {
      throw FormatError(files_[k], 0, fmt::format("holds step {} where {} holds step {} (or other columns): the "
                                                  "per-rank files do not belong together",
                                                  piece_.step, files_.front(), f.step));
    }
    f.atoms += piece_.atoms;
    f.values.insert(f.values.end(), piece_.values.begin(), piece_.values.end());
  }
  ++frames_;
  return true;
}

std::unique_ptr<DumpReader> open_dump(const std::string& path, bool binary, const std::vector<std::string>& columns) {
  if (std::filesystem::path(path).filename().string().find_first_of("*%") != std::string::npos) {
    return std::make_unique<MultiFileDumpReader>(path, binary, columns);
  }
  if (binary) return std::make_unique<BinaryDumpReader>(path, columns);
  return std::make_unique<TextDumpReader>(path);
}

void require_columns(const DumpFrame& frame, const std::vector<std::string>& names, const std::string& path) {
  std::vector<std::string> missing;
  for (const auto& n : names) {
    if (frame.column(n) < 0) missing.push_back(n);
  }
  if (!missing.empty()) {
    throw FormatError(path, frame.first_line,
                      fmt::format("the dump lacks column(s) {}: add the keyword(s) '{}' to the 'dump ... custom' line "
                                  "of the deck",
                                  fmt::join(missing, ", "), fmt::join(missing, " ")));
  }
}

}  // namespace granstack::formats
