#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>

#include <fmt/chrono.h>
#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <sys/stat.h>

namespace granstack::formats {

void close_written(std::FILE* file, const std::string& path) {
  const bool flushed = std::fflush(file) == 0 && std::ferror(file) == 0;
  const int flush_error = errno;
  const bool closed = std::fclose(file) == 0;
  if (!flushed || !closed) {
    throw IoError(fmt::format("{}: cannot write: {}", path, std::strerror(flushed ? errno : flush_error)));
  }
}

namespace {
// Writes `text` to PATH.tmp; throws IoError naming `path` (the temporary removed) when it cannot.
std::string write_temporary(const std::filesystem::path& path, std::string_view text) {
  const auto tmp = path.string() + ".tmp";
  std::ofstream out(tmp, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) {
    const int e = errno;
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw IoError(fmt::format("{}: cannot write: {}", path.string(), std::strerror(e)));
  }
  return tmp;
}
}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view text) {
  std::filesystem::rename(write_temporary(path, text), path);
}

void write_files_atomically(const std::filesystem::path& dir,
                            const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::string> written;
  try {
    for (const auto& [name, text] : files) written.push_back(write_temporary(dir / name, text));
  } catch (...) {
    std::error_code ec;
    for (const auto& tmp : written) std::filesystem::remove(tmp, ec);
    throw;
  }
  for (std::size_t i = 0; i < files.size(); ++i) std::filesystem::rename(written[i], dir / files[i].first);
}

std::string why_not_a_regular_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int error = errno;
    // A copy compressed by a program granstack does not read (it reads gzip and zstd).
    for (const auto& [suffix, program] : {std::pair{".xz", "xz"}, std::pair{".bz2", "bzip2"}, std::pair{".lz4", "lz4"},
                                          std::pair{".lzma", "xz"}, std::pair{".7z", "7z"}, std::pair{".zip", "unzip"}}) {
      if (::stat((path + suffix).c_str(), &st) == 0) {
        return fmt::format("is missing, and {}{} is there, compressed with {}, which granstack does not read: decompress it "
                           "({} -d), or compress the file with zstd or gzip, which it reads",
                           path, suffix, program, program);
      }
    }
    return error == ENOENT ? std::string("is missing") : fmt::format("cannot be opened: {}", std::strerror(error));
  }
  if (S_ISREG(st.st_mode)) return "";
  const char* kind = S_ISDIR(st.st_mode)   ? "a directory"
                     : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                     : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a regular file";
  return fmt::format("is {}: granstack reads only regular files; put the file itself there", kind);
}

void require_regular_file(const std::string& path) {
  if (const auto why = why_not_a_regular_file(path); !why.empty()) throw FormatError(path, 0, why);
}

std::string read_file(const std::filesystem::path& path) {
  require_regular_file(path.string());
  std::unique_ptr<std::FILE, decltype(&std::fclose)> in(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!in) throw IoError(fmt::format("{}: cannot open: {}", path.string(), std::strerror(errno)));
  // One read of the size the file has now (a log of a blow-end run is megabytes), then on until
  // its end, should it have grown.
  struct stat st {};
  std::string text(::fstat(fileno(in.get()), &st) == 0 && st.st_size > 0 ? static_cast<std::size_t>(st.st_size) + 1 : 4096,
                   '\0');
  std::size_t got = 0;
  for (std::size_t n; (n = std::fread(text.data() + got, 1, text.size() - got, in.get())) > 0;) {
    got += n;
    if (got == text.size()) text.resize(2 * text.size());
  }
  if (std::ferror(in.get()) != 0) throw IoError(fmt::format("{}: cannot read: {}", path.string(), std::strerror(errno)));
  text.resize(got);
  return text;
}

std::string utc_timestamp() {
  return fmt::format("{:%Y-%m-%dT%H:%M:%SZ}",
                     fmt::gmtime(std::chrono::system_clock::to_time_t(std::chrono::system_clock::now())));
}

}  // namespace granstack::formats
