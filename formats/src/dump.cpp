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

TextDumpReader::TextDumpReader(const std::string& path) : reader_(path) {}

TextDumpReader::TextDumpReader(std::string_view piece, const std::string& path, bool first,
                               std::optional<std::string> next_line)
    : reader_(piece, path), first_(first), last_(!next_line), next_line_(next_line.value_or("")),
      in_memory_(true) {}

TextDumpReader::TextDumpReader(std::unique_ptr<ByteSource> source, const std::string& path, bool first)
    : reader_(std::move(source), path), first_(first) {}

void TextDumpReader::convert_only(std::vector<std::string> columns) {
  wanted_ = std::move(columns);
  convert_.clear();  // worked out again from the next header
}

namespace {
// Skips the next blank-separated word of [p, end); nullptr when there is none.
const char* skip_word(const char* p, const char* end) {
  while (p < end && (*p == ' ' || *p == '\t')) ++p;
  if (p == end) return nullptr;
  while (p < end && *p != ' ' && *p != '\t') ++p;
  return p;
}
// How far same_token may read past the start of a token.
constexpr std::size_t kTokenReach = 40;

// The length of the token at p when the token at q has the same bytes and the same delimiter
// after it (a byte below '!'), else 0. Reads up to 32 bytes at p and at q; tokens of 32 bytes
// or more count as different.
std::size_t same_token(const char* p, const char* q) {
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
std::size_t common_prefix(const char* a, const char* b, std::size_t n) {
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

// The length of the token at p (up to the first byte below '!'), read 8 bytes at a time; 0 when
// it is 32 bytes or longer. Reads up to 32 bytes at p.
std::size_t token_length(const char* p) {
  constexpr std::uint64_t kOnes = 0x0101010101010101ULL, kHigh = 0x8080808080808080ULL;
  for (std::size_t n = 0; n < 32; n += 8) {
    std::uint64_t a = 0;
    std::memcpy(&a, p + n, 8);
    const std::uint64_t delimiters = (a - kOnes * 0x21) & ~a & kHigh;
    if (delimiters != 0) return n + static_cast<std::size_t>(__builtin_ctzll(delimiters)) / 8;
  }
  return 0;
}
}  // namespace

bool TextDumpReader::next(DumpFrame& f) {
  std::string_view line;
  const auto& path = reader_.path();
  step_read_ = -1;
  auto fail = [&](const std::string& msg) {
    if (reader_.saw_nul()) {
      return FormatError(path, line_number(), "binary data where a text dump was expected (" + msg + ")");
    }
    return FormatError(path, line_number(), msg);
  };
  auto step_text = [&] { return fmt::format("frame at step {}", f.step); };
  // A line inside a frame. A piece of a file that is not its end is followed by the next
  // frame's 'ITEM: TIMESTEP' line: a frame that runs into it meets that line here, and fails as
  // it would reading the whole file.
  auto in_frame = [&](std::string_view& l) {
    if (reader_.next(l)) return true;
    if (last_ || next_frame_seen_) return false;
    next_frame_seen_ = true;
    l = next_line_;
    return true;
  };
  auto expect_item = [&](std::string_view item) {
    if (!in_frame(line)) {
      throw TruncatedError(path, line_number(), fmt::format("file ends inside the {} (no '{}')", step_text(), item));
    }
    if (line.substr(0, item.size()) != item) {
      throw fail(fmt::format("expected '{}' in the {}, found '{}'", item, step_text(), line.substr(0, 60)));
    }
  };

  // Skip blank lines between frames; a clean end of file ends the dump.
  do {
    if (!reader_.next(line)) {
      if (frames_ == 0 && first_) throw fail("empty file: no frame (a dump starts with 'ITEM: TIMESTEP')");
      return false;
    }
  } while (line.find_first_not_of(" \t") == std::string_view::npos);
  if (line.substr(0, 14) != "ITEM: TIMESTEP") {
    throw fail(fmt::format("expected 'ITEM: TIMESTEP', found '{}'", line.substr(0, 60)));
  }
  f.first_line = reader_.line_number();
  if (!in_frame(line)) throw TruncatedError(path, line_number(), "file ends after 'ITEM: TIMESTEP'");
  if (!parse_long(line, f.step) || f.step < 0) throw fail(fmt::format("'{}' is not a timestep", line.substr(0, 60)));
  step_read_ = f.step;
  nul_by_step_ = reader_.saw_nul();
  if (f.step < last_step_) {
    throw fail(fmt::format("timestep {} comes after {}: timesteps go backwards (two runs appended to one file?)", f.step,
                           last_step_));
  }
  expect_item("ITEM: NUMBER OF ATOMS");
  if (!in_frame(line)) throw TruncatedError(path, line_number(), "file ends in the frame header");
  if (!parse_long(line, f.atoms) || f.atoms < 0) throw fail(fmt::format("'{}' is not an atom count", line.substr(0, 60)));
  expect_item("ITEM: BOX BOUNDS");
  f.box_flags = std::string(line.substr(16));
  while (!f.box_flags.empty() && f.box_flags.front() == ' ') f.box_flags.erase(0, 1);
  for (int axis = 0; axis < 3; ++axis) {
    if (!in_frame(line)) throw TruncatedError(path, line_number(), "file ends in the box bounds");
    split_words(line, words_);
    if (words_.size() < 2 || !parse_double(words_[0], f.box[static_cast<std::size_t>(2 * axis)]) ||
        !parse_double(words_[1], f.box[static_cast<std::size_t>(2 * axis + 1)])) {
      throw fail("a box-bounds line has two numbers");
    }
  }
  expect_item("ITEM: ATOMS");
  split_words(line.substr(11), words_);
  if (words_.empty()) throw fail("'ITEM: ATOMS' names no column");
  if (frames_ == 0 || words_.size() != f.columns.size() ||
      !std::equal(words_.begin(), words_.end(), f.columns.begin())) {
    f.columns.assign(words_.begin(), words_.end());
    convert_.clear();
  }
  const std::size_t ncol = f.columns.size();
  if (convert_.size() != ncol) {
    convert_.assign(ncol, 1);
    if (!wanted_.empty()) {
      for (std::size_t c = 0; c < ncol; ++c) {
        convert_[c] = std::find(wanted_.begin(), wanted_.end(), f.columns[c]) != wanted_.end() ? 1 : 0;
      }
    }
  }
  const bool convert_all = std::find(convert_.begin(), convert_.end(), 0) == convert_.end();
  // The header's count is not trusted with memory: the frame grows as its lines arrive (and the
  // storage of the previous frame is reused without clearing it).
  const std::size_t expected = static_cast<std::size_t>(f.atoms) * ncol;
  if (f.values.size() > expected) f.values.resize(expected);
  // A token with the same bytes as in the atom's line of the previous frame has its value (DEM
  // dumps repeat much: radius, mass, resting atoms, zeros). Only for a piece in memory, whose
  // earlier lines stay put, and a frame stored apart from the previous one.
  const bool keep_lines = in_memory_;
  const bool reuse = keep_lines && !previous_lines_.empty() && previous_values_ != nullptr &&
                     previous_values_ != f.values.data() && previous_columns_ == f.columns;

  for (long a = 0; a < f.atoms; ++a) {
    if (!in_frame(line)) {
      throw TruncatedError(path, line_number(),
                           fmt::format("file ends inside the frame at step {}: {} of {} atom lines", f.step, a, f.atoms));
    }
    // A bad last line of the file is a run killed while writing: truncation, not corruption.
    auto bad_row = [&](const std::string& msg) {
      FormatError error = fail(msg);
      std::string_view rest;
      if (last_ && !reader_.next(rest)) {
        throw TruncatedError(path, error.line(),
                             fmt::format("file ends inside the frame at step {}: atom line {} of {} is cut short",
                                         f.step, a + 1, f.atoms));
      }
      throw error;
    };
    // The numbers are parsed in place; the words are split only to explain a bad line.
    const std::size_t base = static_cast<std::size_t>(a) * ncol;
    if (f.values.size() < base + ncol) f.values.resize(std::min(expected, std::max(base + ncol, 2 * f.values.size())));
    double* out = f.values.data() + base;
    const char* p = line.data();
    const char* end = line.data() + line.size();
    std::size_t c = 0;
    // The same atom line of the previous frame of this piece, when there is one to compare with.
    const bool cached = reuse && static_cast<std::size_t>(a) < previous_lines_.size() &&
                        line.data() + line.size() + kTokenReach <= reader_.data_end();
    const double* old = cached ? previous_values_ + base : nullptr;
    const std::string_view before = cached ? previous_lines_[static_cast<std::size_t>(a)] : std::string_view();
    const std::uint32_t* old_starts = cached ? previous_starts_.data() + base : nullptr;
    if (keep_lines && lines_.size() <= static_cast<std::size_t>(a)) {  // grown as lines arrive, as the values
      lines_.resize(std::min(static_cast<std::size_t>(f.atoms), std::max<std::size_t>(a + 1, 2 * lines_.size())));
      starts_.resize(lines_.size() * ncol);
    }
    std::uint32_t* starts = keep_lines ? starts_.data() + base : nullptr;
    const std::size_t common =
        cached ? common_prefix(line.data(), before.data(), std::min(line.size(), before.size())) : 0;
    if (cached && common == line.size() && common == before.size()) {  // an atom at rest: the line again
      std::memcpy(out, old, ncol * sizeof(double));
      std::memcpy(starts, old_starts, ncol * sizeof(std::uint32_t));
      c = ncol;
      p = end;
    } else if (cached) {
      // The columns wholly inside the bytes both lines begin with (id, type, radius, mass and
      // often the position) repeat: taken in one go. The rest are compared token by token.
      while (c + 1 < ncol && old_starts[c + 1] <= common) ++c;
      std::memcpy(out, old, c * sizeof(double));
      std::memcpy(starts, old_starts, c * sizeof(std::uint32_t));
      p = line.data() + (c > 0 ? old_starts[c] : 0);
    }
    for (; c < ncol && p != nullptr; ++c) {
      if (cached && *p == ' ' && p[1] > ' ') {
        ++p;  // the one space LIGGGHTS writes between numbers (the bytes ahead may be read: see cached)
      } else {
        while (p < end && (*p == ' ' || *p == '\t')) ++p;
      }
      if (starts != nullptr) starts[c] = static_cast<std::uint32_t>(p - line.data());
      if (cached) {
        const std::size_t same = same_token(p, before.data() + old_starts[c]);
        if (same > 0) {
          out[c] = old[c];
          p += same;
          continue;
        }
      }
      if (convert_all || convert_[c] != 0) {
        if (p + 1 < end && p[0] == '0' && (p[1] == ' ' || p[1] == '\t')) {  // the commonest number
          out[c] = 0.0;
          ++p;
          continue;
        }
        p = parse_next_double(p, end, out[c]);
      } else {
        // Not converted, but checked to be a finite number: its first character past a sign is a
        // digit or a point (nan, inf and words are not).
        const char* q = p < end && (*p == '-' || *p == '+') ? p + 1 : p;
        if (q < end && !(*q >= '0' && *q <= '9') && *q != '.') {
          const char* w = q;
          while (w < end && *w != ' ' && *w != '\t') ++w;
          throw fail(fmt::format("'{}' in column '{}' (atom line {} of the frame at step {}) is not a finite number",
                                 std::string_view(p, static_cast<std::size_t>(std::min<long>(w - p, 40))), f.columns[c],
                                 a + 1, f.step));
        }
        const std::size_t length = cached ? token_length(p) : 0;
        p = length > 0 && p + length <= end ? p + length : skip_word(p, end);
        out[c] = 0.0;
      }
    }
    while (p != nullptr && p < end && (*p == ' ' || *p == '\t')) ++p;
    if (p == nullptr || p != end) {
      split_words(line, words_);
      if (words_.size() != ncol) {
        bad_row(fmt::format("atom line {} of the frame at step {} has {} values, the header names {} columns", a + 1,
                            f.step, words_.size(), ncol));
      }
      for (std::size_t k = 0; k < ncol; ++k) {
        double ignored = 0.0;
        if (!parse_double(words_[k], ignored)) {
          bad_row(fmt::format("'{}' in column '{}' (frame at step {}) is not a number", words_[k].substr(0, 40),
                              f.columns[k], f.step));
        }
      }
      bad_row(fmt::format("atom line {} of the frame at step {} is not a row of numbers", a + 1, f.step));
    }
    if (keep_lines) lines_[static_cast<std::size_t>(a)] = line;
  }
  // In a piece held in memory, this frame's lines stay readable for the next frame's comparison.
  if (keep_lines) {
    previous_lines_.swap(lines_);
    previous_starts_.swap(starts_);
    previous_values_ = f.values.data();
    previous_columns_ = f.columns;
  } else {
    previous_lines_.clear();
  }
  last_step_ = f.step;
  ++frames_;
  return true;
}

BinaryDumpReader::BinaryDumpReader(const std::string& path, std::vector<std::string> columns)
    : path_(path), columns_(std::move(columns)), source_(open_bytes(path)) {}

namespace {
// The header of one binary frame, as LIGGGHTS writes it (dump_custom.cpp header_binary); LAMMPS
// (since 2021) writes the same after a format tag (binary_tag), and more after the box.
#pragma pack(push, 1)
struct BinaryHeader {
  std::int64_t step;
  std::int64_t atoms;
  std::int32_t triclinic;
  std::int32_t boundary[6];
};
#pragma pack(pop)
static_assert(sizeof(BinaryHeader) == 44);

// LAMMPS's binary dump tag: -(length of the magic string), "DUMPCUSTOM", endianness 1, revision 2.
constexpr std::string_view kLammpsMagic = "DUMPCUSTOM";
constexpr std::int32_t kLammpsRevision = 2;
}  // namespace

bool BinaryDumpReader::next(DumpFrame& f) {
  // Reads exactly `bytes` unless the data end first; returns what it got.
  auto fill = [&](void* dst, std::size_t bytes) {
    std::size_t got = 0;
    while (got < bytes) {
      const std::size_t k = source_->read(static_cast<char*>(dst) + got, bytes - got);
      if (k == 0) break;
      got += k;
    }
    return got;
  };
  const long frame_offset = offset_;
  const long frame_index = frames_ + 1;
  auto where = [&] { return fmt::format("frame {} (at byte {})", frame_index, frame_offset); };
  auto read = [&](void* dst, std::size_t bytes, const char* what) {
    const std::size_t got = fill(dst, bytes);
    offset_ += static_cast<long>(got);
    if (got != bytes) {
      throw TruncatedError(path_, 0, fmt::format("file ends inside {} ({}): the run was cut short", where(), what));
    }
  };
  // LAMMPS's tag before the header: the magic string, its endianness and format revision.
  const auto read_lammps_tag = [&] {
    char magic[kLammpsMagic.size()];
    std::int32_t endian = 0, revision = 0;
    read(magic, sizeof magic, "the format tag");
    read(&endian, sizeof endian, "the format tag");
    read(&revision, sizeof revision, "the format tag");
    if (std::string_view(magic, sizeof magic) != kLammpsMagic || endian != 1 || revision != kLammpsRevision) {
      throw FormatError(path_, 0, fmt::format("{} is tagged as a LAMMPS binary dump but not of revision {} with this "
                                              "machine's byte order (magic '{}', endianness {}, revision {}): written "
                                              "by another LAMMPS, or corrupted",
                                              where(), kLammpsRevision, std::string(magic, sizeof magic), endian, revision));
    }
  };
  // What LAMMPS writes after the column count: the unit style, the time, the column names (checked
  // against the deck's).
  const auto read_lammps_columns = [&] {
    std::int32_t length = 0;
    read(&length, sizeof length, "the unit style");
    if (length < 0 || length > 64) throw FormatError(path_, 0, fmt::format("{}: a unit style of {} bytes: corrupted", where(), length));
    std::string text(static_cast<std::size_t>(length), '\0');
    read(text.data(), text.size(), "the unit style");
    char time_flag = 0;
    read(&time_flag, 1, "the time flag");
    if (time_flag != 0) {
      double time = 0.0;
      read(&time, sizeof time, "the time");
    }
    read(&length, sizeof length, "the column names");
    if (length < 0 || length > 65536) throw FormatError(path_, 0, fmt::format("{}: column names of {} bytes: corrupted", where(), length));
    text.assign(static_cast<std::size_t>(length), '\0');
    read(text.data(), text.size(), "the column names");
    if (text != fmt::format("{}", fmt::join(columns_, " "))) {
      throw FormatError(path_, 0, fmt::format("{} has the columns '{}', the deck's dump line names '{}'", where(), text,
                                              fmt::join(columns_, " ")));
    }
  };
  BinaryHeader h{};
  std::size_t got = fill(&h, sizeof h.step);
  offset_ += static_cast<long>(got);
  if (got == 0) {
    if (frames_ == 0) throw FormatError(path_, 0, "empty file: no frame");
    return false;
  }
  if (got >= 8 && std::string_view(reinterpret_cast<const char*>(&h), 8) == "ITEM: TI") {
    throw FormatError(path_, 0, "this is a text dump, not a binary one: generate the case with --dump-format text");
  }
  const bool lammps = got == sizeof h.step && h.step == -static_cast<std::int64_t>(kLammpsMagic.size());
  if (lammps) {
    read_lammps_tag();
    read(&h.step, sizeof h.step, "the header");
  }
  got = fill(reinterpret_cast<char*>(&h) + sizeof h.step, sizeof h - sizeof h.step);
  offset_ += static_cast<long>(got);
  if (got != sizeof h - sizeof h.step) throw TruncatedError(path_, 0, fmt::format("file ends inside the header of {}", where()));
  bool boundary_ok = true;
  for (const auto b : h.boundary) boundary_ok = boundary_ok && b >= 0 && b <= 3;
  if (h.step < 0 || h.atoms < 0 || h.atoms > (std::int64_t{1} << 40) || (h.triclinic != 0 && h.triclinic != 1) ||
      !boundary_ok) {
    throw FormatError(path_, 0, fmt::format("{} has an impossible header (step {}, {} atoms): not a LIGGGHTS or "
                                            "LAMMPS binary dump, or corrupted",
                                            where(), h.step, h.atoms));
  }
  if (h.step < last_step_) {
    throw FormatError(path_, 0, fmt::format("{}: timestep {} comes after {}: timesteps go backwards", where(), h.step,
                                            last_step_));
  }
  double box[9];
  read(box, sizeof(double) * (h.triclinic ? 9 : 6), "the box");
  std::int32_t size_one = 0, chunks = 0;
  read(&size_one, sizeof size_one, "the column count");
  if (lammps) read_lammps_columns();
  read(&chunks, sizeof chunks, "the chunk count");
  if (size_one != static_cast<std::int32_t>(columns_.size())) {
    throw FormatError(path_, 0, fmt::format("{} has {} columns per atom, the deck's dump line names {} ({})", where(),
                                            size_one, columns_.size(), fmt::join(columns_, " ")));
  }
  if (chunks < 1 || chunks > (1 << 24)) {
    throw FormatError(path_, 0, fmt::format("{} claims {} chunks: corrupted", where(), chunks));
  }
  f.step = h.step;
  f.atoms = h.atoms;
  f.first_line = 0;
  static constexpr char kBoundary[] = {'p', 'f', 's', 'm'};
  f.box_flags.clear();
  for (int axis = 0; axis < 3; ++axis) {
    if (axis > 0) f.box_flags += ' ';
    f.box_flags += kBoundary[h.boundary[2 * axis]];
    f.box_flags += kBoundary[h.boundary[2 * axis + 1]];
  }
  std::copy(box, box + 6, f.box.begin());
  f.columns = columns_;
  const std::size_t total = static_cast<std::size_t>(h.atoms) * columns_.size();
  // The header's count is not trusted with memory: the frame grows as its chunks arrive (and the
  // storage of the previous frame is reused without clearing it).
  if (f.values.size() > total) f.values.resize(total);
  f.deferred.clear();
  std::size_t filled = 0;
  for (std::int32_t c = 0; c < chunks; ++c) {
    std::int32_t n = 0;
    read(&n, sizeof n, "a chunk length");
    if (n < 0 || static_cast<std::size_t>(n) > total - filled || n % size_one != 0) {
      throw FormatError(path_, 0, fmt::format("{}: chunk {} holds {} values, which does not fit {} atoms of {} columns",
                                              where(), c + 1, n, h.atoms, size_one));
    }
    if (defer_) {
      const long bytes = static_cast<long>(sizeof(double)) * n;
      if (source_->remaining() < bytes) {
        throw TruncatedError(path_, 0, fmt::format("file ends inside {} (atom data): the run was cut short", where()));
      }
      f.deferred.emplace_back(offset_, n);
      source_->skip(static_cast<std::size_t>(bytes));
      offset_ += bytes;
      filled += static_cast<std::size_t>(n);
      continue;
    }
    for (std::size_t done = 0; done < static_cast<std::size_t>(n);) {
      const std::size_t part = std::min<std::size_t>(static_cast<std::size_t>(n) - done, std::size_t{1} << 20);
      if (f.values.size() < filled + part) f.values.resize(filled + part);
      read(f.values.data() + filled, sizeof(double) * part, "atom data");
      filled += part;
      done += part;
    }
  }
  if (filled != total) {
    throw FormatError(path_, 0, fmt::format("{} holds {} values for {} atoms of {} columns", where(), filled, h.atoms,
                                            size_one));
  }
  last_step_ = f.step;
  ++frames_;
  return true;
}

bool BinaryDumpReader::defer_values() {
  defer_ = source_->remaining() >= 0;
  return defer_;
}

void read_deferred(DumpFrame& f, int fd, const std::string& path) {
  if (f.deferred.empty()) return;
  std::size_t total = 0;
  for (const auto& [offset, count] : f.deferred) total += static_cast<std::size_t>(count);
  f.values.resize(total);
  char* out = reinterpret_cast<char*>(f.values.data());
  for (const auto& [offset, count] : f.deferred) {
    std::size_t want = sizeof(double) * static_cast<std::size_t>(count);
    off_t at = static_cast<off_t>(offset);
    while (want > 0) {
      const ssize_t got = ::pread(fd, out, want, at);
      if (got <= 0) {
        throw FormatError(path, 0, fmt::format("cannot read the frame at step {} (byte {}): {}", f.step, at,
                                               got == 0 ? "the file got shorter while being read" : std::strerror(errno)));
      }
      out += got;
      at += got;
      want -= static_cast<std::size_t>(got);
    }
  }
  f.deferred.clear();
}

DumpWriter::DumpWriter(const std::string& path, bool binary)
    : path_(path), binary_(binary), file_(nullptr, &std::fclose) {
  // Only the file's own name is a pattern: a '*' or '%' in a directory's name is a character.
  name_at_ = path_.size() - std::filesystem::path(path_).filename().string().size();
  if (const auto rank = path_.find('%', name_at_); rank != std::string::npos) path_.replace(rank, 1, "0");
  per_step_ = path_.find('*', name_at_) != std::string::npos;
  if (!per_step_) open(path_);
}

void DumpWriter::open(const std::string& path) {
  close();
  file_.reset(std::fopen(path.c_str(), "wb"));
  if (!file_) throw std::runtime_error(fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
  current_ = path;
}

void DumpWriter::close() {
  if (file_) close_written(file_.release(), current_);
}

void DumpWriter::write(const DumpFrame& f, const ForShares& shares) {
  if (per_step_) {
    std::string name = path_;
    name.replace(name.find('*', name_at_), 1, std::to_string(f.step));
    open(name);
  }
  buffer_.clear();
  auto out = std::back_inserter(buffer_);
  const std::size_t ncol = f.columns.size();
  if (binary_) {
    auto put = [&](const auto& value) {
      const char* bytes = reinterpret_cast<const char*>(&value);
      buffer_.append(bytes, sizeof value);
    };
    put(static_cast<std::int64_t>(f.step));
    put(static_cast<std::int64_t>(f.atoms));
    put(std::int32_t{0});
    for (std::size_t k = 0; k < 6; ++k) {
      const char c = f.box_flags.size() > k + k / 2 ? f.box_flags[k + k / 2] : 'm';
      put(std::int32_t{c == 'p' ? 0 : c == 'f' ? 1 : c == 's' ? 2 : 3});
    }
    for (const double b : f.box) put(b);
    put(static_cast<std::int32_t>(ncol));
    put(std::int32_t{1});
    put(static_cast<std::int32_t>(f.values.size()));
    buffer_.append(reinterpret_cast<const char*>(f.values.data()), f.values.size() * sizeof(double));
  } else {
    fmt::format_to(out, "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS {}\n{:g} {:g}\n{:g} {:g}\n{:g} {:g}\n",
                   f.step, f.atoms, f.box_flags, f.box[0], f.box[1], f.box[2], f.box[3], f.box[4], f.box[5]);
    fmt::format_to(out, "ITEM: ATOMS");
    std::vector<bool> integer(ncol);
    for (std::size_t c = 0; c < ncol; ++c) {
      fmt::format_to(out, " {}", f.columns[c]);
      integer[c] = f.columns[c] == "id" || f.columns[c] == "type";
    }
    buffer_ += " \n";
    write_atoms(f, integer, shares);
  }
  // The header, then (text) the atoms' lines as write_atoms left them.
  bool written = std::fwrite(buffer_.data(), 1, buffer_.size(), file_.get()) == buffer_.size();
  if (!binary_) {
    for (const auto& p : previous_pieces_) {
      written = written && std::fwrite(p.text.data(), 1, p.text.size(), file_.get()) == p.text.size();
    }
  }
  if (!written) throw std::runtime_error(fmt::format("{}: cannot write: {}", current_, std::strerror(errno)));
}

// Each value in the shortest text that reads back to the same double (LIGGGHTS writes %.17g).
// A value equal to the bit to the same atom's and column's in the frame before (radius, mass,
// zeros, spheres at rest) is copied from that frame's text instead of being formatted again;
// the frame before's values are read in order, so their lengths say where each one starts.
// Each share formats its atoms into a piece of its own, reserved once from the frame before's
// size and never zero-filled, and keeps its values for the next frame itself: nothing of a
// frame's size is copied or first touched on one thread.
void DumpWriter::write_atoms(const DumpFrame& f, const std::vector<bool>& integer, const ForShares& shares) {
  const std::size_t ncol = f.columns.size();
  const std::size_t atoms = static_cast<std::size_t>(f.atoms);
  const std::size_t n = atoms * ncol;
  const bool reuse = n > 0 && previous_count_ == n && f.values.size() == n && !previous_pieces_.empty();
  lengths_.resize(n);
  if (!reuse) {
    previous_values_ = std::make_unique_for_overwrite<double[]>(n);
    previous_count_ = n;
  }
  std::size_t previous_size = 0;
  for (const auto& p : previous_pieces_) previous_size += p.text.size();
  // Formatted straight into the piece (a third faster than through an iterator), grown as the
  // lines need it: a value takes at most 24 characters and its space, a line its newline.
  constexpr std::size_t kLongestValue = 25;
  const std::size_t longest_line = ncol * kLongestValue + 1;
  const double bytes_per_atom = reuse && atoms > 0 ? static_cast<double>(previous_size) / static_cast<double>(atoms)
                                                   : static_cast<double>(ncol * 20 + 1);
  const auto format = [&](std::size_t begin, std::size_t end, fmt::memory_buffer& text) {
    text.reserve(static_cast<std::size_t>(1.1 * bytes_per_atom * static_cast<double>(end - begin)) + longest_line);
    // The frame before's text of atom `begin` on: its piece, and where in it.
    std::size_t piece = 0;
    const char* previous = nullptr;
    std::size_t next_first = atoms;  // the next piece's first atom
    if (reuse) {
      while (piece + 1 < previous_pieces_.size() && previous_pieces_[piece + 1].first_atom <= begin) ++piece;
      previous = previous_pieces_[piece].text.data();
      for (std::size_t a = previous_pieces_[piece].first_atom; a < begin; ++a) {  // each line and its newline
        for (std::size_t c = 0; c < ncol; ++c) previous += previous_lengths_[a * ncol + c];
        ++previous;
      }
      next_first = piece + 1 < previous_pieces_.size() ? previous_pieces_[piece + 1].first_atom : atoms;
    }
    std::size_t used = 0, k = begin * ncol;
    for (std::size_t a = begin; a < end; ++a) {
      if (reuse && a == next_first) {
        previous = previous_pieces_[++piece].text.data();
        next_first = piece + 1 < previous_pieces_.size() ? previous_pieces_[piece + 1].first_atom : atoms;
      }
      if (text.size() < used + longest_line) text.resize(std::max(text.capacity(), used + longest_line));
      char* const first = text.data();
      char* out = first + used;
      for (std::size_t c = 0; c < ncol; ++c, ++k) {
        const double v = f.values[k];
        char* const start = out;
        if (reuse && std::memcmp(&v, &previous_values_[k], sizeof v) == 0) {
          out = std::copy_n(previous, previous_lengths_[k], out);
        } else if (integer[c]) {
          out = fmt::format_to(out, FMT_COMPILE("{} "), static_cast<long>(v));
        } else {
          out = fmt::format_to(out, FMT_COMPILE("{} "), v);
        }
        if (reuse) previous += previous_lengths_[k];
        previous_values_[k] = v;  // read above: each share keeps its own for the next frame
        lengths_[k] = static_cast<std::uint8_t>(out - start);
      }
      *out++ = '\n';
      if (reuse) ++previous;  // the frame before's newline
      used = static_cast<std::size_t>(out - first);
    }
    text.resize(used);
  };
  pieces_.clear();
  if (!shares) {
    pieces_.emplace_back();
    format(0, atoms, pieces_.back().text);
  } else {
    std::mutex m;
    shares(atoms, [&](std::size_t begin, std::size_t end) {
      if (begin == end) return;  // no piece: the pieces' first atoms rise strictly
      TextPiece piece;
      piece.first_atom = begin;
      format(begin, end, piece.text);
      const std::lock_guard<std::mutex> lock(m);
      pieces_.push_back(std::move(piece));
    });
    std::sort(pieces_.begin(), pieces_.end(), [](const auto& a, const auto& b) { return a.first_atom < b.first_atom; });
  }
  // The text is written from previous_pieces_; its lengths are kept for the next frame.
  std::swap(previous_pieces_, pieces_);
  std::swap(previous_lengths_, lengths_);
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
