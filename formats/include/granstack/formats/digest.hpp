#pragma once
// SHA-256 digests (OpenSSL's), in lower-case hexadecimal as `sha256sum` prints them, so a user
// can check a recorded digest by hand.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace granstack::formats {

std::string sha256_hex(std::string_view bytes);
// The digest of a whole regular file, read in pieces. Throws FormatError naming the file when
// it cannot be read.
std::string sha256_file(const std::filesystem::path& path);
// The digest of a file's content as the readers see it: decompressed when it is gzip or zstd
// (formats::open_bytes), so a file and its compressed copy have the same one.
std::string sha256_content(const std::filesystem::path& path);
// The XXH3 128-bit hash of a file's content as the readers see it (decompressed, as above), in the
// hexadecimal `xxhsum -H2` prints: what a run records of its outputs, checked wherever they are
// read. A non-cryptographic hash: it tells a file apart from any other by accident (a copy from
// another case, an edit, a cut), at the speed of reading the file, where SHA-256 took a third of
// reduce's time; it does not stand against forgery, which could edit run.json as well.
std::string xxh128_content(const std::filesystem::path& path);

// The same hash over bytes given in order, piece by piece (reduce digests a dump from the pieces
// its threads read to parse it, instead of reading the file a second time).
class Xxh128 {
 public:
  Xxh128();
  ~Xxh128();
  Xxh128(const Xxh128&) = delete;
  Xxh128& operator=(const Xxh128&) = delete;
  void update(const char* bytes, std::size_t n);
  std::string hex() const;  // of every byte given so far

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace granstack::formats
