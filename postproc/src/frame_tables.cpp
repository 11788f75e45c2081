#include "frame_tables.hpp"

#include <fmt/compile.h>

#include <cstdio>
#include <iterator>
#include <stdexcept>

namespace granstack::postproc::detail {

namespace fs = std::filesystem;

// A CSV table written as it grows: rows collect in a buffer that goes to a temporary file
// beside the target whenever it passes 64 KiB, and the file is renamed into place at the end, so
// memory does not grow with the number of frames and no reader sees half a table. The buffer
// stays below malloc's mmap threshold (128 KiB), so case after case reuses the same heap pages
// instead of faulting fresh ones in (reproduce's 91 cases write 230 MB of tables).
class StreamedTable {
 public:
  StreamedTable(fs::path target, bool write) : target_(std::move(target)), write_(write) {}
  ~StreamedTable() {
    if (file_ != nullptr) {
      std::fclose(file_);
      std::error_code ec;
      fs::remove(temporary(), ec);
    }
  }
  std::back_insert_iterator<fmt::memory_buffer> out() { return std::back_inserter(buffer_); }
  void append(const fmt::memory_buffer& text) { buffer_.append(text.data(), text.data() + text.size()); }
  void row_done() {
    if (buffer_.size() > (1u << 16)) flush();
  }
  void finish() {
    flush();
    if (file_ == nullptr) return;
    const bool ok = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok) throw std::runtime_error(fmt::format("{}: cannot write", temporary().string()));
    fs::rename(temporary(), target_);
  }

 private:
  fs::path temporary() const { return target_.string() + ".tmp"; }
  void flush() {
    if (write_) {
      if (file_ == nullptr) {
        fs::create_directories(target_.parent_path());
        file_ = std::fopen(temporary().c_str(), "wb");
        if (file_ == nullptr) throw std::runtime_error(fmt::format("{}: cannot write", temporary().string()));
      }
      if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) {
        throw std::runtime_error(fmt::format("{}: cannot write", temporary().string()));
      }
    }
    buffer_.clear();
  }
  fs::path target_;
  bool write_;
  std::FILE* file_ = nullptr;
  fmt::memory_buffer buffer_;
};


std::vector<double> panel_energies(const FrameEnergy& e) {
  std::vector<double> panels(e.column_y_ke.empty() ? 0 : e.column_y_ke.front().size(), 0.0);
  for (const auto& block : e.column_y_ke) {
    for (std::size_t p = 0; p < panels.size(); ++p) panels[p] += block[p];
  }
  return panels;
}

namespace {

void values(fmt::memory_buffer& out, const std::vector<double>& xs) {
  for (const double x : xs) fmt::format_to(std::back_inserter(out), FMT_COMPILE(",{}"), x);
}

// block_ke.csv: each block's kinetic energy, the striker's, the output sphere's, the bottom
// row's, the total, the elastic energy and their sum.
const FrameTable kBlocks{
    [](const model::Stack&) { return std::string("block_ke.csv"); },
    [](const model::Stack& stack, fmt::memory_buffer& out) {
      for (int k = 1; k <= stack.spec().blocks; ++k) fmt::format_to(std::back_inserter(out), ",ke_block{}_J", k);
      fmt::format_to(std::back_inserter(out),
                     ",ke_striker_J,ke_output_sphere_J,ke_bottom_row_J,ke_total_J,elastic_J,energy_total_J");
    },
    [](const FrameEnergy& e, double, bool, fmt::memory_buffer& out) {
      values(out, e.block_ke);
      fmt::format_to(std::back_inserter(out), FMT_COMPILE(",{},{},{},{},{},{}"), e.striker_ke, e.output_sphere_ke,
                     e.bottom_row_ke, e.kinetic, e.elastic, e.kinetic + e.elastic);
    }};

// energy_parts.csv: each block's sideways, downward and rotational parts, the top row's
// sideways and downward energy (the friction study's), and what has been dissipated.
const FrameTable kParts{
    [](const model::Stack&) { return std::string("energy_parts.csv"); },
    [](const model::Stack& stack, fmt::memory_buffer& out) {
      for (const auto& b : stack.blocks()) {
        fmt::format_to(std::back_inserter(out), ",ke_sideways_block{0}_J,ke_downward_block{0}_J,ke_rotational_block{0}_J",
                       b.index);
      }
      // A path-dependent law's elastic energy is not in the dump: what is not kinetic is then
      // stored and dissipated together.
      fmt::format_to(std::back_inserter(out), ",top_row_sideways_J,top_row_downward_J,{}",
                     model::has_overlap_energy(stack.spec().contact_model()) ? "dissipated_J" : "elastic_and_dissipated_J");
    },
    [](const FrameEnergy& e, double e_in, bool, fmt::memory_buffer& out) {
      for (std::size_t k = 0; k < e.block_ke.size(); ++k) {
        fmt::format_to(std::back_inserter(out), FMT_COMPILE(",{},{},{}"), e.block_ke_sideways[k], e.block_ke_downward[k],
                       e.block_ke_rotational[k]);
      }
      fmt::format_to(std::back_inserter(out), FMT_COMPILE(",{},{},{}"), e.top_row_sideways, e.top_row_downward,
                     e_in - e.kinetic - e.elastic);
    }};

// row_ke.csv: every row of every block.
const FrameTable kRows{
    [](const model::Stack&) { return std::string("row_ke.csv"); },
    [](const model::Stack& stack, fmt::memory_buffer& out) {
      for (const auto& b : stack.blocks()) {
        for (int i = 1; i <= b.rows; ++i) fmt::format_to(std::back_inserter(out), ",ke_block{}_row{}_J", b.index, i);
      }
    },
    [](const FrameEnergy& e, double, bool, fmt::memory_buffer& out) {
      for (const auto& block : e.row_ke) values(out, block);
    }};

// column_ke.csv: every column (along x) of every block.
const FrameTable kColumns{
    [](const model::Stack&) { return std::string("column_ke.csv"); },
    [](const model::Stack& stack, fmt::memory_buffer& out) {
      for (const auto& b : stack.blocks()) {
        for (int j = 1; j <= b.columns; ++j) fmt::format_to(std::back_inserter(out), ",ke_block{}_column{}_J", b.index, j);
      }
    },
    [](const FrameEnergy& e, double, bool, fmt::memory_buffer& out) {
      for (const auto& block : e.column_ke) values(out, block);
    }};

// A 3D nest's columns along y (column_y_ke.csv); a container's panels, whole, then the matrix,
// then per block (panel_ke.csv). The strip has neither.
const FrameTable kDepth{
    [](const model::Stack& stack) {
      return stack.container() ? std::string("panel_ke.csv") : stack.three_d() ? std::string("column_y_ke.csv") : "";
    },
    [](const model::Stack& stack, fmt::memory_buffer& out) {
      const bool container = stack.container();
      if (container) {
        for (int p = 1; p <= stack.panels(); ++p) fmt::format_to(std::back_inserter(out), ",ke_panel{}_J", p);
        fmt::format_to(std::back_inserter(out), ",ke_matrix_J");
      }
      for (const auto& b : stack.blocks()) {
        for (int l = 1; l <= b.depth; ++l) {
          fmt::format_to(std::back_inserter(out), ",ke_block{}_{}{}_J", b.index, container ? "panel" : "column_y", l);
        }
      }
    },
    [](const FrameEnergy& e, double, bool container, fmt::memory_buffer& out) {
      if (container) {
        values(out, panel_energies(e));
        fmt::format_to(std::back_inserter(out), FMT_COMPILE(",{}"), e.matrix_ke);
      }
      for (const auto& block : e.column_y_ke) values(out, block);
    }};

}  // namespace

const std::vector<FrameTable>& frame_tables() {
  static const std::vector<FrameTable> tables{kBlocks, kParts, kRows, kColumns, kDepth};
  return tables;
}

FrameTables::FrameTables(const model::Stack& stack, const fs::path& dir, bool write) : container_(stack.container()) {
  for (const auto& t : frame_tables()) {
    const auto file = t.file(stack);
    if (file.empty()) continue;
    kinds_.push_back(&t);
    files_.push_back(std::make_unique<StreamedTable>(dir / file, write));
    fmt::memory_buffer header;
    fmt::format_to(std::back_inserter(header), "step,time_s");
    t.header(stack, header);
    header.push_back('\n');
    files_.back()->append(header);
  }
}

FrameTables::~FrameTables() = default;

void FrameTables::format(const FrameEnergy& e, double time, double e_in, std::vector<fmt::memory_buffer>& rows) const {
  rows.resize(kinds_.size());
  for (std::size_t k = 0; k < kinds_.size(); ++k) {
    auto& row = rows[k];
    row.clear();
    fmt::format_to(std::back_inserter(row), FMT_COMPILE("{},{}"), e.step, time);
    kinds_[k]->row(e, e_in, container_, row);
    row.push_back('\n');
  }
}

void FrameTables::append(const std::vector<fmt::memory_buffer>& rows) {
  for (std::size_t k = 0; k < files_.size(); ++k) {
    files_[k]->append(rows[k]);
    files_[k]->row_done();
  }
}

void FrameTables::finish() {
  for (auto& f : files_) f->finish();
}

}  // namespace granstack::postproc::detail
