// Frames written in LIGGGHTS's `dump custom` layouts, text or binary.
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
#include <zstd.h>

namespace granstack::formats {

namespace {
// zstd's fastest level: what a stack's dump repeats (spheres at rest, constant columns) is
// what it removes.
constexpr int kZstdLevel = 1;
}  // namespace

// The text of a share of a frame's atoms' lines; fmt's buffer grows without filling what it adds.
struct DumpWriter::TextPiece {
  std::size_t first_atom = 0;
  fmt::memory_buffer text;
};

DumpWriter::DumpWriter(const std::string& path, bool binary, bool compressed)
    : path_(path), binary_(binary), file_(nullptr, &std::fclose), zstd_(nullptr, &ZSTD_freeCCtx) {
  if (compressed && binary) {
    zstd_.reset(ZSTD_createCCtx());
    if (!zstd_) throw std::runtime_error(fmt::format("{}: cannot start zstd", path));
    ZSTD_CCtx_setParameter(zstd_.get(), ZSTD_c_compressionLevel, kZstdLevel);
    compressed_.resize(ZSTD_CStreamOutSize());
  }
  // Only the file's own name is a pattern: a '*' or '%' in a directory's name is a character.
  name_at_ = path_.size() - std::filesystem::path(path_).filename().string().size();
  if (const auto rank = path_.find('%', name_at_); rank != std::string::npos) path_[rank] = '0';
  per_step_ = path_.find('*', name_at_) != std::string::npos;
  if (!per_step_) open(path_);
}

void DumpWriter::open(const std::string& path) {
  close();
  file_.reset(std::fopen(path.c_str(), "wb"));
  if (!file_) throw std::runtime_error(fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
  current_ = path;
}

DumpWriter::~DumpWriter() {
  try {
    if (file_) end_stream();
  } catch (const std::exception&) {  // NOLINT(bugprone-empty-catch): unchecked, as documented
  }
}

void DumpWriter::close() {
  if (!file_) return;
  end_stream();
  close_written(file_.release(), current_);
}

void DumpWriter::put(const char* bytes, std::size_t n) {
  if (zstd_) {
    compress(bytes, n, false);
  } else {
    write_out(bytes, n);
  }
}

void DumpWriter::write_out(const char* bytes, std::size_t n) {
  if (std::fwrite(bytes, 1, n, file_.get()) != n) {
    throw std::runtime_error(fmt::format("{}: cannot write: {}", current_, std::strerror(errno)));
  }
}

void DumpWriter::end_stream() {
  if (zstd_) compress(nullptr, 0, true);
}

// Feeds `n` bytes to zstd (and, with `end`, ends the stream), writing what it gives out.
void DumpWriter::compress(const char* bytes, std::size_t n, bool end) {
  ZSTD_inBuffer in{bytes, n, 0};
  for (;;) {
    ZSTD_outBuffer out{compressed_.data(), compressed_.size(), 0};
    const std::size_t left = ZSTD_compressStream2(zstd_.get(), &out, &in, end ? ZSTD_e_end : ZSTD_e_continue);
    if (ZSTD_isError(left)) throw std::runtime_error(fmt::format("{}: zstd: {}", current_, ZSTD_getErrorName(left)));
    write_out(compressed_.data(), out.pos);
    if (end ? left == 0 : in.pos == in.size) return;
  }
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
  put(buffer_.data(), buffer_.size());
  if (!binary_) {
    for (const auto& p : previous_pieces_) put(p.text.data(), p.text.size());
  }
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

}  // namespace granstack::formats
