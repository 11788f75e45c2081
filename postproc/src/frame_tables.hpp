#pragma once
// The tables reduce writes with one row per dump frame (reduce/*.csv), each in one place: its
// file, the stacks that have it, its header and its row. A new per-frame table is an entry of
// frame_tables() (frame_tables.cpp); reduce_case's frame loop fills every one that applies.
#include <granstack/model/stack.hpp>
#include <granstack/postproc/energy.hpp>

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace granstack::postproc::detail {

struct FrameTable {
  // Its file name in reduce/ for this stack ("" where the stack has no such table).
  std::string (*file)(const model::Stack& stack);
  // Its columns after "step,time_s", each with a leading comma.
  void (*header)(const model::Stack& stack, fmt::memory_buffer& out);
  // A frame's values after "step,time", each with a leading comma (e_in: the incident energy).
  void (*row)(const FrameEnergy& e, double e_in, bool container, fmt::memory_buffer& out);
};

// Every table, in the order reduce writes them; the first is block_ke.csv, the summary's csv_path.
const std::vector<FrameTable>& frame_tables();

class StreamedTable;

// The tables of one case, streamed to their files: each frame's rows are formatted on the
// thread that analysed it (format), then appended in frame order (append).
class FrameTables {
 public:
  FrameTables(const model::Stack& stack, const std::filesystem::path& dir, bool write);
  ~FrameTables();
  void format(const FrameEnergy& e, double time, double e_in, std::vector<fmt::memory_buffer>& rows) const;
  void append(const std::vector<fmt::memory_buffer>& rows);
  void finish();  // renames every file into place

 private:
  bool container_;
  std::vector<const FrameTable*> kinds_;
  std::vector<std::unique_ptr<StreamedTable>> files_;
};

// A container's panels' energies (each panel's blocks summed), in panel order.
std::vector<double> panel_energies(const FrameEnergy& e);

}  // namespace granstack::postproc::detail
