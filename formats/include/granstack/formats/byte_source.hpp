#pragma once
// The bytes of a file, decompressed on the fly when it is gzip or zstd (told by its first
// bytes, whatever its name), so every reader takes plain and compressed files alike.
#include <cstddef>
#include <memory>
#include <string>

namespace granstack::formats {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  // Up to `n` bytes into `buffer`; 0 at the end. Throws FormatError on corrupt compressed data.
  virtual std::size_t read(char* buffer, std::size_t n) = 0;
  // "plain", "gzip" or "zstd".
  virtual const char* kind() const = 0;
  // The bytes left, when that is known without reading them (a plain file); else -1.
  virtual long remaining() const { return -1; }
  // Passes over `n` bytes: seeks when remaining() is known (and at least n), else reads them.
  virtual void skip(std::size_t n);
};

// Throws FormatError when the file cannot be opened.
std::unique_ptr<ByteSource> open_bytes(const std::string& path);

}  // namespace granstack::formats
