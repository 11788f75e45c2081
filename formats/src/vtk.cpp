#include <granstack/formats/vtk.hpp>

#include <fmt/format.h>

#include <bit>
#include <stdexcept>

namespace granstack::formats {

namespace {

constexpr const char* byte_order() { return std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian"; }

// Appends a block of the appended data (its size in bytes, then its bytes); returns its offset.
template <typename T>
std::uint64_t append_block(std::string& data, const std::vector<T>& values) {
  const std::uint64_t offset = data.size();
  const std::uint64_t bytes = values.size() * sizeof(T);
  data.append(reinterpret_cast<const char*>(&bytes), sizeof bytes);
  data.append(reinterpret_cast<const char*>(values.data()), bytes);
  return offset;
}

std::string data_array(const char* type, const std::string& name, int components, std::uint64_t offset) {
  return fmt::format("        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" offset=\"{}\"/>\n",
                     type, name, components, offset);
}

}  // namespace

std::string vtp_document(const VtkPoints& points) {
  if (points.xyz.size() % 3 != 0) throw std::invalid_argument("vtk: point coordinates must come in threes");
  const std::size_t n = points.xyz.size() / 3;
  std::string data, arrays;
  for (const auto& a : points.arrays) {
    const bool integer = !a.integers.empty();
    const std::size_t size = integer ? a.integers.size() : a.reals.size();
    if (a.components < 1 || size != n * static_cast<std::size_t>(a.components)) {
      throw std::invalid_argument(fmt::format("vtk: array '{}' holds {} values for {} points of {} components", a.name, size, n,
                                              a.components));
    }
    arrays += data_array(integer ? "Int64" : "Float64", a.name, a.components,
                         integer ? append_block(data, a.integers) : append_block(data, a.reals));
  }
  const std::uint64_t at_points = append_block(data, points.xyz);
  // One vertex cell per point, so that ParaView draws them (as points or glyphs).
  std::vector<std::int64_t> connectivity(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  const std::uint64_t at_connectivity = append_block(data, connectivity);
  const std::uint64_t at_offsets = append_block(data, offsets);
  std::string out = fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"{}\" header_type=\"UInt64\">\n"
      "  <PolyData>\n"
      "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
      "      <PointData Scalars=\"{}\" Vectors=\"{}\">\n{}      </PointData>\n"
      "      <Points>\n{}      </Points>\n"
      "      <Verts>\n{}{}      </Verts>\n"
      "    </Piece>\n"
      "  </PolyData>\n"
      "  <AppendedData encoding=\"raw\">\n   _",
      byte_order(), n, n, points.scalars, points.vectors, arrays, data_array("Float64", "Points", 3, at_points),
      data_array("Int64", "connectivity", 1, at_connectivity), data_array("Int64", "offsets", 1, at_offsets));
  out += data;
  out += "\n  </AppendedData>\n</VTKFile>\n";
  return out;
}

std::string pvd_document(const std::vector<PvdEntry>& entries) {
  std::string out = fmt::format("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"{}\">\n"
                                "  <Collection>\n",
                                byte_order());
  for (const auto& e : entries) {
    out += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.time, e.file);
  }
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

}  // namespace granstack::formats
