#include <granstack/model/contact.hpp>
#include <granstack/model/stack.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace granstack::model {

double seat_height(double lower_radius, double upper_radius, int supports) {
  const double d = lower_radius + upper_radius;
  // The supports' centres lie sqrt(supports / 2) R_l from the axis.
  return std::sqrt(d * d - 0.5 * static_cast<double>(supports) * lower_radius * lower_radius);
}

double interface_height(double lower_radius, int n, bool aligned, int supports) {
  if (!aligned) return seat_height(lower_radius, n * lower_radius, supports);
  return static_cast<double>(n + 1) * lower_radius;
}

bool aligned_interface(int n, bool upper_columns_odd, bool lower_columns_odd) {
  const bool upper_site_odd = n % 2 == 1 && !upper_columns_odd;  // n (1 + C_k) mod 2
  const bool lower_site_odd = !lower_columns_odd;                 // (1 + C_(k+1)) mod 2
  return upper_site_odd == lower_site_odd;
}

bool extra_column_below(const StackSpec& spec, int k, bool upper_columns_odd) {
  if (spec.stacking == Stacking::by_ratio) return false;
  const int n = spec.ratio_below(k);
  const bool natural_odd = n % 2 == 1 && upper_columns_odd;  // n C_k
  return aligned_interface(n, upper_columns_odd, natural_odd) != (spec.stacking == Stacking::aligned);
}

MatrixChain matrix_chain(double block_radius, double half_pitch) {
  const double n = half_pitch / block_radius;
  if (!(n > 1.0)) return {};
  MatrixChain c;
  c.count = static_cast<int>(std::ceil(n + 1.0 - std::sqrt(2.0)));
  // In units of R: the offset sqrt((1 + r)^2 - 2) and the chain's (count - 1) 2 r span the half
  // pitch twice over, n = offset + (count - 1) r; the left side grows with r, from below n at
  // r = sqrt(2) - 1 to at least n at r = 1 (the count's choice): bisection to the last bit.
  const double links = c.count - 1;
  const auto offset = [](double r) { return std::sqrt((1.0 + r) * (1.0 + r) - 2.0); };
  double lo = std::sqrt(2.0) - 1.0, hi = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (offset(mid) + links * mid < n ? lo : hi) = mid;
  }
  c.radius = hi * block_radius;
  c.offset = offset(hi) * block_radius;
  return c;
}

Stack Stack::build(const StackSpec& spec) {
  require_valid(spec);
  Stack s;
  s.spec_ = spec;
  const auto lib = spec.material_library();
  const int nb = spec.blocks;
  const int supports = s.three_d() ? 4 : 2;

  // Radii and columns, top block first: R_k = r n_k n_(k+1) ... n_(N_B - 1) (r n^(N_B - k) with one
  // ratio n), C_(k+1) = C_k n_k (one more where the stacking asks, extra_column_below).
  int first_id = 1 + s.strikers();
  int columns = spec.top_columns;
  for (int k = 1; k <= nb; ++k) {
    Block b;
    b.index = k;
    b.material = spec.block_material(k);
    b.radius = spec.bottom_radius * spec.radius_factor(k);
    b.rows = spec.rows_of(k);
    b.columns = columns;
    b.depth = s.three_d() ? columns : s.panels();
    b.first_id = first_id;
    b.atom_type = k;
    b.sphere_mass = sphere_mass(b.radius, lib.at(b.material).density);
    first_id += b.count();
    if (k < nb) columns = columns * spec.ratio_below(k) + (extra_column_below(spec, k, columns % 2 == 1) ? 1 : 0);
    s.blocks_.push_back(b);
  }

  // Row-centre heights, from the bottom face (z = 0) up.
  s.blocks_.back().bottom_row_z = s.block(nb).radius;
  for (int k = nb - 1; k >= 1; --k) {
    const auto& below = s.block(k + 1);
    const double top_row_below = below.bottom_row_z + 2.0 * below.radius * (below.rows - 1);
    const bool aligned = aligned_interface(spec.ratio_below(k), s.block(k).columns % 2 == 1, below.columns % 2 == 1);
    s.blocks_[static_cast<std::size_t>(k - 1)].bottom_row_z = top_row_below + interface_height(below.radius, spec.ratio_below(k), aligned, supports);
  }

  s.spheres_.reserve(static_cast<std::size_t>(first_id - 1));
  const auto& top = s.block(1);
  // The striker rests on the two central top spheres (at x = -+R_1; in 3D the four at
  // (-+R_1, -+R_1)): sqrt(3) R_1 above their row for the study's striker (sqrt(2) R_1 in 3D).
  const double striker_radius = spec.striker_radius_ratio * top.radius;
  s.striker_mass_ = sphere_mass(striker_radius, lib.at(spec.effective_striker_material()).density);
  if (s.has_matrix()) s.matrix_density_ = lib.at(spec.effective_matrix_material()).density;
  const double seat = seat_height(top.radius, striker_radius, supports);
  for (int p = 1; p <= s.panels(); ++p) {
    if (!s.struck(p)) continue;
    // Above the midpoint of the two struck top spheres (x = 2 k R_1 for impact_offset k, on the panel's plane).
    const Eigen::Vector3d below{2.0 * spec.impact_offset * top.radius, s.panel_y(p), s.site(top, 1, 1, 1).z()};
    s.add({static_cast<int>(s.spheres_.size()) + 1, 0, 0, 0, 0, 0, s.striker_type(), striker_radius},
          below + seat * Eigen::Vector3d::UnitZ());
  }
  for (const auto& b : s.blocks_) {
    for (int i = 1; i <= b.rows; ++i) {
      for (int l = 1; l <= b.depth; ++l) {
        for (int j = 1; j <= b.columns; ++j) {
          s.add({s.id_of(b, i, j, l), b.index, i, j, l, 0, b.atom_type, b.radius}, s.site(b, i, j, l));
        }
      }
    }
  }
  if (s.has_matrix()) s.add_matrix();
  return s;
}

MatrixChain Stack::chain_beside(const Block& b) const {
  return has_matrix() ? matrix_chain(b.radius, block(1).radius) : MatrixChain{};
}

Eigen::Vector3d Stack::site(const Block& b, int row, int column, int column_y) const {
  return {lattice_centre(column, b.columns, b.radius),
          container() ? panel_y(column_y) : lattice_centre(column_y, b.depth, b.radius),
          b.bottom_row_z + 2.0 * b.radius * (b.rows - row)};
}

void Stack::add(Sphere s, const Eigen::Vector3d& centre) {
  s.x = centre.x();
  s.y = centre.y();
  s.z = centre.z();
  spheres_.push_back(s);
}

void Stack::add_matrix() {
  // Each pocket of a panel's block (the centre of four sites: rows i and i + 1, columns j and
  // j + 1) holds a chain along y to the same pocket of the next panel.
  int id = first_matrix_id();
  for (const auto& b : blocks_) {
    const auto chain = chain_beside(b);
    for (int g = 1; g < panels(); ++g) {
      for (int i = 1; i < b.rows; ++i) {
        for (int j = 1; j < b.columns; ++j) {
          const Eigen::Vector3d pocket = 0.5 * (site(b, i, j, g) + site(b, i + 1, j + 1, g));
          for (int m = 1; m <= chain.count; ++m) {
            add({id++, b.index, i, j, g, m, matrix_type(), chain.radius},
                pocket + (chain.offset + 2.0 * chain.radius * (m - 1)) * Eigen::Vector3d::UnitY());
          }
        }
      }
    }
  }
}

double Stack::lattice_centre(int j, int count, double radius) {
  // Centres at odd multiples of the radius about the axis: (2 j - 1 - C) R.
  return static_cast<double>(2 * j - 1 - count) * radius;
}

double Stack::panel_y(int panel) const {
  return container() ? lattice_centre(panel, spec_.panels, block(1).radius) : 0.0;
}

int Stack::id_of(const Block& b, int row, int column, int column_y) {
  return b.first_id + (row - 1) * b.layer() + (column_y - 1) * b.columns + (column - 1);
}

int Stack::id_of(int block_index, int row, int column, int column_y) const {
  const auto& b = block(block_index);
  if (row < 1 || row > b.rows || column < 1 || column > b.columns || column_y < 1 || column_y > b.depth) {
    throw std::out_of_range("row or column outside the block");
  }
  return id_of(b, row, column, column_y);
}

namespace {
// The column of block k of the path down from top sphere u_1 (its centre at x = u_1 R_1, u_1 odd).
// The path's centre in block k is x_k = u_k R_k, at v = n u_k in units of R_(k+1); the block below
// has a sphere there when v + 1 + C_(k+1) is even (x_j = (2j - 1 - C) R), and the path goes
// straight down to it (aligned); else the sphere rests on two at v -+ 1, of which the path takes
// the inner (toward the axis; on the axis, the one on `side`, +1 right, -1 left).
// j = (u_k + 1 + C_k) / 2. The path from -u_1 on side -1 is the mirror image of the one from u_1 on
// side +1, block by block.
int path_column(const Stack& s, const Block& b, long u, int side) {
  for (int k = 1; k < b.index; ++k) {
    const long v = s.spec().ratio_below(k) * u;
    const bool on_site = (v + 1 + s.block(k + 1).columns) % 2 == 0;
    u = on_site ? v : v == 0 ? side : v - (v > 0 ? 1 : -1);
  }
  return static_cast<int>((u + 1 + b.columns) / 2);
}

// The side of the axis a blow at impact_offset k is on: right for k >= 0 (the central blow's path
// takes the right-hand sphere), left for k < 0.
int blow_side(const StackSpec& spec) { return spec.impact_offset < 0 ? -1 : 1; }
}  // namespace

int Stack::impact_column(int block_index) const {
  // The top block's struck sphere on the blow's side, the outer of the two (x = (1 + 2k) R_1 for
  // k >= 0, (2k - 1) R_1 for k < 0): a blow at -k is the mirror image of one at k, and so is its path.
  const int side = blow_side(spec_);
  return path_column(*this, block(block_index), side * (1 + 2L * std::abs(spec_.impact_offset)), side);
}

int Stack::impact_path_id(int block_index, int row) const {
  const int c = impact_column(block_index);
  // In 3D the y-column follows the same rule from y = R_1 (the offset is along x only).
  return id_of(block_index, row, c, three_d() ? path_column(*this, block(block_index), 1, 1) : impact_panel());
}

int Stack::output_sphere_id() const { return impact_path_id(spec_.blocks, blocks_.back().rows); }

int Stack::middle_path_id(int block_index) const { return impact_path_id(block_index, block(block_index).rows / 2 + 1); }

std::vector<SeriesGroup> series_groups(const Stack& stack) {
  std::vector<SeriesGroup> g;
  for (const auto& b : stack.blocks()) {
    SeriesGroup group{fmt::format("block{}", b.index), std::to_string(b.index), b.atom_type, {}};
    for (int id = b.first_id; id <= b.last_id(); ++id) group.ids.push_back(id);
    g.push_back(std::move(group));
  }
  SeriesGroup strikers{"striker", "s", stack.striker_type(), {}};
  for (int id = 1; id <= stack.strikers(); ++id) strikers.ids.push_back(id);
  g.push_back(std::move(strikers));
  g.push_back({"output_sphere", "o", 0, {stack.output_sphere_id()}});
  g.push_back({"bottom_row", "b", 0, stack.bottom_row_ids()});
  for (const auto& b : stack.blocks()) {
    g.push_back({fmt::format("middle{}", b.index), fmt::format("m{}", b.index), 0, {stack.middle_path_id(b.index)}});
  }
  return g;
}

std::vector<std::string> series_contact_columns(const Stack& stack) {
  if (!normal_law(stack.spec().contact_model().normal).series_energy) return {};
  std::vector<std::string> c{kContactElasticColumn, kContactDissipatedColumn};
  for (const auto& g : series_groups(stack)) {
    if (g.atom_type != 0) c.push_back("dissipated_" + g.name);  // the blocks and the strikers
  }
  return c;
}

std::vector<int> Stack::bottom_row_ids() const {
  const auto& b = blocks_.back();
  std::vector<int> ids;
  for (int l = 1; l <= b.depth; ++l) {
    if (container() && l != impact_panel()) continue;
    for (int j = 1; j <= b.columns; ++j) ids.push_back(id_of(b.index, b.rows, j, l));
  }
  return ids;
}

std::vector<Wall> Stack::walls() const {
  std::vector<Wall> w;
  if (spec_.bottom == Boundary::wall) w.push_back({kBottomWallName, 2, 0.0, spec_.has_plate()});
  if (spec_.sides == Boundary::wall) {
    w.push_back({"wall_left", 0, -half_width()});
    w.push_back({"wall_right", 0, half_width()});
    if (three_d() || container()) {
      w.push_back({"wall_front", 1, -half_depth()});
      w.push_back({"wall_back", 1, half_depth()});
    }
  }
  if (container() && spec_.separator == Separator::walls) {
    for (int g = 1; g < panels(); ++g) w.push_back({fmt::format("wall_separator{}", g), 1, panel_y(g) + block(1).radius});
  }
  return w;
}

bool Stack::has_walls() const { return spec_.has_walls(); }

std::vector<std::string> Stack::type_materials() const {
  std::vector<std::string> out;
  for (const auto& b : blocks_) out.push_back(b.material);
  out.push_back(spec_.effective_striker_material());
  if (has_walls()) out.push_back(spec_.effective_wall_material());
  if (has_matrix()) out.push_back(spec_.effective_matrix_material());
  return out;
}

double Stack::half_width() const {
  double w = 0.0;  // the widest block's (they are one width unless the stacking adds a column)
  for (const auto& b : blocks_) w = std::max(w, b.columns * b.radius);
  return w;
}
double Stack::half_depth() const {
  return three_d() ? half_width() : static_cast<double>(panels()) * block(1).radius;
}
double Stack::lattice_mass() const {
  double m = 0.0;
  for (const auto& b : blocks_) m += b.sphere_mass * static_cast<double>(b.count()) * panels();
  return m;
}
double Stack::lattice_height() const {
  const auto& top = block(1);
  return top.bottom_row_z + top.radius * (2.0 * (top.rows - 1) + 1.0);
}
double Stack::footprint_area() const { return 4.0 * half_width() * half_depth(); }

double Stack::top_z() const { return spheres_.front().z + spheres_.front().radius; }
std::array<double, 6> Stack::box() const {
  const double r1 = block(1).radius;
  return {-half_width(), half_width(), -half_depth(), half_depth(), -r1, top_z() + r1};
}
double Stack::striker_radius() const { return spheres_.front().radius; }
double Stack::striker_mass() const { return striker_mass_; }

double Stack::mass(const Sphere& s) const {
  if (is_matrix(s)) return sphere_mass(s.radius, matrix_density_);
  return s.block > 0 ? block(s.block).sphere_mass : striker_mass_;
}
double Stack::incident_energy() const {
  return strikers() * (0.5 * striker_mass() * spec_.striker_speed * spec_.striker_speed);
}

}  // namespace granstack::model
