#include <granstack/formats/dump.hpp>
#include <granstack/formats/repeated_tokens.hpp>

#include <algorithm>

namespace granstack::formats {

void RepeatedTokens::begin_frame(const DumpFrame& f, bool in_memory) {
  keep_ = in_memory;
  columns_ = f.columns.size();
  reuse_ = keep_ && !previous_lines_.empty() && previous_values_ != nullptr && previous_values_ != f.values.data() &&
           previous_columns_ == f.columns;
}

void RepeatedTokens::grow(std::size_t a, std::size_t atoms) {
  lines_.resize(std::min(atoms, std::max<std::size_t>(a + 1, 2 * lines_.size())));
  starts_.resize(lines_.size() * columns_);
}

void RepeatedTokens::end_frame(const DumpFrame& f) {
  if (!keep_) {
    previous_lines_.clear();
    return;
  }
  previous_lines_.swap(lines_);
  previous_starts_.swap(starts_);
  previous_values_ = f.values.data();
  previous_columns_ = f.columns;
}

}  // namespace granstack::formats
