#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/os/interrupt.hpp>

#include <fmt/format.h>
#include <openssl/evp.h>

#include <array>
#include <algorithm>
#include <optional>
#include <string_view>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>

namespace granstack::formats {

namespace {

using Context = std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)>;

Context new_context() {
  Context ctx(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("OpenSSL cannot start a SHA-256 digest");
  }
  return ctx;
}

std::string finish(EVP_MD_CTX* ctx) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
  unsigned int n = 0;
  if (EVP_DigestFinal_ex(ctx, md.data(), &n) != 1) throw std::runtime_error("OpenSSL cannot finish a SHA-256 digest");
  std::string hex;
  hex.reserve(2 * n);
  for (unsigned int i = 0; i < n; ++i) hex += fmt::format("{:02x}", md[i]);
  return hex;
}

}  // namespace

std::string sha256_hex(std::string_view bytes) {
  auto ctx = new_context();
  EVP_DigestUpdate(ctx.get(), bytes.data(), bytes.size());
  return finish(ctx.get());
}

std::string sha256_file(const std::filesystem::path& path) {
  require_regular_file(path.string());
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path.string(), 0, fmt::format("cannot open: {}", std::strerror(errno)));
  auto ctx = new_context();
  std::string buffer(std::size_t{1} << 20, '\0');
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto got = in.gcount();
    if (got > 0) EVP_DigestUpdate(ctx.get(), buffer.data(), static_cast<std::size_t>(got));
  }
  if (in.bad()) throw FormatError(path.string(), 0, fmt::format("cannot read: {}", std::strerror(errno)));
  return finish(ctx.get());
}

namespace {
// A plain file's digest straight from the page cache (mapped: no copy into a buffer), in pieces so
// that a stop request is seen; nullopt where it cannot be mapped (the caller reads it instead).
std::optional<std::string> sha256_mapped(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0) {
    ::close(fd);
    return std::nullopt;
  }
  const auto size = static_cast<std::size_t>(st.st_size);
  void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (map == MAP_FAILED) return std::nullopt;
  ::madvise(map, size, MADV_SEQUENTIAL);
  const auto* bytes = static_cast<const unsigned char*>(map);
  auto ctx = new_context();
  constexpr std::size_t kPiece = std::size_t{16} << 20;
  for (std::size_t at = 0; at < size; at += kPiece) {
    if (os::interrupt_signal() != 0) {
      ::munmap(map, size);
      throw std::runtime_error(fmt::format("{}: digest stopped by a signal", path.string()));
    }
    EVP_DigestUpdate(ctx.get(), bytes + at, std::min(kPiece, size - at));
  }
  ::munmap(map, size);
  return finish(ctx.get());
}
}  // namespace

std::string sha256_content(const std::filesystem::path& path) {
  const auto source = open_bytes(path.string());
  if (std::string_view(source->kind()) == "plain") {
    if (auto mapped = sha256_mapped(path)) return *mapped;
  }
  auto ctx = new_context();
  std::string buffer(std::size_t{1} << 20, '\0');
  for (std::size_t got; (got = source->read(buffer.data(), buffer.size())) > 0;) {
    // A digest of gigabytes is a long pass: a stop request ends it (reduce digests beside its reading).
    if (os::interrupt_signal() != 0) throw std::runtime_error(fmt::format("{}: digest stopped by a signal", path.string()));
    EVP_DigestUpdate(ctx.get(), buffer.data(), got);
  }
  return finish(ctx.get());
}

}  // namespace granstack::formats
