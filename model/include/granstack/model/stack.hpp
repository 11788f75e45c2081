#pragma once
// The nested-stack geometry of physics.md section 1, laid out in double precision with
// exactly touching spheres, and the index of which ids form each block, row and column.
//
// Coordinates: x horizontal, z vertical (the striker moves along -z); the strip has y = 0 for
// every centre, a 3D nest is a cubic lattice in x and y too. The lattice is centred on x = 0
// (and y = 0); the bottom face of the bottom block is the plane z = 0.
//
// Id order (documented, stable): id 1 is the striker (a container struck on every panel has one
// striker per panel, ids 1..P by panel); then block 1 (top) to block N_B; within
// a block row 1 (its top row, or layer) to its bottom row; within a row, y-column 1 (smallest
// y; the strip has one) upwards, and within it column 1 (smallest x) upwards:
//   id(block k, row i, column j, y-column l) = first_id(k) + (i - 1) * columns(k) * depth(k)
//                                              + (l - 1) * columns(k) + (j - 1).
// LIGGGHTS atom types: block k has type k, the striker N_B + 1, a wall (if any) N_B + 2, the
// matrix of a container (if any) the next.
//
// The container (geometry = panels): P strips side by side along y, panel p centred on
// y_p = (2p - 1 - P) R_1, so neighbouring top blocks touch; a panel is the y-column p of every
// block (column_y = p, the id formula above). The matrix spheres follow the last block: block
// region 2 to N_B, gap g (between panels g and g + 1), pocket row i (below row i), pocket column
// j (between columns j and j + 1), then m along the chain (increasing y).
#include <granstack/model/spec.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace granstack::model {

// A group of spheres whose kinetic energy the in-situ series records (series_groups).
struct SeriesGroup {
  std::string name;      // the deck's group, and the series' columns ke_trans_<name>, ke_rot_<name>
  std::string tag;       // the deck's compute ids, kt<tag> and kr<tag>
  int atom_type = 0;     // the deck selects the group by this atom type when not 0 (a block, the strikers)
  std::vector<int> ids;  // its atoms, ascending
};

struct Sphere {
  int id = 0;
  int block = 0;   // 1 = top; 0 for the striker
  int row = 0;     // 1 = top row of its block; 0 for the striker
  int column = 0;  // 1 = smallest x; 0 for the striker
  int column_y = 0;  // 1 = smallest y (the strip's only one; the panel in a container); 0 for the striker
  // A container's matrix sphere: block is the block it lies beside, row and column its pocket's
  // (below row `row`, right of column `column`), column_y the gap g (between panels g and g + 1)
  // and chain its place along the chain (1 = smallest y). 0 for every other sphere.
  int chain = 0;
  int atom_type = 0;
  double radius = 0.0;  // m
  double x = 0.0;       // m
  double y = 0.0;       // m
  double z = 0.0;       // m
  Eigen::Vector3d centre() const { return {x, y, z}; }
};

// A planar wall (LIGGGHTS wall/gran ... primitive xplane/yplane/zplane): the plane where
// coordinate `axis` (0 = x, 1 = y, 2 = z) equals `position`, in m.
struct Wall {
  std::string name;  // the deck's fix id: wall_bottom, wall_left, wall_right (3D: wall_front, wall_back)
  int axis = 2;
  double position = 0.0;  // where it stands at the start
  // The bottom wall that is the protected plate (StackSpec::plate_mass): it moves with it.
  bool plate = false;
  // Where it stands with the plate displaced by `plate_z` from its start.
  double at(double plate_z) const { return plate ? position + plate_z : position; }
  // How far a sphere of radius r centred at c reaches into the wall (LIGGGHTS's wall/gran test:
  // the centre's distance to the plane below r); > 0 only when it touches.
  double overlap(const std::array<double, 3>& c, double r, double plate_z = 0.0) const {
    return r - std::fabs(c[static_cast<std::size_t>(axis)] - at(plate_z));
  }
};

struct Block {
  int index = 0;  // 1 = top
  std::string material;
  double radius = 0.0;       // m
  int rows = 0;
  int columns = 0;           // along x
  int depth = 1;             // columns along y: 1 in the strip, `columns` in a 3D nest
  int first_id = 0;
  int atom_type = 0;
  double sphere_mass = 0.0;  // kg
  double bottom_row_z = 0.0;  // m: the height of its bottom row's centres
  int layer() const { return columns * depth; }  // spheres per row (per layer in 3D)
  int count() const { return rows * layer(); }
  int last_id() const { return first_id + count() - 1; }
};

// A container's matrix in one pocket of a panel's block (radius R), bridging it to the same
// pocket of the next panel, whose plane lies 2 N R away (N = R_1 / R): `count` spheres of
// `radius` in a row along y, each touching the next, the first `offset` from the panel's plane
// so that it touches the four spheres around the pocket (sqrt((R + r)^2 - 2 R^2)), the last
// likewise on the other panel. count is the fewest that keeps r below R, ceil(N + 1 - sqrt(2)),
// so the chains of neighbouring pockets never touch; none where the panels touch (N = 1).
struct MatrixChain {
  int count = 0;
  double radius = 0.0;  // m
  double offset = 0.0;  // m
};
MatrixChain matrix_chain(double block_radius, double half_pitch);

class Stack {
 public:
  // Throws SpecError when the spec is invalid.
  static Stack build(const StackSpec& spec);

  const StackSpec& spec() const { return spec_; }
  const std::vector<Sphere>& spheres() const { return spheres_; }  // ordered by id
  const Sphere& sphere(int id) const { return spheres_.at(static_cast<std::size_t>(id - 1)); }
  const std::vector<Block>& blocks() const { return blocks_; }     // top first
  const Block& block(int k) const { return blocks_.at(static_cast<std::size_t>(k - 1)); }

  int id_of(int block, int row, int column, int column_y = 1) const;
  bool three_d() const { return spec_.geometry == Geometry::nested3d; }
  bool container() const { return spec_.geometry == Geometry::panels; }
  int panels() const { return container() ? spec_.panels : 1; }
  // The panel whose impact path, output sphere and bottom row are measured (the one the striker
  // hits; the centre one when a striker hits every panel): 1 outside a container.
  int impact_panel() const { return spec_.measured_panel(); }
  // Whether a striker hits panel p; the strikers, one per panel hit, hold ids 1..strikers().
  bool struck(int panel) const { return spec_.strikes_every_panel() || panel == impact_panel(); }
  int strikers() const { return spec_.strikes_every_panel() ? spec_.panels : 1; }
  // The plane of panel p (y_p; 0 outside a container).
  double panel_y(int panel) const;
  bool has_matrix() const { return container() && spec_.separator == Separator::matrix; }
  // The matrix chain in each pocket of block b (matrix_chain at the container's pitch); none
  // without a matrix.
  MatrixChain chain_beside(const Block& b) const;
  // The matrix spheres, in id order after the last block (empty without a matrix).
  int first_matrix_id() const { return blocks_.back().last_id() + 1; }
  bool is_matrix(const Sphere& s) const { return s.chain > 0; }
  // The panel a sphere belongs to: column_y in a container, 1 for every block sphere of a strip
  // or nest (one panel); 0 for the striker and the matrix.
  int panel_of(const Sphere& s) const {
    return s.block == 0 || is_matrix(s) ? 0 : container() ? s.column_y : 1;
  }
  static constexpr int striker_id() { return 1; }  // the first striker
  // The column of block k on the impact path, the chain of contacts down from the top block's
  // right central sphere (x = R_1; with impact_offset k, the outer one of the two struck, at
  // x = (1 + 2k) R_1 for k > 0 and (2k - 1) R_1 for k < 0, so that the blow at -k and its path are
  // the mirror images of those at k): with an even radius ratio each sphere rests on two and the
  // path takes the inner one, toward the axis (on the axis, the one on the blow's side; for the
  // study's ratio 2, the central column just right of the axis in every block); with an odd ratio each rests on the one straight below (x = R_1 in
  // every block), and its side neighbours receive no downward push. In a 3D nest the path starts
  // at the central top sphere at (R_1, R_1) and follows the same rule along x and along y, so
  // without an offset its y-column is this column too.
  int impact_column(int block) const;
  // The sphere of row `row` of block k on the impact path: the impact column, in 3D its y-column
  // along the same rule, in a container the impacted panel.
  int impact_path_id(int block, int row) const;
  // The bottom sphere of the impact column of the bottom block (physics.md section 4; in 3D the
  // bottom sphere of the impact path, the same definition along y).
  int output_sphere_id() const;
  // The sphere of the impact path in the middle row of block k (row rows/2 + 1), away from the
  // block's interfaces: Fig. 2's per-sphere reading and where waves are counted.
  int middle_path_id(int block) const;
  std::vector<int> bottom_row_ids() const;  // the bottom row (in 3D the bottom layer), in id order

  int striker_type() const { return static_cast<int>(blocks_.size()) + 1; }
  // 0 when the spec has no wall.
  int wall_type() const { return has_walls() ? striker_type() + 1 : 0; }
  // Where the spec's walls stand, touching the lattice: the bottom face z = 0, the sides
  // x = -+half_width (and in 3D and in a container y = -+half_depth), a container's rigid
  // separators midway between its panels; in the deck's order (bottom, left, right, front,
  // back, separators by increasing y). The generator, refsim and the post-processor all place
  // walls through this.
  std::vector<Wall> walls() const;
  bool has_walls() const;
  // 0 without a matrix.
  int matrix_type() const { return has_matrix() ? (has_walls() ? wall_type() : striker_type()) + 1 : 0; }
  int atom_types() const { return std::max({striker_type(), wall_type(), matrix_type()}); }
  // The material of each LIGGGHTS atom type, index 0 = type 1.
  std::vector<std::string> type_materials() const;

  double half_width() const;       // m: the lattice spans -half_width..half_width in x (C R_1)
  double half_depth() const;       // m: and -half_depth..half_depth in y (R_1 in the strip, C R_1 in 3D, P R_1 in a container)
  double top_z() const;            // m: the top of the striker
  // m: the data file's box (xlo xhi ylo yhi zlo zhi), the least box LIGGGHTS's shrink-wrapped
  // boundaries keep. x and y end at the lattice's faces, so that MPI ranks' uniform split planes
  // fall between columns of every block (a margin put the planes through columns: the busiest
  // of 16 ranks held 1.28 times the mean); z runs from one top radius below the bottom face to
  // one above the striker.
  std::array<double, 6> box() const;
  double striker_radius() const;   // m
  double striker_mass() const;     // kg
  double mass(const Sphere& s) const;  // kg: the striker's, its block's or a matrix sphere's
  double incident_energy() const;  // E_in = 1/2 m_s v^2 (times the strikers), J
  // The design objectives' measures of a stack (docs/physics.md, "Designing stacks"):
  double lattice_mass() const;     // kg: every block's spheres (not the striker, the matrix or walls)
  double lattice_height() const;   // m: from the bottom face (z = 0) to the top of block 1's top row
  // m^2: the lattice's footprint, 2 half_width x 2 half_depth (in the strip, one top sphere's
  // diameter deep: the pitch at which the study's container sets strips side by side).
  double footprint_area() const;
  // kg/m^2: lattice_mass / footprint_area, the mass a panel of such stacks puts on each square
  // metre it protects.
  double areal_mass() const { return lattice_mass() / footprint_area(); }

 private:
  static int id_of(const Block& b, int row, int column, int column_y);
  static double lattice_centre(int j, int count, double radius);
  // The centre of the lattice site of block b in row i, column j and y-column l (in a container
  // the panel l's plane).
  Eigen::Vector3d site(const Block& b, int row, int column, int column_y) const;
  void add(Sphere s, const Eigen::Vector3d& centre);
  void add_matrix();
  StackSpec spec_;
  double striker_mass_ = 0.0;
  double matrix_density_ = 0.0;  // kg/m^3
  std::vector<Sphere> spheres_;
  std::vector<Block> blocks_;
};

// The groups of the in-situ series, in its column order: every block (top first), the strikers,
// the output sphere, the bottom row, and every block's middle_path_id. The generator's deck and
// refsim both record exactly these.
std::vector<SeriesGroup> series_groups(const Stack& stack);
// With a bottom wall, the series' last column: the z force the bottom wall exerts on the stack
// at each sample, in N (the protected object's load, upward positive). The deck stores each
// sphere's wall force (fix wall/gran ... store_force yes, fix_wall_gran_base.h: the sphere's
// force after the wall's contribution minus before it) and sums it over all spheres in atom
// order (compute reduce sum); refsim does the same.
inline constexpr const char* kBottomWallForceColumn = "fz_wall_bottom";
inline constexpr const char* kBottomWallName = "wall_bottom";
// With a protected plate (StackSpec::plate_mass), the series' last columns after the wall's force:
// the plate's displacement from where it stood at the start (m, along +z), its velocity (m/s) and
// its acceleration (m/s^2: the force on it over its mass), at each sample.
inline constexpr std::array<const char*, 3> kPlateColumns{"plate_z", "plate_vz", "plate_az"};
// The unit of a series column after the step, by its name: "N" for the wall's force, the plate's
// "m", "m/s" and "m/s^2", "J" for every energy (the groups' and the contacts').
inline std::string_view series_column_unit(std::string_view column) {
  if (column == kBottomWallForceColumn) return "N";
  if (column == kPlateColumns[0]) return "m";
  if (column == kPlateColumns[1]) return "m/s";
  if (column == kPlateColumns[2]) return "m/s^2";
  return "J";
}
// Where the case's law has its run report its contacts' energy (NormalLaw::series_energy), the
// series' columns after the groups' kinetic energies and before the wall's force: the elastic
// energy in all contacts, the work all have dissipated, then the share of it of each block's
// spheres and of the strikers' (dissipated_<group>: half of a pair contact's to each sphere, all
// of a wall contact's), in J; none otherwise.
std::vector<std::string> series_contact_columns(const Stack& stack);
inline constexpr const char* kContactElasticColumn = "contact_elastic";
inline constexpr const char* kContactDissipatedColumn = "contact_dissipated";

// The vertical distance between the centre of a sphere of radius R_k and the centres it rests
// on in the block below (radius R_k / n): nested, on two spheres at +-R_{k+1}
// (sqrt((n+1)^2 - 1) R_{k+1}, 2 sqrt(2) R_{k+1} for the study's n = 2); aligned, on the one
// directly below ((n+1) R_{k+1}). In a 3D nest (supports = 4) a nested sphere rests on four.
double interface_height(double lower_radius, int radius_ratio, bool aligned, int supports = 2);
// Whether the bottom row of a block with `upper_columns_odd` columns sits straight on lattice
// sites of the block below (ratio n, `lower_columns_odd` columns) or between two: the parity of
// the centres' x, n (2j - 1 - C_k) against (2i - 1 - C_(k+1)), in units of the lower radius.
bool aligned_interface(int radius_ratio, bool upper_columns_odd, bool lower_columns_odd);
// Whether block k + 1 has one column more than n C_k, so that block k rests on it as the spec's
// stacking says (StackSpec::stacking; never with by_ratio).
bool extra_column_below(const StackSpec& spec, int k, bool upper_columns_odd);
// The height of the centre of a sphere of radius `upper_radius` above the centres of the
// touching spheres of radius `lower_radius` it rests on, touching each: two at -+lower_radius
// (supports = 2), sqrt((R_u + R_l)^2 - R_l^2); or the four of a square pocket at (-+R_l, -+R_l)
// (supports = 4, a 3D nest), sqrt((R_u + R_l)^2 - 2 R_l^2). The striker's seat (sqrt(3) R_1 for
// the study's striker, sqrt(2) R_1 in 3D) and the even-ratio interface (2 sqrt(2) R_{k+1},
// sqrt(7) R_{k+1} in 3D).
double seat_height(double lower_radius, double upper_radius, int supports = 2);

}  // namespace granstack::model
