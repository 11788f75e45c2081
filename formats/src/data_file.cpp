#include <granstack/formats/data_file.hpp>
#include <granstack/formats/error.hpp>
#include <granstack/formats/line_reader.hpp>

#include <fmt/format.h>

#include <map>

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

DataFile parse_data_file(const std::string& path) {
  LineReader reader(path);
  DataFile d;
  std::string_view line;
  if (!reader.next(line)) throw FormatError(path, 0, "empty file: a LIGGGHTS data file starts with a title line");
  d.title = std::string(line);
  long natoms = -1;
  std::vector<std::string_view> w;
  auto fail = [&](const std::string& msg) -> FormatError { return FormatError(path, reader.line_number(), msg); };
  auto number = [&](std::string_view word) {
    double v = 0.0;
    if (!parse_double(word, v)) throw fail(fmt::format("'{}' is not a number", word));
    return v;
  };
  auto integer = [&](std::string_view word) {
    long v = 0;
    if (!parse_long(word, v)) throw fail(fmt::format("'{}' is not a whole number", word));
    return v;
  };

  // Header.
  std::string section;
  while (reader.next(line)) {
    auto text = strip_comment(line);
    if (text.empty()) continue;
    split_words(text, w);
    if (w.size() == 2 && w[1] == "atoms") {
      natoms = integer(w[0]);
    } else if (w.size() == 3 && w[1] == "atom" && w[2] == "types") {
      d.atom_types = static_cast<int>(integer(w[0]));
    } else if (w.size() == 4 && (w[2] == "xlo" || w[2] == "ylo" || w[2] == "zlo")) {
      const int axis = w[2] == "xlo" ? 0 : w[2] == "ylo" ? 1 : 2;
      d.box[static_cast<std::size_t>(2 * axis)] = number(w[0]);
      d.box[static_cast<std::size_t>(2 * axis + 1)] = number(w[1]);
    } else if (w.size() == 1 && (w[0] == "Atoms" || w[0] == "Velocities")) {
      section = std::string(w[0]);
      break;
    } else {
      throw fail(fmt::format("unexpected header line '{}'", text));
    }
  }
  if (natoms < 0) throw fail("no 'N atoms' line in the header");
  if (d.atom_types < 1) throw fail("no 'T atom types' line in the header");

  std::map<long, std::size_t> index;
  bool have_atoms = false;
  while (!section.empty()) {
    if (!reader.next(line)) throw fail(fmt::format("file ends after the '{}' keyword", section));  // the skipped line
    for (long i = 0; i < natoms; ++i) {
      if (!reader.next(line)) throw fail(fmt::format("{} section ends after {} of {} lines", section, i, natoms));
      split_words(line, w);
      if (section == "Atoms") {
        if (w.size() != 7 && w.size() != 10) {
          throw fail(fmt::format("an Atoms line has 7 or 10 words (id type diameter density x y z [ix iy iz]), "
                                 "this has {}",
                                 w.size()));
        }
        DataAtom a;
        a.id = integer(w[0]);
        a.type = static_cast<int>(integer(w[1]));
        if (a.type < 1 || a.type > d.atom_types) {
          throw fail(fmt::format("atom type {} is outside 1..{}", a.type, d.atom_types));
        }
        a.diameter = number(w[2]);
        a.density = number(w[3]);
        a.x = number(w[4]);
        a.y = number(w[5]);
        a.z = number(w[6]);
        if (!index.emplace(a.id, d.atoms.size()).second) throw fail(fmt::format("atom id {} appears twice", a.id));
        d.atoms.push_back(a);
      } else {
        if (w.size() != 7) throw fail("a Velocities line has 7 words (id vx vy vz wx wy wz)");
        const auto it = index.find(integer(w[0]));
        if (it == index.end()) throw fail(fmt::format("velocity for unknown atom id {}", w[0]));
        auto& a = d.atoms[it->second];
        a.vx = number(w[1]);
        a.vy = number(w[2]);
        a.vz = number(w[3]);
        a.wx = number(w[4]);
        a.wy = number(w[5]);
        a.wz = number(w[6]);
      }
    }
    if (section == "Atoms") have_atoms = true;
    section.clear();
    while (reader.next(line)) {
      auto text = strip_comment(line);
      if (text.empty()) continue;
      if (text == "Velocities" && have_atoms) {
        section = "Velocities";
        break;
      }
      throw fail(fmt::format("unexpected line '{}' after a section", text));
    }
  }
  if (!have_atoms) throw fail("no Atoms section");
  return d;
}

}  // namespace granstack::formats
