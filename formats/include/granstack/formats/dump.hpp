#pragma once
// LIGGGHTS `dump custom` text files (docs/liggghts.md section 6), read one frame at a time so
// memory does not grow with the number of frames. Columns are found by name, in any order.
#include <granstack/os/for_shares.hpp>
#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/line_reader.hpp>
#include <granstack/formats/repeated_tokens.hpp>


#include <array>
#include <cstdint>
#include <optional>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

struct ZSTD_CCtx_s;  // zstd.h's compression context

namespace granstack::formats {

struct DumpFrame {
  long step = 0;
  long atoms = 0;
  std::string box_flags;            // e.g. "mm mm mm"
  std::array<double, 6> box{};      // xlo xhi ylo yhi zlo zhi
  std::vector<std::string> columns; // as in the ITEM: ATOMS line
  std::vector<double> values;       // atoms x columns, row-major
  long first_line = 0;              // line of "ITEM: TIMESTEP", for messages
  // Values not read yet (BinaryDumpReader::defer_values): (byte offset in the file, count), in
  // the order they fill `values`.
  std::vector<std::pair<long, long>> deferred;
  // Every value is known to be finite: the text reader checked each number it parsed (and took
  // the others from a frame it had checked). False: not known, the reader of the values checks.
  bool finite = false;

  // Index of a column, or -1.
  int column(std::string_view name) const;
  double at(long row, int col) const {
    return values[static_cast<std::size_t>(row) * columns.size() + static_cast<std::size_t>(col)];
  }
};

// A dump read one frame at a time.
class DumpReader {
 public:
  virtual ~DumpReader() = default;
  // Reads the next frame; false at the end of the file. Throws FormatError for a malformed
  // frame (naming file, frame and line or byte offset) and TruncatedError when the file ends
  // inside a frame (the frames before it are complete).
  virtual bool next(DumpFrame& frame) = 0;
  virtual const std::string& path() const = 0;
  long frames_read() const { return frames_; }

 protected:
  long frames_ = 0;
};

class TextDumpReader final : public DumpReader {
 public:
  explicit TextDumpReader(const std::string& path);
  // Whole frames of `path` already in memory (FrameBatchSource): line numbers count from the
  // piece's start. `first`: the piece starts the file (so no frame at all is an empty file).
  // `next_line`: the file's line after the piece (a frame cut short by it fails as it would when
  // reading the whole file); none when the piece ends the file (a frame cut short is truncated).
  // The piece must outlive the reader, and the frames it fills stay untouched until the next call
  // (a token repeating the previous frame's takes that frame's value).
  TextDumpReader(std::string_view piece, const std::string& path, bool first, std::optional<std::string> next_line);
  // The rest of a file from an open source; `first` as above.
  TextDumpReader(std::unique_ptr<ByteSource> source, const std::string& path, bool first);
  bool next(DumpFrame& frame) override;
  const std::string& path() const override { return reader_.path(); }
  long line_number() const { return reader_.line_number() + (next_frame_seen_ ? 1 : 0); }
  // The step of the frame the last next() was reading, once its step line was read; else -1.
  long step_read() const { return step_read_; }
  // Whether a NUL byte (binary data) came before that step's line.
  bool nul_by_step() const { return nul_by_step_; }
  // Only these columns are converted to numbers; the others are checked to be there and to be
  // finite numbers (FormatError otherwise) and left 0 (LIGGGHTS dumps often carry columns an
  // analysis does not need). Empty: every column.
  void convert_only(std::vector<std::string> columns);

 private:
  // The parts of next(): the frame's header (false at a clean end of the file), which columns are
  // converted, and its atom lines, each parsed in place.
  bool read_header(DumpFrame& f, std::string_view& line);
  void choose_conversions(DumpFrame& f);
  void read_atoms(DumpFrame& f);
  // Why atom line a is bad (a file's cut-short last line is truncation, not corruption).
  [[noreturn]] void bad_row(const DumpFrame& f, long a, std::string_view line);
  [[noreturn]] void bad_row_message(const DumpFrame& f, long a, const std::string& msg);
  [[noreturn]] void not_finite(const DumpFrame& f, long a, std::size_t c, const char* p, const char* end);
  bool in_frame(std::string_view& line);
  void expect_item(std::string_view& line, std::string_view item, long step);
  FormatError fail(const std::string& msg) const;

  LineReader reader_;
  bool first_ = true, last_ = true;
  std::string next_line_;
  bool in_memory_ = false;
  bool next_frame_seen_ = false;
  bool previous_finite_ = false;  // the frame read before had only finite values
  RepeatedTokens repeats_;  // the previous frame's lines, where the piece in memory lets them be reused
  long step_read_ = -1;
  bool nul_by_step_ = false;
  std::vector<std::string> wanted_;
  std::vector<char> convert_;  // per column of the current header
  bool convert_all_ = true;
  std::vector<std::string_view> words_;
  long last_step_ = -1;
};

struct BinaryHeader;  // one binary frame's header (binary_dump_reader.cpp)

// LIGGGHTS's binary `dump custom` (.bin, docs/liggghts.md section 6): little-endian, full double
// precision, no column names, so they come from the deck (the manifest's dump_columns).
class BinaryDumpReader final : public DumpReader {
 public:
  BinaryDumpReader(const std::string& path, std::vector<std::string> columns);
  bool next(DumpFrame& frame) override;
  const std::string& path() const override { return path_; }
  // For a plain (uncompressed) file: next() checks and records where each frame's values are
  // (DumpFrame::deferred) instead of reading them, so other threads can read them
  // (read_deferred). Returns false, and changes nothing, for a compressed file.
  bool defer_values();

 private:
  // The parts of next(): the header (false at a clean end of the file), LAMMPS's tag and column
  // names where it wrote them, the values chunk by chunk.
  bool read_header(BinaryHeader& h, bool& lammps);
  void read_lammps_tag();
  void read_lammps_columns();
  void read_chunks(DumpFrame& f, std::int32_t chunks);
  // Reads up to `bytes` (fewer only where the data end), counting them in offset_.
  std::size_t fill(void* dst, std::size_t bytes);
  // Reads exactly `bytes`, or throws TruncatedError naming `what` of this frame.
  void read(void* dst, std::size_t bytes, const char* what);
  std::string where() const;  // "frame N (at byte B)"

  bool defer_ = false;
  std::string path_;
  std::vector<std::string> columns_;
  std::unique_ptr<ByteSource> source_;
  long offset_ = 0;
  long frame_offset_ = 0;  // where the frame being read began
  long last_step_ = -1;
};

// A dump split over files as LIGGGHTS splits it: `*` in the name stands for the step (a file
// per dumped step, read in step order), `%` for the MPI rank (a file per rank, whose pieces of
// each step are merged into one frame). Each piece may be plain, gzip or zstd.
class MultiFileDumpReader final : public DumpReader {
 public:
  // Throws FormatError when no file matches the pattern.
  MultiFileDumpReader(const std::string& pattern, bool binary, std::vector<std::string> columns);
  bool next(DumpFrame& frame) override;
  const std::string& path() const override { return pattern_; }
  const std::vector<std::string>& files() const { return files_; }

 private:
  std::string pattern_;
  bool binary_;
  bool per_rank_;
  std::vector<std::string> columns_;
  std::vector<std::string> files_;                 // step or rank order
  std::vector<std::unique_ptr<DumpReader>> open_;  // per rank: all; per step: the current one
  std::size_t current_ = 0;
  DumpFrame piece_;
  long last_step_ = -1;
};

// The files matching a LIGGGHTS dump name with '*' or '%', ordered by the number standing in
// for it (compressed copies, name.gz or name.zst, count too).
std::vector<std::string> dump_files_matching(const std::string& pattern);

// Reads the values a deferring BinaryDumpReader left in `frame.deferred` from the open file
// `fd` (pread: any number of threads at once). Throws FormatError if the file has changed.
void read_deferred(DumpFrame& frame, int fd, const std::string& path);

// Writes frames in LIGGGHTS's `dump custom` layouts: text as the generated decks ask for it
// (ids and types as integers, every other column %.17g, each line ending in a space), or binary.
// A compressed binary dump is the same bytes as one zstd stream per file (`zstd -d` gives
// LIGGGHTS's file back; every reader here takes either, told by the first bytes).
using os::ForShares;

class DumpWriter {
 public:
  // A '*' in the file name of `path` writes a file per frame (the step in its place); a '%' there
  // stands for rank 0. The same characters in its directories are only characters.
  DumpWriter(const std::string& path, bool binary, bool compressed = false);  // throws std::runtime_error
  DumpWriter(const DumpWriter&) = delete;
  DumpWriter& operator=(const DumpWriter&) = delete;
  ~DumpWriter();  // ends the file's zstd stream and closes it, without checking
  // A text frame's lines are formatted in `shares`' shares of its atoms (empty: in one); the
  // file does not depend on them.
  void write(const DumpFrame& frame, const ForShares& shares = {});
  // Writes out what is buffered and closes the file; throws std::runtime_error naming it if
  // the system could not write all of it (a full disk). The destructor closes without checking.
  void close();

 private:
  void open(const std::string& path);
  void put(const char* bytes, std::size_t n);  // to the file, through zstd when compressed
  void end_stream();                          // a compressed file's last bytes
  void compress(const char* bytes, std::size_t n, bool end);
  void write_out(const char* bytes, std::size_t n);  // to the file as they are
  void write_atoms(const DumpFrame& f, const std::vector<bool>& integer, const ForShares& shares);
  std::string path_, current_;  // the path given, and the file open now
  std::size_t name_at_ = 0;     // where the file's name begins in path_
  bool binary_;
  bool per_step_ = false;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::unique_ptr<ZSTD_CCtx_s, std::size_t (*)(ZSTD_CCtx_s*)> zstd_;  // null: not compressed
  std::vector<char> compressed_;                                     // zstd's output, written as it fills
  std::string buffer_;
  // The text of the atoms' lines of a frame, in pieces (one per share that formatted it), the
  // first atom of each; written one after the other.
  struct TextPiece;  // dump_writer.cpp
  // This frame's and the frame before's text, each value's length (at most 25 characters), and
  // the frame before's values (allocated unwritten, so that the shares first touch their parts).
  std::vector<TextPiece> pieces_, previous_pieces_;
  std::vector<std::uint8_t> lengths_, previous_lengths_;
  std::unique_ptr<double[]> previous_values_;
  std::size_t previous_count_ = 0;
};

// A text or binary reader for `path`; `columns` names the binary dump's columns.
std::unique_ptr<DumpReader> open_dump(const std::string& path, bool binary, const std::vector<std::string>& columns);

// Throws FormatError naming each missing column and the `dump custom` keyword that adds it.
void require_columns(const DumpFrame& frame, const std::vector<std::string>& names, const std::string& path);

}  // namespace granstack::formats
