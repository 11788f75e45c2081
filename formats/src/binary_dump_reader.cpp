// LIGGGHTS's and LAMMPS's binary `dump custom`, and reading a frame's values later, apart.
#include <granstack/formats/dump.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/files.hpp>

#include <fmt/compile.h>
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unistd.h>

namespace granstack::formats {

BinaryDumpReader::BinaryDumpReader(const std::string& path, std::vector<std::string> columns)
    : path_(path), columns_(std::move(columns)), source_(open_bytes(path)) {}

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

namespace {

// LAMMPS's binary dump tag: -(length of the magic string), "DUMPCUSTOM", endianness 1, revision 2.
constexpr std::string_view kLammpsMagic = "DUMPCUSTOM";
constexpr std::int32_t kLammpsRevision = 2;
}  // namespace

std::size_t BinaryDumpReader::fill(void* dst, std::size_t bytes) {
  std::size_t got = 0;
  while (got < bytes) {
    const std::size_t k = source_->read(static_cast<char*>(dst) + got, bytes - got);
    if (k == 0) break;
    got += k;
  }
  offset_ += static_cast<long>(got);
  return got;
}

std::string BinaryDumpReader::where() const { return fmt::format("frame {} (at byte {})", frames_ + 1, frame_offset_); }

void BinaryDumpReader::read(void* dst, std::size_t bytes, const char* what) {
  if (fill(dst, bytes) != bytes) {
    throw TruncatedError(path_, 0, fmt::format("file ends inside {} ({}): the run was cut short", where(), what));
  }
}

// LAMMPS's tag before the header: the magic string, its endianness and format revision.
void BinaryDumpReader::read_lammps_tag() {
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
}

// What LAMMPS writes after the column count: the unit style, the time, the column names (checked
// against the deck's).
void BinaryDumpReader::read_lammps_columns() {
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
}

bool BinaryDumpReader::next(DumpFrame& f) {
  frame_offset_ = offset_;
  BinaryHeader h{};
  bool lammps = false;
  if (!read_header(h, lammps)) return false;
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
  if (chunks < 1 || chunks > (1 << 24)) throw FormatError(path_, 0, fmt::format("{} claims {} chunks: corrupted", where(), chunks));
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
  read_chunks(f, chunks);
  last_step_ = f.step;
  ++frames_;
  return true;
}

// The frame's header (after LAMMPS's tag, where there is one), checked; false at a clean end.
bool BinaryDumpReader::read_header(BinaryHeader& h, bool& lammps) {
  std::size_t got = fill(&h, sizeof h.step);
  if (got == 0) {
    if (frames_ == 0) throw FormatError(path_, 0, "empty file: no frame");
    return false;
  }
  if (got >= 8 && std::string_view(reinterpret_cast<const char*>(&h), 8) == "ITEM: TI") {
    throw FormatError(path_, 0, "this is a text dump, not a binary one: generate the case with --dump-format text");
  }
  lammps = got == sizeof h.step && h.step == -static_cast<std::int64_t>(kLammpsMagic.size());
  if (lammps) {
    read_lammps_tag();
    read(&h.step, sizeof h.step, "the header");
  }
  got = fill(reinterpret_cast<char*>(&h) + sizeof h.step, sizeof h - sizeof h.step);
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
  return true;
}

// The frame's values, chunk by chunk (or where they lie, with defer_values()).
void BinaryDumpReader::read_chunks(DumpFrame& f, std::int32_t chunks) {
  const auto size_one = static_cast<std::int32_t>(columns_.size());
  const std::size_t total = static_cast<std::size_t>(f.atoms) * columns_.size();
  // The header's count is not trusted with memory: the frame grows as its chunks arrive (and the
  // storage of the previous frame is reused without clearing it).
  if (f.values.size() > total) f.values.resize(total);
  f.deferred.clear();
  f.finite = false;  // the bytes as written: not checked here
  std::size_t filled = 0;
  for (std::int32_t c = 0; c < chunks; ++c) {
    std::int32_t n = 0;
    read(&n, sizeof n, "a chunk length");
    if (n < 0 || static_cast<std::size_t>(n) > total - filled || n % size_one != 0) {
      throw FormatError(path_, 0, fmt::format("{}: chunk {} holds {} values, which does not fit {} atoms of {} columns",
                                              where(), c + 1, n, f.atoms, size_one));
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
    throw FormatError(path_, 0, fmt::format("{} holds {} values for {} atoms of {} columns", where(), filled, f.atoms, size_one));
  }
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

}  // namespace granstack::formats
