#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>
#include <vector>
#include <zlib.h>
#include <zstd.h>

namespace granstack::formats {

namespace {

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

class PlainSource final : public ByteSource {
 public:
  explicit PlainSource(File file) : file_(std::move(file)) {
    struct stat st {};
    if (::fstat(::fileno(file_.get()), &st) == 0 && S_ISREG(st.st_mode)) size_ = static_cast<long>(st.st_size);
  }
  std::size_t read(char* buffer, std::size_t n) override { return std::fread(buffer, 1, n, file_.get()); }
  const char* kind() const override { return "plain"; }
  long remaining() const override { return size_ < 0 ? -1 : std::max(0L, size_ - static_cast<long>(::ftello(file_.get()))); }
  void skip(std::size_t n) override {
    if (size_ < 0 || ::fseeko(file_.get(), static_cast<off_t>(n), SEEK_CUR) != 0) ByteSource::skip(n);
  }

 private:
  File file_;
  long size_ = -1;  // of a regular file
};

class GzipSource final : public ByteSource {
 public:
  GzipSource(const std::string& path) : path_(path), file_(gzopen(path.c_str(), "rb")) {
    if (file_ == nullptr) throw FormatError(path, 0, "cannot open as gzip");
    gzbuffer(file_, 1 << 20);
  }
  ~GzipSource() override { gzclose(file_); }
  std::size_t read(char* buffer, std::size_t n) override {
    const int got = gzread(file_, buffer, static_cast<unsigned>(std::min<std::size_t>(n, 1u << 30)));
    if (got < 0) {
      int code = 0;
      const char* msg = gzerror(file_, &code);
      // Cut short (a run killed while compressing): the end of the data, which the dump
      // readers report as a truncated frame with its context.
      if (code == Z_BUF_ERROR) return 0;
      throw FormatError(path_, 0, fmt::format("corrupt gzip data: {}", msg != nullptr ? msg : "unknown error"));
    }
    return static_cast<std::size_t>(got);
  }
  const char* kind() const override { return "gzip"; }

 private:
  std::string path_;
  gzFile file_;
};

class ZstdSource final : public ByteSource {
 public:
  ZstdSource(const std::string& path, File file)
      : path_(path), file_(std::move(file)), stream_(ZSTD_createDStream()), in_(ZSTD_DStreamInSize()) {
    ZSTD_initDStream(stream_);
  }
  ~ZstdSource() override { ZSTD_freeDStream(stream_); }
  // zstd fills kStep bytes at a time (into the caller's buffer, or into a block of its own that
  // serves smaller reads), whatever the caller asks for: zstd gives none of what is left of a
  // frame whose checksum fails, so how much comes before corrupt data depends only on the file.
  std::size_t read(char* buffer, std::size_t n) override {
    if (next_ == filled_ && n >= kStep) return decompress(buffer);  // straight in, kStep bytes at most
    if (next_ == filled_) {
      next_ = 0;
      filled_ = decompress(block_.data());
      if (filled_ == 0) return 0;
    }
    const std::size_t k = std::min(n, filled_ - next_);
    std::memcpy(buffer, block_.data() + next_, k);
    next_ += k;
    return k;
  }
  const char* kind() const override { return "zstd"; }

 private:
  std::string path_;
  File file_;
  ZSTD_DStream* stream_;
  std::vector<char> in_;
  ZSTD_inBuffer input_{nullptr, 0, 0};
  static constexpr std::size_t kStep = 1 << 16;
  std::vector<char> block_ = std::vector<char>(kStep);
  std::size_t next_ = 0, filled_ = 0;  // block_[next_, filled_) is still to be read

  // Up to kStep next bytes into `to` (0 at the end). Throws FormatError on corrupt data.
  std::size_t decompress(char* to) {
    ZSTD_outBuffer out{to, kStep, 0};
    while (out.pos == 0) {
      if (input_.pos == input_.size) {
        const std::size_t got = std::fread(in_.data(), 1, in_.size(), file_.get());
        if (got == 0) return 0;  // the end, or cut short: the dump readers report a truncated frame
        input_ = {in_.data(), got, 0};
      }
      const std::size_t rc = ZSTD_decompressStream(stream_, &out, &input_);
      if (ZSTD_isError(rc)) throw FormatError(path_, 0, fmt::format("corrupt zstd data: {}", ZSTD_getErrorName(rc)));
    }
    return out.pos;
  }
};

}  // namespace

void ByteSource::skip(std::size_t n) {
  char sink[1 << 14];
  while (n > 0) {
    const std::size_t got = read(sink, std::min(n, sizeof sink));
    if (got == 0) return;
    n -= got;
  }
}

std::unique_ptr<ByteSource> open_bytes(const std::string& path) {
  require_regular_file(path);
  File file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw FormatError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  unsigned char magic[4] = {0, 0, 0, 0};
  const std::size_t got = std::fread(magic, 1, 4, file.get());
  std::rewind(file.get());
  if (got >= 2 && magic[0] == 0x1f && magic[1] == 0x8b) return std::make_unique<GzipSource>(path);
  if (got == 4 && magic[0] == 0x28 && magic[1] == 0xb5 && magic[2] == 0x2f && magic[3] == 0xfd) {
    return std::make_unique<ZstdSource>(path, std::move(file));
  }
  return std::make_unique<PlainSource>(std::move(file));
}

}  // namespace granstack::formats
