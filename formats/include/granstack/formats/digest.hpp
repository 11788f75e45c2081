#pragma once
// SHA-256 digests (OpenSSL's), in lower-case hexadecimal as `sha256sum` prints them, so a user
// can check a recorded digest by hand.
#include <filesystem>
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

}  // namespace granstack::formats
