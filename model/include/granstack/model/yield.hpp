#pragma once
// Where the elastic model stops being the material (docs/physics.md section 7): the largest Hertz
// contact pressure of a run over the pair's first-yield pressure. Fed the same frames by refsim's
// in-situ run and by reduce of a LIGGGHTS or refsim case, so both engines give the same number.
#include <granstack/model/material.hpp>
#include <granstack/model/stack.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace granstack::model {

// First yield of a Hertz contact (Johnson, Contact Mechanics, 1985, section 6.2): the von Mises
// stress under the surface reaches the yield strength Y when the peak pressure p0 reaches 1.60 Y
// (nu = 0.3; 1.5 to 1.7 Y across nu = 0.2 to 0.5), in the body with the lower Y.
inline constexpr double kFirstYieldPressurePerYield = kDefaultYieldPressureFactor;

// Hertz's peak contact pressure at overlap d is p0 = 3F / (2 pi a^2), F = 4/3 Y* sqrt(R*) d^(3/2),
// a^2 = R* d, that is (2 Y* / pi) sqrt(d / R*); the meter takes its square over p_y^2.
// The pressure at which a contact of a and b starts to yield: kFirstYieldPressurePerYield times
// the lower yield strength of the two that have one; none when neither has one (brittle pairs).
std::optional<double> first_yield_pressure(const Material& a, const Material& b);
// ... at `factor` times that lower yield strength (the elastic-plastic laws' p_y).
std::optional<double> yield_pressure(const Material& a, const Material& b, double factor);

// LIGGGHTS's thornton_ning yields where the contact radius reaches a_y = r_i *
// coefficientYieldRatio[type_i], of the first sphere alone; a pair whose two spheres give different
// r * ratio gives an answer that depends on which LIGGGHTS calls i. The plan gives every sphere
// type the ratio that makes r * ratio one yield radius a_y, bitwise (the stack's touching types
// form one chain, striker to bottom, so one a_y serves every contact): a_y is the one of block 1's
// own pairs at factor times their yield strength (the impacted block, where the blow yields
// first), and each other kind of contact yields at its own effective pressure 2 E* a_y / (pi R*).
struct YieldRadiusPlan {
  double yield_radius = 0.0;           // m, a_y
  std::vector<double> ratio;           // per atom type (index type - 1); the wall's is unread
  std::string honoured;                // the contact kind whose intended p_y a_y gives
  struct Kind {
    std::string what;                  // "block 1 - block 2", "striker - block 1", "block 3 - wall"
    double effective = 0.0, intended = 0.0;  // Pa
  };
  std::vector<Kind> kinds;
  // Why no such ratios exist (a ratio above 1; a type of two radii, or of a radius no double ratio
  // fits, unless the spec's order_dependent_yield accepts it), or "".
  std::string refusal;
  std::string order_dependent;         // accepted by the spec: which type depends on LIGGGHTS's atom order, or ""
};
YieldRadiusPlan thornton_ning_plan(const Stack& stack);
// Under the stack's law, the least and largest of its kinds of contact's yield pressure over the one
// their materials give (the plan's effective over intended, for the kinds with one): thornton_ning's
// one yield radius sets every kind's but block 1's own; none under any other law, whose contacts
// each yield at their materials' pressure.
std::optional<std::pair<double, double>> yield_pressure_departure(const Stack& stack);

// The largest contact pressure over first yield seen: its ratio p0 / p_y, p0, the frame's step and
// the contact (sphere ids; id_b = 0 for a wall, named by `wall`).
struct YieldPeak {
  double ratio = 0.0;     // p0 / p_y; > 1: the contact yields, and the elastic result is a model there
  double pressure = 0.0;  // Pa, p0 there
  long step = 0;
  int id_a = 0, id_b = 0;
  std::string wall;
};

// The contact of a peak in words: "sphere 12 (block 1, row 2, steel) and sphere 1 (the striker,
// steel)", "sphere 40 (block 3, row 4, nylon) on wall_bottom (steel)".
std::string describe_contact(const Stack& stack, const YieldPeak& peak);

// What a YieldMeter judges: the material of each atom type (index type - 1), each sphere's type and
// radius (index id - 1), the walls and their material, and whether the normal contacts are Hertz's.
struct YieldContacts {
  std::vector<Material> type_materials;
  std::vector<int> sphere_type;  // 1-based atom types
  std::vector<double> radius;    // m
  std::vector<Wall> walls;
  std::optional<Material> wall_material;
  NormalModel normal = NormalModel::hertz;  // the meter judges a Hertzian law's pressure (NormalLaw::hertzian)
};
YieldContacts yield_contacts(const Stack& stack);

// One frame's largest so far, as YieldMeter::pair and walls offer it the frame's contacts: the
// squared ratio (one square root a frame, not one a contact) and its contact.
struct YieldFrame {
  double ratio2 = 0.0;
  double yield = 0.0;  // Pa, that contact's first-yield pressure
  int id_a = 0, id_b = 0;
  const Wall* wall = nullptr;
};

class YieldMeter {
 public:
  explicit YieldMeter(const Stack& stack) : YieldMeter(yield_contacts(stack)) {}
  explicit YieldMeter(const YieldContacts& contacts);
  // Whether the run's contacts can be judged: Hertz normal contacts (a linear spring has no Hertz
  // pressure); otherwise why not.
  bool judged() const { return why_not_.empty(); }
  const std::string& why_not_judged() const { return why_not_; }
  // The materials of the stack, its striker and walls with no yield strength (brittle): their
  // contacts with each other are not judged; with a material that has one they are, by its.
  const std::vector<std::string>& unjudged_materials() const { return unjudged_; }

  // One frame at `step`: every overlapping pair among `pairs` (indices id - 1, ContactCandidates's)
  // and every sphere pressing a wall, positions x, y, z by index. The largest ratio; on a tie the
  // first pair in (sphere, sphere) order, spheres before walls, so the answer does not depend on
  // the pairs' order. Over a protected plate, the bottom wall displaced by `plate_z`.
  YieldPeak at(long step, const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
               const std::vector<std::pair<std::size_t, std::size_t>>& pairs, double plate_z = 0.0) const;
  // at() in parts, for a caller that finds the overlaps itself (reduce, beside the elastic
  // energy): the contact of spheres i < j (indices) at overlap d > 0, each sphere against the
  // walls, and the frame's peak. Given the same contacts in the same order, the same answer.
  void pair(YieldFrame& f, std::size_t i, std::size_t j, double overlap) const;
  void walls(YieldFrame& f, const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
             double plate_z = 0.0) const;
  YieldPeak peak(long step, const YieldFrame& f) const;
  // The largest over the frames given (the earlier frame on a tie).
  void add(const YieldPeak& frame);
  const YieldPeak& largest() const { return largest_; }

 private:
  struct PairConstants {
    double y_star = 0.0;
    double yield = 0.0;   // Pa, the first-yield pressure; 0: not judged
    double scale2 = 0.0;  // (2 Y* / (pi p_y))^2: (p0 / p_y)^2 = scale2 d / R*
  };
  void offer(YieldFrame& f, double ratio2, const PairConstants& c, int a, int b, const Wall* wall) const;
  const PairConstants& pair(std::size_t i, std::size_t j) const;
  std::vector<int> type_;                 // per sphere index: its atom type - 1
  std::vector<double> radius_;            // per sphere index
  std::vector<double> inverse_radius_;    // 1 / radius: 1 / R* = 1 / R_i + 1 / R_j
  std::size_t ntypes_ = 0;
  std::vector<PairConstants> pairs_;      // [type_a * ntypes + type_b]
  std::vector<PairConstants> wall_;       // [type] against the walls' material
  std::vector<Wall> walls_;
  std::vector<std::string> unjudged_;
  std::string why_not_;
  YieldPeak largest_;
  bool seen_ = false;
};

}  // namespace granstack::model
