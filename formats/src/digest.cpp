#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/digest.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/os/interrupt.hpp>

#include <fmt/format.h>
#include <openssl/evp.h>
#include <xxhash.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <memory>
#include <stdexcept>
#include <sys/stat.h>
#include <time.h>

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

// Bytes as the lower-case hexadecimal sha256sum and xxhsum print.
std::string lower_hex(const unsigned char* bytes, std::size_t n) {
  std::string hex;
  hex.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) hex += fmt::format("{:02x}", bytes[i]);
  return hex;
}

std::string finish(EVP_MD_CTX* ctx) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
  unsigned int n = 0;
  if (EVP_DigestFinal_ex(ctx, md.data(), &n) != 1) throw std::runtime_error("OpenSSL cannot finish a SHA-256 digest");
  return lower_hex(md.data(), n);
}

}  // namespace

// Files are digested in pieces of this many bytes: small enough that a fresh buffer's pages cost
// little to touch (run digests a case's deck, data file and outputs after every run), large
// enough that the reads are few.
constexpr std::size_t kDigestPiece = std::size_t{256} << 10;

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
  std::unique_ptr<char[]> buffer(new char[kDigestPiece]);  // not zeroed: every byte is read before use
  while (in) {
    in.read(buffer.get(), static_cast<std::streamsize>(kDigestPiece));
    const auto got = in.gcount();
    if (got > 0) EVP_DigestUpdate(ctx.get(), buffer.get(), static_cast<std::size_t>(got));
  }
  if (in.bad()) throw FormatError(path.string(), 0, fmt::format("cannot read: {}", std::strerror(errno)));
  return finish(ctx.get());
}

namespace {

// Every byte of a file's content (decompressed), in order. (Read, never mapped: a file cut short
// while mapped would end the process with SIGBUS.)
template <typename Update>
void for_content_pieces(const std::filesystem::path& path, Update update) {
  const auto source = open_bytes(path.string());
  std::unique_ptr<char[]> buffer(new char[kDigestPiece]);  // not zeroed: every byte is read before use
  for (std::size_t got; (got = source->read(buffer.get(), kDigestPiece)) > 0;) {
    if (os::interrupt_signal() != 0) throw std::runtime_error(fmt::format("{}: digest stopped by a signal", path.string()));
    update(buffer.get(), got);
  }
}
}  // namespace

struct Xxh128::State {
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> xxh{XXH3_createState(), &XXH3_freeState};
};

Xxh128::Xxh128() : state_(std::make_unique<State>()) {
  if (!state_->xxh || XXH3_128bits_reset(state_->xxh.get()) != XXH_OK) throw std::runtime_error("xxHash cannot start a digest");
}

Xxh128::~Xxh128() = default;

void Xxh128::update(const char* bytes, std::size_t n) { XXH3_128bits_update(state_->xxh.get(), bytes, n); }

std::string Xxh128::hex() const {
  XXH128_canonical_t canonical;
  XXH128_canonicalFromHash(&canonical, XXH3_128bits_digest(state_->xxh.get()));
  return lower_hex(canonical.digest, sizeof canonical.digest);
}

namespace {

// What identifies a file's content without reading it, as far as this process can tell: the same
// inode, size, modification and change time. Any write, truncation or replacement changes the
// change time (which no user can set), but to the kernel's coarse clock: a digest is remembered
// only of a file last changed kMemoSettledNs before its reading ended, so that a later change cannot
// share its change time.
struct FileState {
  dev_t dev = 0;
  ino_t ino = 0;
  off_t size = 0;
  timespec mtime{}, ctime{};
  bool operator==(const FileState& o) const {
    return dev == o.dev && ino == o.ino && size == o.size && mtime.tv_sec == o.mtime.tv_sec &&
           mtime.tv_nsec == o.mtime.tv_nsec && ctime.tv_sec == o.ctime.tv_sec && ctime.tv_nsec == o.ctime.tv_nsec;
  }
};

constexpr long kMemoSettledNs = 100'000'000;

std::optional<FileState> file_state(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return FileState{st.st_dev, st.st_ino, st.st_size, st.st_mtim, st.st_ctim};
}

long long ns(const timespec& t) { return static_cast<long long>(t.tv_sec) * 1'000'000'000LL + t.tv_nsec; }

// The digests this process took of files (a run digests its outputs, and reproduce's reduce checks
// them seconds later: read once, not twice).
struct Memo {
  std::mutex mutex;
  std::map<std::string, std::pair<FileState, std::string>> digests;
};
Memo& memo() {
  static Memo m;
  return m;
}

}  // namespace

std::string xxh128_content(const std::filesystem::path& path) {
  const auto key = std::filesystem::absolute(path).lexically_normal().string();
  const auto before = file_state(path);
  if (before) {
    const std::lock_guard lock(memo().mutex);
    const auto it = memo().digests.find(key);
    if (it != memo().digests.end() && it->second.first == *before) return it->second.second;
  }
  Xxh128 digest;
  for_content_pieces(path, [&](const char* bytes, std::size_t n) { digest.update(bytes, n); });
  auto hex = digest.hex();
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  const auto after = file_state(path);
  if (before && after && *after == *before && ns(now) - ns(after->ctime) > kMemoSettledNs) {
    const std::lock_guard lock(memo().mutex);
    memo().digests[key] = {*after, hex};
  }
  return hex;
}

std::string sha256_content(const std::filesystem::path& path) {
  auto ctx = new_context();
  for_content_pieces(path, [&](const char* bytes, std::size_t n) { EVP_DigestUpdate(ctx.get(), bytes, n); });
  return finish(ctx.get());
}

}  // namespace granstack::formats
