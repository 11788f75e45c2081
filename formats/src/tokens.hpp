#pragma once
// Tokens of a text dump's atom line, read 8 bytes at a time (the text reader's inner loop).
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace granstack::formats::tokens {

// Skips the next blank-separated word of [p, end); nullptr when there is none.
inline const char* skip_word(const char* p, const char* end) {
  while (p < end && (*p == ' ' || *p == '\t')) ++p;
  if (p == end) return nullptr;
  while (p < end && *p != ' ' && *p != '\t') ++p;
  return p;
}

// The length of the token at p when the token at q has the same bytes and the same delimiter
// after it (a byte below '!'), else 0. Reads up to 32 bytes at p and at q; tokens of 32 bytes
// or more count as different.
inline std::size_t same_token(const char* p, const char* q) {
  constexpr std::uint64_t kOnes = 0x0101010101010101ULL, kHigh = 0x8080808080808080ULL;
  for (std::size_t n = 0; n < 32; n += 8) {
    std::uint64_t a = 0, b = 0;
    std::memcpy(&a, p + n, 8);
    std::memcpy(&b, q + n, 8);
    const std::uint64_t diff = a ^ b;
    // Bytes below 0x21 (space, tab, line ends): the lowest flagged byte is exact.
    const std::uint64_t delimiters = (a - kOnes * 0x21) & ~a & kHigh;
    if (delimiters != 0) {
      const auto d = static_cast<std::size_t>(__builtin_ctzll(delimiters)) / 8;  // little-endian byte index
      const std::uint64_t through = d == 7 ? ~std::uint64_t{0} : (std::uint64_t{1} << (8 * (d + 1))) - 1;
      return (diff & through) == 0 && n + d > 0 ? n + d : 0;
    }
    if (diff != 0) return 0;
  }
  return 0;
}

// How many bytes a and b have in common at their start (at most n), 8 at a time.
inline std::size_t common_prefix(const char* a, const char* b, std::size_t n) {
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8) {
    std::uint64_t x = 0, y = 0;
    std::memcpy(&x, a + k, 8);
    std::memcpy(&y, b + k, 8);
    if (x != y) return k + static_cast<std::size_t>(__builtin_ctzll(x ^ y)) / 8;
  }
  while (k < n && a[k] == b[k]) ++k;
  return k;
}

// How many bytes the n bytes before a_end and before b_end have in common at their end, 8 at a time.
inline std::size_t common_suffix(const char* a_end, const char* b_end, std::size_t n) {
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8) {
    std::uint64_t x = 0, y = 0;
    std::memcpy(&x, a_end - k - 8, 8);
    std::memcpy(&y, b_end - k - 8, 8);
    if (x != y) return k + static_cast<std::size_t>(__builtin_clzll(x ^ y)) / 8;  // little-endian: the last byte is the top one
  }
  while (k < n && a_end[-1 - static_cast<std::ptrdiff_t>(k)] == b_end[-1 - static_cast<std::ptrdiff_t>(k)]) ++k;
  return k;
}

// The length of the token at p (up to the first byte below '!'), read 8 bytes at a time; 0 when
// it is 32 bytes or longer. Reads up to 32 bytes at p.
inline std::size_t token_length(const char* p) {
  constexpr std::uint64_t kOnes = 0x0101010101010101ULL, kHigh = 0x8080808080808080ULL;
  for (std::size_t n = 0; n < 32; n += 8) {
    std::uint64_t a = 0;
    std::memcpy(&a, p + n, 8);
    const std::uint64_t delimiters = (a - kOnes * 0x21) & ~a & kHigh;
    if (delimiters != 0) return n + static_cast<std::size_t>(__builtin_ctzll(delimiters)) / 8;
  }
  return 0;
}

}  // namespace granstack::formats::tokens
