#include <granstack/model/contact.hpp>
#include <granstack/model/stack.hpp>

#include <cmath>

namespace granstack::model {

double seat_height(double lower_radius, double upper_radius, int supports) {
  const double d = lower_radius + upper_radius;
  // The supports' centres lie sqrt(supports / 2) R_l from the axis.
  return std::sqrt(d * d - 0.5 * static_cast<double>(supports) * lower_radius * lower_radius);
}

double interface_height(double lower_radius, int n, int supports) {
  if (n % 2 == 0) return seat_height(lower_radius, n * lower_radius, supports);
  return static_cast<double>(n + 1) * lower_radius;
}

Stack Stack::build(const StackSpec& spec) {
  require_valid(spec);
  Stack s;
  s.spec_ = spec;
  const auto lib = spec.material_library();
  const int nb = spec.blocks;
  const int n = spec.radius_ratio;
  const int supports = s.three_d() ? 4 : 2;

  // Radii and columns, top block first: R_k = r n^(N_B - k), C_k = C n^(k-1).
  int first_id = 2;
  int columns = spec.top_columns;
  for (int k = 1; k <= nb; ++k) {
    Block b;
    b.index = k;
    b.material = spec.block_material(k);
    b.radius = spec.bottom_radius * std::pow(static_cast<double>(n), nb - k);
    b.rows = spec.rows;
    b.columns = columns;
    b.depth = s.three_d() ? columns : 1;
    b.first_id = first_id;
    b.atom_type = k;
    b.sphere_mass = sphere_mass(b.radius, lib.at(b.material).density);
    first_id += b.count();
    columns *= n;
    s.blocks_.push_back(b);
  }

  // Row-centre heights, from the bottom face (z = 0) up.
  std::vector<double> bottom_row_z(static_cast<std::size_t>(nb + 1));
  bottom_row_z[static_cast<std::size_t>(nb)] = s.block(nb).radius;
  for (int k = nb - 1; k >= 1; --k) {
    const auto& below = s.block(k + 1);
    const double top_row_below = bottom_row_z[static_cast<std::size_t>(k + 1)] + 2.0 * below.radius * (below.rows - 1);
    bottom_row_z[static_cast<std::size_t>(k)] = top_row_below + interface_height(below.radius, n, supports);
  }

  s.spheres_.reserve(static_cast<std::size_t>(first_id - 1));
  const auto& top = s.block(1);
  const double top_row_z = bottom_row_z[1] + 2.0 * top.radius * (top.rows - 1);
  // The striker rests on the two central top spheres (at x = -+R_1; in 3D the four at
  // (-+R_1, -+R_1)): sqrt(3) R_1 above their row for the study's striker (sqrt(2) R_1 in 3D).
  const double striker_radius = spec.striker_radius_ratio * top.radius;
  s.striker_mass_ = sphere_mass(striker_radius, lib.at(spec.effective_striker_material()).density);
  s.spheres_.push_back({1, 0, 0, 0, 0, s.striker_type(), striker_radius, 0.0, 0.0,
                        top_row_z + seat_height(top.radius, striker_radius, supports)});
  // Centres at odd multiples of the radius about the axis: (2 j - 1 - C) R.
  const auto centre = [](int j, int count, double radius) { return static_cast<double>(2 * j - 1 - count) * radius; };
  for (const auto& b : s.blocks_) {
    for (int i = 1; i <= b.rows; ++i) {
      const double z = bottom_row_z[static_cast<std::size_t>(b.index)] + 2.0 * b.radius * (b.rows - i);
      for (int l = 1; l <= b.depth; ++l) {
        for (int j = 1; j <= b.columns; ++j) {
          s.spheres_.push_back({s.id_of(b, i, j, l), b.index, i, j, l, b.atom_type, b.radius, centre(j, b.columns, b.radius),
                                centre(l, b.depth, b.radius), z});
        }
      }
    }
  }
  return s;
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

int Stack::impact_column(int block_index) const {
  // The path's centre in block k is x_k = u_k R_k: u_1 = 1 (the top block's right central
  // sphere); an even ratio n rests a sphere on two at x_k -+ R_(k+1), of which the path takes the
  // inner, u_(k+1) = n u_k - 1; an odd one on the one straight below, u_(k+1) = n u_k. u_k stays
  // odd, and x_j = (2j - 1 - C_k) R_k gives j = (u_k + 1 + C_k) / 2.
  const int n = spec_.radius_ratio;
  long u = 1;
  for (int k = 1; k < block_index; ++k) u = n % 2 == 0 ? n * u - 1 : n * u;
  return static_cast<int>((u + 1 + block(block_index).columns) / 2);
}

int Stack::output_sphere_id() const {
  const auto& b = blocks_.back();
  const int c = impact_column(b.index);
  return id_of(b.index, b.rows, c, three_d() ? c : 1);
}

std::vector<int> Stack::bottom_row_ids() const {
  const auto& b = blocks_.back();
  std::vector<int> ids;
  for (int l = 1; l <= b.depth; ++l) {
    for (int j = 1; j <= b.columns; ++j) ids.push_back(id_of(b.index, b.rows, j, l));
  }
  return ids;
}

std::vector<Wall> Stack::walls() const {
  std::vector<Wall> w;
  if (spec_.bottom == Boundary::wall) w.push_back({"wall_bottom", 2, 0.0});
  if (spec_.sides == Boundary::wall) {
    w.push_back({"wall_left", 0, -half_width()});
    w.push_back({"wall_right", 0, half_width()});
    if (three_d()) {
      w.push_back({"wall_front", 1, -half_depth()});
      w.push_back({"wall_back", 1, half_depth()});
    }
  }
  return w;
}

bool Stack::has_walls() const {
  return spec_.bottom == Boundary::wall || spec_.sides == Boundary::wall;
}

std::vector<std::string> Stack::type_materials() const {
  std::vector<std::string> out;
  for (const auto& b : blocks_) out.push_back(b.material);
  out.push_back(spec_.effective_striker_material());
  if (has_walls()) out.push_back(spec_.effective_wall_material());
  return out;
}

double Stack::half_width() const { return spec_.top_columns * block(1).radius; }
double Stack::half_depth() const { return three_d() ? half_width() : block(1).radius; }
double Stack::top_z() const { return spheres_.front().z + spheres_.front().radius; }
double Stack::striker_radius() const { return spheres_.front().radius; }
double Stack::striker_mass() const { return striker_mass_; }
double Stack::incident_energy() const { return 0.5 * striker_mass() * spec_.striker_speed * spec_.striker_speed; }

}  // namespace granstack::model
