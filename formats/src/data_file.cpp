#include <granstack/formats/byte_source.hpp>
#include <granstack/formats/data_file.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/line_reader.hpp>
#include <granstack/os/workers.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <tuple>

namespace granstack::formats {

std::string format_data_file(const DataFile& d) {
  fmt::memory_buffer out;
  auto it = std::back_inserter(out);
  fmt::format_to(it, "{}\n\n{} atoms\n{} atom types\n\n", d.title, d.atoms.size(), d.atom_types);
  fmt::format_to(it, "{} {} xlo xhi\n{} {} ylo yhi\n{} {} zlo zhi\n", d.box[0], d.box[1], d.box[2], d.box[3], d.box[4],
                 d.box[5]);
  // The line after a section keyword is skipped by LIGGGHTS (read_data.cpp:1537-1544): keep it blank.
  fmt::format_to(it, "\nAtoms\n\n");
  for (const auto& a : d.atoms) {
    fmt::format_to(it, "{} {} {} {} {} {} {}\n", a.id, a.type, a.diameter, a.density, a.x, a.y, a.z);
  }
  fmt::format_to(it, "\nVelocities\n\n");
  for (const auto& a : d.atoms) {
    fmt::format_to(it, "{} {} {} {} {} {} {}\n", a.id, a.vx, a.vy, a.vz, a.wx, a.wy, a.wz);
  }
  return fmt::to_string(out);
}

namespace {
std::string_view strip_comment(std::string_view line) {
  auto hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
  while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
  return line;
}
}  // namespace

namespace {

// The whole file, decompressed where it is compressed.
std::string read_all(const std::string& path) {
  auto source = open_bytes(path);
  std::string text;
  if (const long n = source->remaining(); n > 0) text.reserve(static_cast<std::size_t>(n));
  char buffer[1 << 16];
  while (const auto got = source->read(buffer, sizeof buffer)) text.append(buffer, got);
  return text;
}

double number(std::string_view word) {
  double v = 0.0;
  if (!parse_double(word, v)) throw std::invalid_argument(fmt::format("'{}' is not a number", word));
  return v;
}

long integer(std::string_view word) {
  long v = 0;
  if (!parse_long(word, v)) throw std::invalid_argument(fmt::format("'{}' is not a whole number", word));
  return v;
}

void atom_line(const std::vector<std::string_view>& w, int atom_types, DataAtom& a) {
  if (w.size() != 7 && w.size() != 10) {
    throw std::invalid_argument(fmt::format(
        "an Atoms line has 7 or 10 words (id type diameter density x y z [ix iy iz]), this has {}", w.size()));
  }
  a.id = integer(w[0]);
  a.type = static_cast<int>(integer(w[1]));
  if (a.type < 1 || a.type > atom_types) throw std::invalid_argument(fmt::format("atom type {} is outside 1..{}", a.type, atom_types));
  a.diameter = number(w[2]);
  a.density = number(w[3]);
  a.x = number(w[4]);
  a.y = number(w[5]);
  a.z = number(w[6]);
}

// A Velocities line: the atom's id and its six values.
struct VelocityLine {
  long id = 0;
  std::array<double, 6> v{};
};

void velocity_line(const std::vector<std::string_view>& w, VelocityLine& out) {
  if (w.size() != 7) throw std::invalid_argument("a Velocities line has 7 words (id vx vy vz wx wy wz)");
  out.id = integer(w[0]);
  for (std::size_t k = 0; k < 6; ++k) out.v[k] = number(w[k + 1]);
}

// A section's `count` lines from byte `at` of `text` (whose first line is line `first_line` of
// the file), each parsed by `parse(words, index)` in `threads` pieces of whole lines at once.
// Returns the byte after the last line. The first failing line in the file's order is thrown.
template <class Parse>
std::size_t parse_lines(const std::string& path, std::string_view text, std::size_t at, long count, long first_line,
                        const std::string& section, int threads, Parse parse) {
  // Where each piece starts: line k * count / threads.
  const long pieces = std::max(1L, std::min<long>(threads, count / 4096 + 1));
  std::vector<std::size_t> starts{at};
  std::size_t pos = at;
  for (long line = 0; line < count; ++line) {
    if (pieces > 1 && line > 0 && line == static_cast<long>(starts.size()) * count / pieces) starts.push_back(pos);
    const auto nl = text.find('\n', pos);
    if (nl == std::string_view::npos && !(line + 1 == count && pos < text.size())) {
      throw FormatError(path, first_line + line - 1, fmt::format("{} section ends after {} of {} lines", section, line, count));
    }
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
  }
  starts.push_back(pos);
  struct Failure {
    long line = -1;
    std::string message;
  };
  std::vector<Failure> failures(starts.size() - 1);
  const auto run_piece = [&](std::size_t p) {
    LineReader reader(text.substr(starts[p], starts[p + 1] - starts[p]), path);
    std::vector<std::string_view> w;
    std::string_view line;
    const long first = static_cast<long>(p) * count / pieces;
    for (long k = first; reader.next(line); ++k) {
      split_words(line, w);
      try {
        parse(w, static_cast<std::size_t>(k));
      } catch (const std::invalid_argument& e) {
        failures[p] = {first_line + k, e.what()};
        return;
      }
    }
  };
  os::Workers(static_cast<int>(starts.size() - 1)).run([&](int p) { run_piece(static_cast<std::size_t>(p)); });
  for (const auto& f : failures) {
    if (f.line >= 0) throw FormatError(path, f.line, f.message);
  }
  return pos;
}

DataFile parse(const std::string& path, bool with_atoms, int threads) {
  const std::string text = read_all(path);
  auto reader = std::make_unique<LineReader>(std::string_view(text), path);
  DataFile d;
  std::string_view line;
  if (!reader->next(line)) throw FormatError(path, 0, "empty file: a LIGGGHTS data file starts with a title line");
  d.title = std::string(line);
  long natoms = -1;
  std::vector<std::string_view> w;
  long line_base = 0;  // the reader counts lines from its piece's first
  auto fail = [&](const std::string& msg) { return FormatError(path, line_base + reader->line_number(), msg); };
  auto checked = [&](auto f) {
    try {
      return f();
    } catch (const std::invalid_argument& e) {
      throw fail(e.what());
    }
  };

  // Header.
  std::string section;
  while (reader->next(line)) {
    auto text_line = strip_comment(line);
    if (text_line.empty()) continue;
    split_words(text_line, w);
    if (w.size() == 2 && w[1] == "atoms") {
      natoms = checked([&] { return integer(w[0]); });
    } else if (w.size() == 3 && w[1] == "atom" && w[2] == "types") {
      d.atom_types = static_cast<int>(checked([&] { return integer(w[0]); }));
    } else if (w.size() == 4 && (w[2] == "xlo" || w[2] == "ylo" || w[2] == "zlo")) {
      const int axis = w[2] == "xlo" ? 0 : w[2] == "ylo" ? 1 : 2;
      d.box[static_cast<std::size_t>(2 * axis)] = checked([&] { return number(w[0]); });
      d.box[static_cast<std::size_t>(2 * axis + 1)] = checked([&] { return number(w[1]); });
    } else if (w.size() == 1 && (w[0] == "Atoms" || w[0] == "Velocities")) {
      section = std::string(w[0]);
      break;
    } else {
      throw fail(fmt::format("unexpected header line '{}'", text_line));
    }
  }
  if (natoms < 0) throw fail("no 'N atoms' line in the header");
  if (d.atom_types < 1) throw fail("no 'T atom types' line in the header");
  if (!with_atoms) return d;

  std::map<long, std::size_t> index;  // only where the ids are not 1..N in order
  bool dense = true, have_atoms = false;
  const auto where = [&](long id) -> std::optional<std::size_t> {
    if (dense) return id >= 1 && id <= natoms ? std::optional<std::size_t>(static_cast<std::size_t>(id - 1)) : std::nullopt;
    const auto it = index.find(id);
    return it == index.end() ? std::nullopt : std::optional<std::size_t>(it->second);
  };
  // LIGGGHTS (read_data) refuses velocities of atoms it has not read: "Must read Atoms before Velocities".
  if (section == "Velocities") throw fail("a Velocities section before the Atoms section: the atoms come first");
  while (!section.empty()) {
    if (!reader->next(line)) throw fail(fmt::format("file ends after the '{}' keyword", section));  // the skipped line
    const long first_line = line_base + reader->line_number() + 1;
    const auto nl = text.find('\n', static_cast<std::size_t>(line.data() - text.data()));
    const std::size_t begin = nl == std::string::npos ? text.size() : nl + 1;
    std::size_t end = 0;
    if (section == "Atoms") {
      d.atoms.resize(static_cast<std::size_t>(natoms));
      std::optional<FormatError> parse_failure;
      try {
        end = parse_lines(path, text, begin, natoms, first_line, section, threads,
                          [&](const std::vector<std::string_view>& words, std::size_t k) { atom_line(words, d.atom_types, d.atoms[k]); });
      } catch (const FormatError& e) {
        parse_failure = e;
      }
      // A repeated id, unless a line before it failed (the order a line-by-line reading meets them).
      const long checked_lines = parse_failure ? parse_failure->line() - first_line : natoms;
      for (long k = 0; k < checked_lines; ++k) dense = dense && d.atoms[static_cast<std::size_t>(k)].id == k + 1;
      if (!dense || checked_lines < natoms) {
        dense = false;
        for (long k = 0; k < checked_lines; ++k) {
          if (!index.emplace(d.atoms[static_cast<std::size_t>(k)].id, static_cast<std::size_t>(k)).second) {
            throw FormatError(path, first_line + k, fmt::format("atom id {} appears twice", d.atoms[static_cast<std::size_t>(k)].id));
          }
        }
      }
      if (parse_failure) throw *parse_failure;
      have_atoms = true;
    } else {
      std::vector<VelocityLine> lines(static_cast<std::size_t>(natoms));
      std::optional<FormatError> parse_failure;
      try {
        end = parse_lines(path, text, begin, natoms, first_line, section, threads,
                          [&](const std::vector<std::string_view>& words, std::size_t k) { velocity_line(words, lines[k]); });
      } catch (const FormatError& e) {
        parse_failure = e;
      }
      const long checked_lines = parse_failure ? parse_failure->line() - first_line : natoms;
      for (long k = 0; k < checked_lines; ++k) {
        const auto& v = lines[static_cast<std::size_t>(k)];
        const auto i = where(v.id);
        if (!i) throw FormatError(path, first_line + k, fmt::format("velocity for unknown atom id {}", v.id));
        auto& a = d.atoms[*i];
        std::tie(a.vx, a.vy, a.vz, a.wx, a.wy, a.wz) = std::tie(v.v[0], v.v[1], v.v[2], v.v[3], v.v[4], v.v[5]);
      }
      if (parse_failure) throw *parse_failure;
    }
    // On after the section, lines counted from its end.
    line_base = first_line + natoms - 1;
    reader = std::make_unique<LineReader>(std::string_view(text).substr(end), path);
    section.clear();
    while (reader->next(line)) {
      auto text_line = strip_comment(line);
      if (text_line.empty()) continue;
      if (text_line == "Velocities" && have_atoms) {
        section = "Velocities";
        break;
      }
      throw fail(fmt::format("unexpected line '{}' after a section", text_line));
    }
  }
  if (!have_atoms) throw fail("no Atoms section");
  return d;
}

}  // namespace

DataFile parse_data_file(const std::string& path, int threads) { return parse(path, true, std::max(1, threads)); }
DataFile read_data_header(const std::string& path) { return parse(path, false, 1); }

}  // namespace granstack::formats
