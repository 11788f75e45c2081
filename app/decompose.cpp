// granstack decompose: how LIGGGHTS would share a case's spheres among MPI ranks, for choosing
// --np before a big run (the loads of every processor grid, the one `run --np` takes first).
#include "commands.hpp"

#include <granstack/formats/case.hpp>
#include <granstack/runner/decomposition.hpp>

#include <fmt/format.h>

#include <memory>

namespace granstack::app {

namespace {

struct DecomposeFlags {
  std::string case_dir;
  std::vector<int> ranks{16};
  int grids = 5;
};

int decompose(const DecomposeFlags& f) {
  const auto c = formats::Case::open(f.case_dir);
  fmt::print("{}: {} spheres; each rank holds as ghosts the spheres within R_max cdf + skin + r = {:.4g} m + r of it\n",
             f.case_dir, c.stack().spheres().size(), runner::ghost_reach(c));
  fmt::print("{:>6}  {:>9}  {:>17}  {:>16}  {:>20}\n", "ranks", "grid", "busiest / mean", "ghosts / owned",
             "busiest rank holds");
  for (const int n : f.ranks) {
    const auto all = runner::candidate_decompositions(c, n);
    for (std::size_t k = 0; k < all.size() && k < static_cast<std::size_t>(f.grids); ++k) {
      const auto& d = all[k];
      fmt::print("{:>6}  {:>9}  {:>17.4f}  {:>16.3f}  {:>20.0f}{}\n", k == 0 ? std::to_string(n) : "",
                 fmt::format("{}x{}x{}", d.grid[0], d.grid[1], d.grid[2]), d.imbalance(), d.ghosts_per_owned(), d.load_max,
                 k == 0 ? "  <- run --np chooses" : "");
    }
  }
  fmt::print("(predicted from the stack with LIGGGHTS 3.8's uniform grid and ghost reach; a run's run.json records "
             "LIGGGHTS's own counts)\n");
  return kOk;
}

}  // namespace

Command add_decompose(CLI::App& app) {
  auto f = std::make_shared<DecomposeFlags>();
  auto* cmd = app.add_subcommand("decompose",
                                 "How LIGGGHTS would share a case among MPI ranks: each processor grid's busiest rank and "
                                 "ghosts, the grid run --np takes first");
  cmd->add_option("case", f->case_dir, "A case directory")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--np", f->ranks, "MPI rank counts, e.g. --np 16 64 [16]")->check(CLI::Range(1, 4096))->expected(1, -1);
  cmd->add_option("--grids", f->grids, "Grids shown per rank count, best first [5]")->check(CLI::Range(1, 1000));
  return {cmd, [f] { return decompose(*f); }};
}

}  // namespace granstack::app
