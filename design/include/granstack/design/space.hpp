#pragma once
// A design space for `granstack design` (docs/design.md): what varies from stack to stack (the
// number of blocks, each block's material and rows, each interface's radius ratio), what stays
// fixed (the footprint, the striker, the boundaries, the contacts: any spec field), the
// constraints and the objectives, read from a TOML file.
#include <granstack/design/objectives.hpp>
#include <granstack/model/protection.hpp>
#include <granstack/model/spec.hpp>
#include <granstack/model/stack.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace granstack::design {

// A design space's top sphere radius when [fixed] gives no top_radius, m (the study's top block's).
inline constexpr double kDefaultTopRadius = 8e-3;

// A space that cannot be searched: every problem found, each naming its key and the fix.
class SpaceError : public std::runtime_error {
 public:
  explicit SpaceError(std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};


struct Constraints {
  std::optional<long> max_spheres;
  std::optional<double> max_height;      // m
  std::optional<double> max_areal_mass;  // kg/m^2
  // Bounds on run measures (objective_table's, by name: max_crush = ... bounds crush), checked on
  // a design's measures after it ran (over its scenarios, as each measure aggregates).
  std::map<std::string, double> max_measures;
};

// The blows a design must survive: each a change to the fixed spec; a space without [scenarios]
// has one, the fixed spec itself.
struct Scenario {
  std::string label;               // "2 m/s, striker 1 R_1", and ", 1 diameter off centre" for an offset
  double striker_speed = 1.0;      // m/s
  double striker_radius_ratio = 1.0;
  int impact_offset = 0;           // top-sphere diameters along +x (model::StackSpec::impact_offset)
  // An elastic-plastic law's p_y / Y (model::StackSpec::yield_pressure_factor: 1.6 first yield to
  // about 3 fully plastic), where the scenarios vary it; none: the fixed spec's.
  std::optional<double> yield_pressure_factor;
  model::StackSpec applied_to(model::StackSpec spec) const;
};
// [confirm] (or confirm's --geometry and --sides): a physical variant of each confirmed design that
// confirm also runs on LIGGGHTS, to its blow's end: the strip as a 3D nest of the same blocks,
// or between rigid side walls. Its measures stand beside the strip's: how far the strip's answer
// carries to the body it stands for. Not part of the space's digest (the search is the same).
struct ConfirmVariant {
  std::optional<model::Geometry> geometry;  // nested3d (from the strip)
  std::optional<model::Boundary> sides;
  bool empty() const { return !geometry && !sides; }
  std::string label() const;   // "3D nest", "side walls", "3D nest, side walls"
  std::string suffix() const;  // of its case's name: "_3d", "_walls", "_3d_walls"
  model::StackSpec applied_to(model::StackSpec spec) const;
  // Why the variant cannot be run on `fixed` (a space's fixed spec), or "".
  std::string problem(const model::StackSpec& fixed) const;
};

// How an objective is taken over the scenarios: the worst (the largest: every objective is
// minimised) or the mean.
enum class Aggregate { worst, mean };
std::string_view to_string(Aggregate a);

// How the designs of a search are run. asynchronous: a steady-state search that starts a new
// design whenever one finishes (every core busy; with more than one job the order in which designs
// finish shapes the search, so two runs on several cores may differ, and the store keeps that
// order); generational: pagmo2's NSGA-II, a generation's designs as one batch (any number of jobs
// gives the same search, bit for bit; SLURM batches run this way).
enum class Schedule { asynchronous, generational };
std::string_view to_string(Schedule s);

// Which design leaves the asynchronous search's population when one joins, and how parents are
// picked: nsga2 (Deb et al. 2002: rank, then crowding; binary tournaments), nsga3 (Deb and Jain
// 2014: rank, then the most crowded of Das and Dennis's reference directions in the normalised
// box, the farthest from it; parents at random), sms_emoa (Beume et al. 2007: rank, then the least
// exclusive hypervolume in the box; parents at random), moead (Zhang and Li 2007: a weight per
// member, pagmo2's low-discrepancy ones; parents from the weight's 20 nearest, with probability
// 0.9; a new design replaces up to two of them it beats in Tchebycheff distance from the box's
// ideal). The generational schedule is NSGA-II.
enum class Algorithm { nsga2, nsga3, sms_emoa, moead };
std::string_view to_string(Algorithm a);

struct Search {
  int population = 24;  // a multiple of 4, at least 8, at most kMaxPopulation
  int generations = 10;  // at most kMaxGenerations; asynchronous: population designs make one
  std::uint64_t seed = 1;                    // the first run's
  std::vector<std::uint64_t> seeds{1};       // [search] seed = N or [N, M, ...]: a run per seed, one store
  Schedule schedule = Schedule::asynchronous;  // [search] evaluation
  Algorithm algorithm = Algorithm::nsga2;       // [search] algorithm
  // The operators (pagmo2's simulated binary crossover and polynomial mutation, both schedules):
  double crossover_probability = 0.95;          // in [0, 1)
  double crossover_eta = 10.0;                  // distribution index, in [1, 100)
  double mutation_eta = 50.0;                   // in [1, 100)
  std::optional<double> mutation_probability;   // per gene, in [0, 1]; none: one over the genes
  // Breeding in the asynchronous search: the chance that a parent is drawn from the search's
  // front (every design it ran that none dominates) instead of by the algorithm's rule in the
  // population, and that a mutated ordinal gene (the blocks, a ratio's index, a block's rows)
  // moves one step instead of to any other of its values. The budget benchmark found neither
  // better than none (the defaults: pagmo2's parents and mutation, as before they existed). A
  // store keeps those its search began with (adopt_schedule).
  double front_parents = 0.0;                   // [search] front_parents, in [0, 1]
  double step_mutation = 0.0;                   // [search] step_mutation, in [0, 1]
  bool breeding_given = false;                  // the file named either
  // The asynchronous search's screening: each design run is the best of this many drawn (half bred,
  // half uniform), by an estimate from the designs run (design/src/screening.hpp); 1: the first bred runs.
  int screening = 1;                            // [search] screening, 1 to kMaxScreening
  // [search] start: spec files (generate --config's, relative to the space file) whose designs
  // begin the search (their blocks, materials, ratios and rows; the rest is the space's), and
  // their genes (read when a search is parsed to run, not from a stored space).
  std::vector<std::string> start_files;
  std::vector<std::vector<double>> start;
  bool schedule_given = false;                 // the file named it (a resumed store keeps its own otherwise)
  // When the search also ends (none of them part of the space's digest, as generations):
  std::optional<long> max_designs;  // distinct designs run by the search, in all
  int stagnation = 0;               // generations over which the hypervolume gains no more than
  double stagnation_tolerance = 1e-3;  // this fraction of itself (0: never)
  double time_limit = 0.0;          // s of wall time after which no design starts (0: none; --time-limit overrides)
  // Settle a design as soon as the scenarios it has run decide it (evaluate_design): the front
  // is the same, the designs off it cost less. Not part of the digest.
  bool shortcuts = true;
};
// Bounds that keep a typo from a search that cannot fit in memory or never ends (a population of
// 1e8 ran out of memory before its first design).
inline constexpr int kMaxPopulation = 100'000;
inline constexpr int kMaxScreening = 64;  // [search] screening: designs drawn per design run, at most
inline constexpr int kMaxGenerations = 100'000;  // as the --generations flag
inline constexpr std::size_t kMaxSeeds = 64;
// The fewest designs a search's budget (max_designs) can hold, and why: its first two are the
// probes that fix the objectives' box.
inline constexpr long kLeastMaxDesigns = 2;
inline constexpr const char* kLeastMaxDesignsWhy =
    "a search's first two designs are the space's lightest and heaviest, the probes that fix its objectives' box";

struct Space {
  model::StackSpec fixed;        // everything a design does not vary
  double top_radius = 0.0;       // m, R_1: with fixed.top_columns, the footprint every design keeps
  int min_blocks = 1, max_blocks = 1;
  std::vector<std::string> materials;  // candidates for each block
  std::vector<int> radius_ratios;      // candidates for each interface
  int min_rows = 1, max_rows = 1;
  Constraints constraints;
  std::vector<Objective> objectives;  // all minimised
  std::vector<Scenario> scenarios;    // [scenarios]: the product of its lists; empty: none
  std::map<std::string, Aggregate> aggregate;  // per run measure; worst when not named
  Aggregate aggregate_of(std::string_view measure) const;
  double impulse_window = 0.0;        // s: [measures] impulse_window, wall_impulse's tau
  double cap_durations = model::kBlowEndCapDurations;  // [measures] cap_durations: a run's cap
  // What the protected object feels ([measures]): the channel frequency class of the force's
  // filter (SAE J211-1; 0: none given), the protected mass (kg) mounted on the wall, and the shock
  // response spectrum's band (Hz) and damping ratio.
  int cfc = 0;
  double protected_mass = 0.0;
  double srs_low = 0.0, srs_high = 0.0;
  double srs_damping = 0.05;
  ConfirmVariant confirm_variant;     // [confirm]
  Search search;
  std::vector<std::string> warnings;  // a stored space's problems a new search would be refused for

  // The decision vector: N_B, a material index per block, a ratio index per interface and a
  // row count per block, for max_blocks (genes past a design's N_B are carried but unused).
  // A gene with one choice spans two values that decode alike (NSGA-II needs lower < upper).
  std::size_t genes() const { return 3 * static_cast<std::size_t>(max_blocks); }
  // Whether gene i is a block's material (a choice with no order; the others are ordinal).
  bool is_material_gene(std::size_t i) const { return i >= 1 && i <= static_cast<std::size_t>(max_blocks); }
  std::pair<std::vector<double>, std::vector<double>> bounds() const;
  // The stack a decision vector stands for (whole numbers; rounded).
  model::StackSpec decode(const std::vector<double>& x) const;
  // The one decision vector of a stack of the space (nullopt: not one of its designs): whole
  // genes, and the genes past its N_B repeat its last block's (its last interface's; with one
  // block, the first ratio), so that one design has one vector.
  std::optional<std::vector<double>> encode(const model::StackSpec& spec) const;
  std::vector<double> canonical_genes(const std::vector<double>& x) const { return *encode(decode(x)); }
  // The space's lightest and heaviest designs (fewest blocks and rows of its lightest material at
  // its largest ratio; most of its densest at its smallest): every design's areal mass and height
  // lie between theirs.
  std::pair<model::StackSpec, model::StackSpec> extreme_designs() const;
  // The canonical digest of what makes two searches the same (all but the generation count):
  // a store written for another space is refused.
  std::string digest() const;
};

// A design space from the text of its file (`source` names it in messages). Throws SpaceError
// listing every problem, std::runtime_error for bad TOML (with line and column).
// `stored`: the space of an existing store (status, report, confirm): what a new search may no
// longer do (a measure that can be gamed, a fixed duration) is said in Space::warnings instead,
// so that a search run before it was refused can still be read.
// [fixed] without `sides` stands between side walls; `free_sides_by_default` reads a space stored
// before that default (stored_space does, where the store's digest says so).
Space parse_space(std::string_view toml_text, const std::string& source, bool stored = false,
                  bool free_sides_by_default = false);

// A design's measures known before it runs, and which constraints it breaks (empty: feasible).
struct Geometry {
  long spheres = 0;
  double height = 0.0;      // m
  double areal_mass = 0.0;  // kg/m^2
  std::vector<std::string> violations;
  double violation = 0.0;   // the sum of each broken constraint's excess over its bound, relative
};
Geometry measure(const Space& space, const model::StackSpec& spec);

// One spelling per design: per-interface ratios that are all equal become the one radius_ratio,
// per-block rows that are all equal the one rows (as a spec file reads a one-entry list), so
// the same stack always has the same digest.
model::StackSpec canonical(model::StackSpec spec);
// The canonical digest of a spec (SHA-256 of its manifest JSON): the store's key.
std::string spec_digest(const model::StackSpec& spec);
// "steel/teflon/steel, ratios 2/3, rows 8/8/4": a design in one line.
std::string describe(const model::StackSpec& spec);

}  // namespace granstack::design
