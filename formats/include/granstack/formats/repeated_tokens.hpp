#pragma once
// The text dump reader's cache: a piece of a file held in memory keeps its previous frame's atom
// lines, values and where each token starts, so that a token with the same bytes as in the same
// atom's line of the previous frame takes that frame's value unparsed (DEM dumps repeat much:
// radius, mass, resting atoms, zeros). TextDumpReader holds one; the rules of what may be reused
// are here.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::formats {

struct DumpFrame;

class RepeatedTokens {
 public:
  // The previous frame's line of one atom, when there is one to compare with.
  struct Previous {
    const double* values = nullptr;         // its values (null: nothing to compare with)
    std::string_view line;
    const std::uint32_t* starts = nullptr;  // where each of its tokens starts in it
  };

  // At a frame's start: whether its lines may be compared with the previous frame's: a piece in
  // memory (`in_memory`), whose earlier lines stay put, and a previous frame stored apart from
  // `f` with the same columns.
  void begin_frame(const DumpFrame& f, bool in_memory);
  // Whether this frame's lines are compared with the previous frame's (begin_frame's verdict).
  bool reusing() const { return reuse_; }
  // Atom a's previous line, where it may be compared: the bytes up to kTokenReach past `line`'s
  // end are the piece's (`data_end`), so a token comparison may read on.
  Previous previous(std::size_t a, std::string_view line, const char* data_end) const {
    if (!reuse_ || a >= previous_lines_.size() || line.data() + line.size() + kTokenReach > data_end) return {};
    return {previous_values_ + a * columns_, previous_lines_[a], previous_starts_.data() + a * columns_};
  }
  // Where atom a's token starts are to be kept (null when the lines are not kept).
  std::uint32_t* starts(std::size_t a, std::size_t atoms) {
    if (!keep_) return nullptr;
    if (lines_.size() <= a) grow(a, atoms);
    return starts_.data() + a * columns_;
  }
  // Keeps atom a's line for the next frame.
  void keep(std::size_t a, std::string_view line) {
    if (keep_) lines_[a] = line;
  }
  // At a frame's end: its lines stay readable for the next frame's comparison (in memory only).
  void end_frame(const DumpFrame& f);

  // How far a token comparison may read past the start of a token.
  static constexpr std::size_t kTokenReach = 40;

 private:
  void grow(std::size_t a, std::size_t atoms);  // room for atom a's line, as the frame's values grow

  bool keep_ = false, reuse_ = false;
  std::size_t columns_ = 0;
  std::vector<std::string_view> lines_, previous_lines_;
  std::vector<std::uint32_t> starts_, previous_starts_;  // where each token starts in its line
  const double* previous_values_ = nullptr;
  std::vector<std::string> previous_columns_;
};

}  // namespace granstack::formats
