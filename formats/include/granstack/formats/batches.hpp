#pragma once
// A dump handed out in batches of whole frames to several threads at once, so that parsing (and
// whatever the caller does with the frames) runs in parallel. A single text file, plain or
// compressed, is cut at frame boundaries under a lock and each piece is parsed by the thread that
// took it; any other dump (binary, or split over files) is read a few frames at a time under
// the lock. Memory is a few batches per thread, whatever the number of frames.
#include <granstack/formats/digest.hpp>
#include <granstack/formats/dump.hpp>

#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace granstack::formats {

struct FrameBatch {
  long index = 0;                 // 0, 1, 2, ... in file order
  std::vector<DumpFrame> frames;  // complete frames, in order
  // What ended the dump after these frames (FormatError, TruncatedError), or null. Line numbers
  // in it and in the frames' first_line count from the batch's start until settle() rebases them.
  std::exception_ptr error;
  // The step of the frame the error is in, and the line of that step, when it was read (else -1):
  // a step that goes backwards is reported before anything else wrong in its frame.
  long error_step = -1, error_step_line = 0;
  // Binary data came before the step line of the first frame, or of the frame in error: a step
  // going backwards is then worded as the whole-file reader words it.
  bool first_step_after_nul = false, error_step_after_nul = false;
  bool last = false;              // nothing comes after this batch
  // The raw piece of text, before parse(): bytes not cleared before use (a std::string would
  // zero every byte it grows by).
  std::unique_ptr<char[]> text;
  std::size_t text_size = 0, text_capacity = 0;
  bool raw = false;               // parse() has yet to turn `text` into frames
  long file_start = 0, file_end = -1;  // a plain file's piece, which parse() reads itself (pread)
  bool plain_piece = false;       // parsed, `text` holds the plain file's bytes from file_start on
  std::string next_line;          // the line after the piece (the next frame's first), unless `last`
  long lines = 0;                 // text lines the batch spans
  bool relative_lines = false;    // line numbers count from the batch's start
  bool first = false;
};

class FrameBatchSource {
 public:
  // `convert` as TextDumpReader::convert_only; `batch_bytes` is the size a batch aims at.
  FrameBatchSource(const std::string& path, bool binary, std::vector<std::string> binary_columns,
                   std::vector<std::string> convert = {}, std::size_t batch_bytes = std::size_t{1} << 20);
  ~FrameBatchSource();
  FrameBatchSource(const FrameBatchSource&) = delete;
  FrameBatchSource& operator=(const FrameBatchSource&) = delete;

  // Thread-safe. Takes the next batch (its frames perhaps still to be parsed by parse(), on the
  // calling thread, outside any lock). False when nothing is left; a batch may be empty.
  bool take(FrameBatch& batch);
  // Parses what take() left raw. Never throws: a bad frame ends the batch with `error`.
  // `parsed`, when given, is called with k as soon as frame k of a text piece is parsed (before
  // frame k + 1 is), so that the caller can use it while its values are still in the cache; when
  // it returns false the parsing stops there, frames 0..k kept.
  void parse(FrameBatch& batch, const std::function<bool(std::size_t)>& parsed = {}) const;
  // Call for the batches in index order, one at a time: rebases line numbers to the file's and
  // checks that timesteps do not go backwards from one batch to the next (cutting the batch
  // short with an error if they do).
  void settle(FrameBatch& batch);
  const std::string& path() const { return path_; }
  // Digests the file's bytes as settle() takes its pieces, in order, so that the caller need not
  // read the file a second time to check it (call before the first take()). Only a single plain
  // text file is cut into such pieces: false otherwise, and the caller digests the file itself.
  bool digest_content();
  // The XXH3-128 of the file's content (formats/digest.hpp), when digest_content() was on, every
  // byte went through settle() in order, and the file still has the size it had when opened;
  // otherwise (a read that stopped early, frames too large to cut) nullopt.
  std::optional<std::string> content_xxh128() const;

 private:
  bool take_piece(FrameBatch& batch);
  bool take_plain_piece(FrameBatch& batch);
  void read_frame_by_frame(FrameBatch& batch, std::unique_ptr<ByteSource> rest);
  bool take_frames(FrameBatch& batch);
  std::string path_;
  std::vector<std::string> convert_;
  std::size_t batch_bytes_;
  std::mutex mutex_;
  long next_index_ = 0;
  bool finished_ = false;
  // A single text file cut into pieces: bytes read but not yet handed out.
  std::unique_ptr<ByteSource> bytes_;
  std::string carry_;
  // Anything else (or a text file whose frames are too large to cut): frames read in turn.
  std::unique_ptr<DumpReader> reader_;
  TextDumpReader* text_reader_ = nullptr;  // reader_, when it reads text
  int fd_ = -1;                            // a file parse() reads pieces or values of (pread)
  long plain_size_ = -1;                   // a plain text file cut without reading it all
  long position_ = 0;                      // where its next piece starts
  long first_text_ = 0;                    // its first byte that is not blank
  std::string window_;                     // bytes read to find a frame boundary
  bool reader_lines_relative_ = false;
  // settle()'s state
  long settled_lines_ = 0;
  long last_step_ = -1;
  std::unique_ptr<Xxh128> digest_;  // with digest_content()
  long digested_ = 0;               // bytes of the file digested, from its start
  bool digest_broken_ = false;      // a piece came that was not the file's next bytes
};

}  // namespace granstack::formats
