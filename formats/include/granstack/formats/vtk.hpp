#pragma once
// Spheres for ParaView: VTK XML PolyData files (.vtp), one per frame, each sphere a vertex with
// its data arrays, and a ParaView data collection (.pvd) listing the frames with their times,
// which ParaView opens as one time series. The values are written raw in the file's appended
// block (this machine's byte order, declared in the file; 64-bit sizes), so a reader gets the
// very doubles written.
#include <cstdint>
#include <string>
#include <vector>

namespace granstack::formats {

// A per-point array: `components` values per point, doubles (Float64) or integers (Int64).
struct VtkArray {
  std::string name;
  int components = 1;
  std::vector<double> reals;
  std::vector<std::int64_t> integers;  // used instead of reals when not empty
};

struct VtkPoints {
  std::vector<double> xyz;  // x, y, z of each point
  std::vector<VtkArray> arrays;
  std::string scalars, vectors;  // the arrays ParaView colours by and draws as arrows first
};

// The .vtp file's bytes. Throws std::invalid_argument if an array's size is not its
// components times the points.
std::string vtp_document(const VtkPoints& points);

struct PvdEntry {
  double time = 0.0;  // s
  std::string file;   // relative to the .pvd
};
std::string pvd_document(const std::vector<PvdEntry>& entries);

}  // namespace granstack::formats
