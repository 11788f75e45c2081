#pragma once
// LIGGGHTS `dump custom` text files (liggghts-3.8.md section 6), read one frame at a time so
// memory does not grow with the number of frames. Columns are found by name, in any order.
#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/line_reader.hpp>

#include <array>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

struct DumpFrame {
  long step = 0;
  long atoms = 0;
  std::string box_flags;            // e.g. "mm mm mm"
  std::array<double, 6> box{};      // xlo xhi ylo yhi zlo zhi
  std::vector<std::string> columns; // as in the ITEM: ATOMS line
  std::vector<double> values;       // atoms x columns, row-major
  long first_line = 0;              // line of "ITEM: TIMESTEP", for messages

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
  bool next(DumpFrame& frame) override;
  const std::string& path() const override { return reader_.path(); }

 private:
  LineReader reader_;
  std::vector<std::string_view> words_;
  long last_step_ = -1;
};

// LIGGGHTS's binary `dump custom` (.bin, liggghts-3.8.md section 6): little-endian, full double
// precision, no column names, so they come from the deck (the manifest's dump_columns).
class BinaryDumpReader final : public DumpReader {
 public:
  BinaryDumpReader(const std::string& path, std::vector<std::string> columns);
  bool next(DumpFrame& frame) override;
  const std::string& path() const override { return path_; }

 private:
  std::string path_;
  std::vector<std::string> columns_;
  std::unique_ptr<ByteSource> source_;
  long offset_ = 0;
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

// Reads the next frame on a second thread while the caller works on the current one: the same
// frames, in the same order, with the same errors (raised after every complete frame before
// them), in about the time of the slower of parsing and the caller's work.
class PrefetchDumpReader final : public DumpReader {
 public:
  explicit PrefetchDumpReader(std::unique_ptr<DumpReader> inner);
  ~PrefetchDumpReader() override;
  PrefetchDumpReader(const PrefetchDumpReader&) = delete;
  PrefetchDumpReader& operator=(const PrefetchDumpReader&) = delete;
  bool next(DumpFrame& frame) override;
  const std::string& path() const override { return path_; }

 private:
  void produce();
  std::unique_ptr<DumpReader> inner_;
  std::string path_;
  std::mutex mutex_;
  std::condition_variable changed_;
  DumpFrame slot_;
  bool full_ = false, done_ = false, stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

// The files matching a LIGGGHTS dump name with '*' or '%', ordered by the number standing in
// for it (compressed copies, name.gz or name.zst, count too).
std::vector<std::string> dump_files_matching(const std::string& pattern);

// Writes frames in LIGGGHTS's `dump custom` layouts: text as the generated decks ask for it
// (ids and types as integers, every other column %.17g, each line ending in a space), or binary.
class DumpWriter {
 public:
  // A '*' in `path` writes a file per frame (the step in its place); a '%' stands for rank 0.
  DumpWriter(const std::string& path, bool binary);  // throws std::runtime_error
  void write(const DumpFrame& frame);
  void flush();

 private:
  void open(const std::string& path);
  std::string path_;
  bool binary_;
  bool per_step_ = false;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::string buffer_;
};

// A text or binary reader for `path`; `columns` names the binary dump's columns.
std::unique_ptr<DumpReader> open_dump(const std::string& path, bool binary, const std::vector<std::string>& columns);

// Throws FormatError naming each missing column and the `dump custom` keyword that adds it.
void require_columns(const DumpFrame& frame, const std::vector<std::string>& names, const std::string& path);

}  // namespace granstack::formats
