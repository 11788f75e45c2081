#pragma once
// LIGGGHTS `read_data` files for atom_style granular (docs/liggghts.md section 4).
#include <array>
#include <string>
#include <vector>

namespace granstack::formats {

struct DataAtom {
  long id = 0;
  int type = 0;
  double diameter = 0.0;  // m
  double density = 0.0;   // kg/m^3
  double x = 0.0, y = 0.0, z = 0.0;
  double vx = 0.0, vy = 0.0, vz = 0.0;  // m/s
  double wx = 0.0, wy = 0.0, wz = 0.0;  // rad/s
  bool operator==(const DataAtom&) const = default;
};

struct DataFile {
  std::string title;  // the first line (LIGGGHTS skips it)
  int atom_types = 0;
  std::array<double, 6> box{};  // xlo xhi ylo yhi zlo zhi
  std::vector<DataAtom> atoms;
  bool operator==(const DataFile&) const = default;
};

// Every number is written in its shortest round-trip form, so reading the file (here or in
// LIGGGHTS, which parses with atof) gives back exactly the same doubles.
std::string format_data_file(const DataFile& data);
// Parses what format_data_file writes and what LIGGGHTS accepts for this atom style
// (header keywords, Atoms and optional Velocities sections, '#' comments).
// Throws FormatError with the line number. The sections' lines are parsed in `threads` pieces
// at once; the result and the error (the first failing line) do not depend on how many.
DataFile parse_data_file(const std::string& path, int threads = 1);
// The title, atom types and box alone (no atoms), for what needs the box of a big case.
DataFile read_data_header(const std::string& path);

}  // namespace granstack::formats
