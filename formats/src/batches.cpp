#include <granstack/formats/batches.hpp>
#include <granstack/formats/error.hpp>

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <optional>

namespace granstack::formats {

namespace {

// Bytes already read, then the rest of a source.
class PrefixedSource final : public ByteSource {
 public:
  PrefixedSource(std::string prefix, std::unique_ptr<ByteSource> rest) : prefix_(std::move(prefix)), rest_(std::move(rest)) {}
  std::size_t read(char* buffer, std::size_t n) override {
    if (used_ < prefix_.size()) {
      const std::size_t k = std::min(n, prefix_.size() - used_);
      std::memcpy(buffer, prefix_.data() + used_, k);
      used_ += k;
      return k;
    }
    return rest_->read(buffer, n);
  }
  const char* kind() const override { return rest_->kind(); }

 private:
  std::string prefix_;
  std::size_t used_ = 0;
  std::unique_ptr<ByteSource> rest_;
};

// A piece is never cut mid-frame; a frame larger than this (or a file with no frame boundary in
// this many bytes, such as a binary file read as text) is read frame by frame instead.
constexpr std::size_t kLargestPiece = std::size_t{64} << 20;
constexpr std::string_view kFrameStart = "ITEM: TIMESTEP";

// Grows a batch's text buffer to hold `n` bytes, keeping what it holds.
void reserve_text(FrameBatch& batch, std::size_t n) {
  if (n <= batch.text_capacity) return;
  const std::size_t capacity = std::max(n, 2 * batch.text_capacity);
  std::unique_ptr<char[]> bigger(new char[capacity]);
  if (batch.text_size > 0) std::memcpy(bigger.get(), batch.text.get(), batch.text_size);
  batch.text = std::move(bigger);
  batch.text_capacity = capacity;
}

// Where the last frame in `text` that starts after `after` begins (just after a '\n', its
// whole first line in `text`), or 0; `line_end` is where that first line ends.
std::size_t last_frame_start(std::string_view text, std::size_t after, std::size_t& line_end) {
  std::size_t end = text.size();
  std::size_t next_nl = std::string::npos;  // the '\n' ending the line after the one looked at
  while (end > after) {
    const void* nl = ::memrchr(text.data(), '\n', end);
    if (nl == nullptr) return 0;
    const auto at = static_cast<std::size_t>(static_cast<const char*>(nl) - text.data());
    if (next_nl != std::string::npos && at + 1 > after && text.substr(at + 1, kFrameStart.size()) == kFrameStart) {
      line_end = next_nl;
      return at + 1;
    }
    next_nl = at;
    end = at;
  }
  return 0;
}

// The line [start, end) of `text`, the first after a piece, without a '\r' ending it.
void set_next_line(FrameBatch& batch, std::string_view text, std::size_t start, std::size_t end) {
  batch.next_line.assign(text.substr(start, end - start));
  if (!batch.next_line.empty() && batch.next_line.back() == '\r') batch.next_line.pop_back();
}

}  // namespace

FrameBatchSource::FrameBatchSource(const std::string& path, bool binary, std::vector<std::string> binary_columns,
                                   std::vector<std::string> convert, std::size_t batch_bytes)
    : path_(path), convert_(std::move(convert)), batch_bytes_(std::max<std::size_t>(batch_bytes, 1)) {
  const bool split = std::filesystem::path(path).filename().string().find_first_of("*%") != std::string::npos;
  if (!binary && !split) {
    bytes_ = open_bytes(path);
    // A plain file: the pieces' bytes are read by the threads that parse them; only the few
    // kilobytes around each boundary are read here. A file with a NUL byte at its start is
    // binary: it is left to the sequential reader, which says so.
    if (std::string_view(bytes_->kind()) == "plain" && bytes_->remaining() >= 0) {
      const long size = bytes_->remaining();
      const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
      bool text = fd >= 0;
      long at = 0;
      std::string probe(std::size_t{1} << 16, '\0');
      for (; text && at < size; at += static_cast<long>(probe.size())) {
        const ssize_t got = ::pread(fd, probe.data(), probe.size(), at);
        if (got <= 0) break;
        const std::string_view head(probe.data(), static_cast<std::size_t>(got));
        if (head.find('\0') != std::string_view::npos) text = false;
        const auto nonblank = head.find_first_not_of(" \t\r\n");
        if (nonblank != std::string_view::npos) {
          at += static_cast<long>(nonblank);
          break;
        }
      }
      if (text) {
        fd_ = fd;
        plain_size_ = size;
        first_text_ = std::min(at, size);
        bytes_.reset();
      } else if (fd >= 0) {
        ::close(fd);
      }
    }
  } else if (binary && !split) {
    // Headers are read in turn, the values by the threads that take the frames.
    auto reader = std::make_unique<BinaryDumpReader>(path, std::move(binary_columns));
    if (reader->defer_values()) fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    reader_ = std::move(reader);
  } else {
    reader_ = open_dump(path, binary, binary_columns);
  }
}

FrameBatchSource::~FrameBatchSource() {
  if (fd_ >= 0) ::close(fd_);
}

bool FrameBatchSource::take(FrameBatch& batch) {
  std::lock_guard lock(mutex_);
  if (finished_) return false;
  batch.index = next_index_++;
  batch.first = batch.index == 0;
  batch.error = nullptr;
  batch.error_step = -1;
  batch.error_step_line = 0;
  batch.first_step_after_nul = batch.error_step_after_nul = false;
  batch.last = false;
  batch.text_size = 0;
  batch.raw = false;
  batch.file_end = -1;
  batch.plain_piece = false;
  batch.lines = 0;
  batch.relative_lines = false;
  if (plain_size_ >= 0) return take_plain_piece(batch);
  if (bytes_) return take_piece(batch);
  return take_frames(batch);
}

bool FrameBatchSource::take_piece(FrameBatch& batch) {
  std::size_t want = batch_bytes_;
  // The piece starts with what the last one left over, then fresh bytes up to `want`.
  batch.text_size = 0;
  reserve_text(batch, std::max(want, carry_.size()));
  std::memcpy(batch.text.get(), carry_.data(), carry_.size());
  batch.text_size = carry_.size();
  carry_.clear();
  for (;;) {
    bool end = false;
    reserve_text(batch, want);
    while (batch.text_size < want) {
      const std::size_t got = bytes_->read(batch.text.get() + batch.text_size, want - batch.text_size);
      batch.text_size += got;
      if (got == 0) {
        end = true;
        break;
      }
    }
    const std::string_view text(batch.text.get(), batch.text_size);
    if (end) {
      finished_ = true;
      batch.last = true;
      batch.relative_lines = true;
      batch.raw = true;
      return true;
    }
    // The first non-blank byte: a frame boundary must come after some text.
    std::size_t after = text.find_first_not_of(" \t\r\n");
    if (after == std::string_view::npos) after = text.size();
    const bool binary = std::memchr(text.data(), '\0', text.size()) != nullptr;
    std::size_t line_end = 0;
    const std::size_t cut = binary ? 0 : last_frame_start(text, after, line_end);
    if (cut > 0) {
      batch.relative_lines = true;
      batch.raw = true;
      set_next_line(batch, text, cut, line_end);
      carry_.assign(text.substr(cut));
      batch.text_size = cut;
      return true;
    }
    if (binary || text.size() >= kLargestPiece) {
      // Read frame by frame from here on: the text reader finds what is wrong, or reads the
      // frames too large to cut.
      auto rest = std::make_unique<PrefixedSource>(std::string(text), std::move(bytes_));
      batch.text_size = 0;
      read_frame_by_frame(batch, std::move(rest));
      return take_frames(batch);
    }
    want *= 2;
  }
}

void FrameBatchSource::read_frame_by_frame(FrameBatch& batch, std::unique_ptr<ByteSource> rest) {
  auto reader = std::make_unique<TextDumpReader>(std::move(rest), path_, batch.first);
  reader->convert_only(convert_);
  text_reader_ = reader.get();
  reader_ = std::move(reader);
  reader_lines_relative_ = true;
}

bool FrameBatchSource::take_plain_piece(FrameBatch& batch) {
  constexpr long kWindow = 1L << 16, kOverlap = 1L << 12;
  batch.relative_lines = true;
  batch.raw = true;
  batch.file_start = position_;
  for (long end = position_ + static_cast<long>(batch_bytes_);; end = position_ + 2 * (end - position_)) {
    if (end >= plain_size_) {
      batch.file_end = plain_size_;
      batch.last = true;
      finished_ = true;
      position_ = plain_size_;
      return true;
    }
    // The last frame start in [position_, end), whole line, after the file's first text: looked
    // for in windows from the end back.
    for (long window_end = end;;) {
      const long window_start = std::max(position_, window_end - kWindow);
      window_.resize(static_cast<std::size_t>(window_end - window_start));
      std::size_t got = 0;
      while (got < window_.size()) {
        const ssize_t k = ::pread(fd_, window_.data() + got, window_.size() - got, window_start + static_cast<long>(got));
        if (k <= 0) break;
        got += static_cast<std::size_t>(k);
      }
      if (got < window_.size()) {
        batch.raw = false;
        batch.error = std::make_exception_ptr(FormatError(path_, 0, "the file got shorter while being read"));
        batch.last = true;
        finished_ = true;
        return true;
      }
      const std::size_t after = static_cast<std::size_t>(std::clamp(first_text_ - window_start, 0L, window_end - window_start));
      std::size_t line_end = 0;
      const std::size_t cut = last_frame_start(window_, after, line_end);
      if (cut > 0) {
        set_next_line(batch, window_, cut, line_end);
        batch.file_end = window_start + static_cast<long>(cut);
        position_ = batch.file_end;
        return true;
      }
      if (window_start == position_) break;
      window_end = window_start + kOverlap;  // a frame start's line may straddle the windows' edge
    }
    if (end - position_ >= static_cast<long>(kLargestPiece)) {
      // Frames too large to cut: read frame by frame from here on.
      batch.raw = false;
      auto rest = open_bytes(path_);
      rest->skip(static_cast<std::size_t>(position_));
      plain_size_ = -1;
      read_frame_by_frame(batch, std::move(rest));
      return take_frames(batch);
    }
  }
}

bool FrameBatchSource::take_frames(FrameBatch& batch) {
  batch.relative_lines = reader_lines_relative_;
  const long line0 = text_reader_ != nullptr ? text_reader_->line_number() : 0;
  std::size_t n = 0, bytes = 0;
  try {
    while (bytes < batch_bytes_) {
      if (batch.frames.size() <= n) batch.frames.resize(n + 1);
      auto& f = batch.frames[n];
      if (!reader_->next(f)) {
        batch.last = true;
        break;
      }
      if (text_reader_ != nullptr) {
        f.first_line -= line0;
        if (n == 0) batch.first_step_after_nul = text_reader_->nul_by_step();
      }
      bytes += static_cast<std::size_t>(f.atoms) * f.columns.size() * sizeof(double);
      ++n;
    }
  } catch (...) {
    batch.error = shift_line(std::current_exception(), -line0);
    if (text_reader_ != nullptr && text_reader_->step_read() >= 0) {
      batch.error_step = text_reader_->step_read();
      batch.error_step_after_nul = text_reader_->nul_by_step();
      batch.error_step_line = batch.frames[n].first_line + 1 - line0;
    }
    batch.last = true;
  }
  batch.frames.resize(n);
  if (text_reader_ != nullptr) batch.lines = text_reader_->line_number() - line0;
  if (batch.last) finished_ = true;
  return true;  // possibly empty, with `last` set
}

void FrameBatchSource::parse(FrameBatch& batch, const std::function<bool(std::size_t)>& parsed) const {
  if (batch.raw && batch.file_end >= 0) {
    const auto n = static_cast<std::size_t>(batch.file_end - batch.file_start);
    batch.text_size = 0;
    reserve_text(batch, n);
    std::size_t got = 0;
    while (got < n) {
      const ssize_t k = ::pread(fd_, batch.text.get() + got, n - got, batch.file_start + static_cast<long>(got));
      if (k <= 0) break;
      got += static_cast<std::size_t>(k);
    }
    batch.file_end = -1;
    if (got < n) {
      batch.raw = false;
      batch.frames.clear();
      batch.error = std::make_exception_ptr(FormatError(path_, 0, "the file got shorter while being read"));
      return;
    }
    batch.text_size = n;
    batch.plain_piece = true;
  }
  if (!batch.raw) {
    for (std::size_t k = 0; k < batch.frames.size(); ++k) {
      if (batch.frames[k].deferred.empty()) continue;
      try {
        if (fd_ < 0) throw FormatError(path_, 0, std::string("cannot open: ") + std::strerror(errno));
        read_deferred(batch.frames[k], fd_, path_);
      } catch (...) {
        batch.error = std::current_exception();
        batch.frames.resize(k);
        break;
      }
    }
    return;
  }
  batch.raw = false;
  TextDumpReader reader(std::string_view(batch.text.get(), batch.text_size), path_, batch.first,
                        batch.last ? std::nullopt : std::optional(batch.next_line));
  reader.convert_only(convert_);
  std::size_t n = 0;
  try {
    for (;;) {
      if (batch.frames.size() <= n) batch.frames.resize(n + 1);
      if (!reader.next(batch.frames[n])) break;
      if (n == 0) batch.first_step_after_nul = reader.nul_by_step();
      ++n;
      if (parsed && !parsed(n - 1)) break;
    }
  } catch (...) {
    batch.error = std::current_exception();
    if (reader.step_read() >= 0) {
      batch.error_step = reader.step_read();
      batch.error_step_after_nul = reader.nul_by_step();
      batch.error_step_line = batch.frames[n].first_line + 1;
    }
  }
  batch.frames.resize(n);
  batch.lines = reader.line_number();
  if (!batch.plain_piece) batch.text_size = 0;  // a plain piece's bytes stay for settle()'s digest
}

bool FrameBatchSource::digest_content() {
  if (plain_size_ < 0 || next_index_ > 0) return false;
  digest_ = std::make_unique<Xxh128>();
  return true;
}

std::optional<std::string> FrameBatchSource::content_xxh128() const {
  struct stat now {};
  if (!digest_ || digest_broken_ || digested_ != plain_size_ || ::fstat(fd_, &now) != 0 || now.st_size != plain_size_) {
    return std::nullopt;
  }
  return digest_->hex();
}

void FrameBatchSource::settle(FrameBatch& batch) {
  if (digest_ && batch.plain_piece && batch.file_start == digested_) {
    digest_->update(batch.text.get(), batch.text_size);
    digested_ += static_cast<long>(batch.text_size);
  } else if (digest_) {
    digest_broken_ = true;
  }
  if (batch.relative_lines) {
    for (auto& f : batch.frames) f.first_line += settled_lines_;
    batch.error = shift_line(batch.error, settled_lines_);
    if (batch.error_step >= 0) batch.error_step_line += settled_lines_;
    settled_lines_ += batch.lines;
  }
  // As TextDumpReader words it, at the step's line.
  auto backwards = [&](long step, long line, bool after_nul) {
    auto message =
        fmt::format("timestep {} comes after {}: timesteps go backwards (two runs appended to one file?)", step, last_step_);
    if (after_nul) message = "binary data where a text dump was expected (" + message + ")";
    return std::make_exception_ptr(FormatError(path_, line, message));
  };
  for (std::size_t k = 0; k < batch.frames.size(); ++k) {
    const auto& f = batch.frames[k];
    if (f.step < last_step_) {
      batch.error = backwards(f.step, f.first_line > 0 ? f.first_line + 1 : 0, k == 0 && batch.first_step_after_nul);
      batch.frames.resize(k);
      batch.last = true;
      return;
    }
    last_step_ = f.step;
  }
  if (batch.error && batch.error_step >= 0 && batch.error_step < last_step_) {
    batch.error = backwards(batch.error_step, batch.error_step_line, batch.error_step_after_nul);
  }
}

}  // namespace granstack::formats
