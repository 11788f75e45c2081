// The design report's figures: each objective against another, the front's and the study's
// designs rerun in situ (their wall force, their energy), and the hypervolume by generation.
#include "report_parts.hpp"

#include <granstack/design/convergence.hpp>
#include <granstack/generator/case_writer.hpp>
#include <granstack/postproc/plot.hpp>
#include <granstack/refsim/case_run.hpp>
#include <granstack/refsim/in_situ.hpp>
#include <granstack/os/interrupt.hpp>
#include <granstack/os/workers.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <map>
#include <set>
#include <string>

namespace granstack::design::report_parts {

namespace fs = std::filesystem;

namespace {

// A value for a log axis or a linear one: the objectives that span decades are drawn on a log axis.
bool log_axis(Objective o) { return o->log_axis; }

std::string axis_label(Objective o) { return fmt::format("{} ({})", to_string(o), unit_of(o)); }

// The front's plot elements: one per top-block material on the front (its own symbol), each
// point coloured by its number of blocks (column 3); column 4 holds the material's index.
std::string front_elements(const Space& space, const std::vector<Evaluation>& front) {
  static constexpr int kSymbols[] = {7, 5, 9, 11, 13, 15};
  std::string out;
  for (std::size_t k = 0; k < space.materials.size(); ++k) {
    const bool present = std::any_of(front.begin(), front.end(), [&](const auto& e) { return e.spec.block_material(1) == space.materials[k]; });
    if (!present) continue;
    out += fmt::format("     '' index 1 using 1:($4 == {} ? $2 : 1/0):3 with points pt {} ps 1.5 lc palette title 'front, top block {}', \\\n",
                       k, kSymbols[k % std::size(kSymbols)], space.materials[k]);
  }
  return out;
}

std::string pair_data(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front, Objective x, Objective y) {
  std::string data = "# every feasible design: x y N_B\n";
  for (const auto& e : s.all) {
    if (e.feasible) data += fmt::format("{:.10g} {:.10g} {}\n", *objective_value(e, x), *objective_value(e, y), e.spec.blocks);
  }
  data += "\n\n# the front: x y N_B top-block-material-index\n";
  for (const auto& e : front) {
    const auto k = std::find(space.materials.begin(), space.materials.end(), e.spec.block_material(1)) - space.materials.begin();
    data += fmt::format("{:.10g} {:.10g} {} {}\n", *objective_value(e, x), *objective_value(e, y), e.spec.blocks, k);
  }
  data += "\n\n# the study's designs: x y name\n";
  for (const auto& [name, e] : s.studies) {
    if (objective_value(e, x) && objective_value(e, y)) {
      data += fmt::format("{:.10g} {:.10g} \"{}\"\n", *objective_value(e, x), *objective_value(e, y), name);
    }
  }
  return data;
}

}  // namespace

// One pair of objectives: every feasible design (grey), the front coloured by N_B with a symbol
// per top-block material, the study's designs labelled.
postproc::Figure pair_figure(const Space& space, const Snapshot& s, const std::vector<Evaluation>& front, Objective x,
                             Objective y, const fs::path& dir) {
  const auto name = fmt::format("{}_vs_{}", to_string(y), to_string(x));
  postproc::PlotOptions o;
  o.format = "svg";
  const auto script = fmt::format(
      "{}\nset output '{}.svg'\nset xlabel '{}' noenhanced\nset ylabel '{}' noenhanced\n{}{}set key outside right top\n"
      "set cblabel 'N_B'\nset cbtics 1\n"
      "set palette defined (1 '#1b9e77', 2 '#d95f02', 3 '#7570b3', 4 '#e7298a', 5 '#66a61e', 6 '#e6ab02')\n"
      "plot '{}.dat' index 0 using 1:2 with points pt 7 ps 0.5 lc rgb '#c0c0c0' title 'evaluated', \\\n{}"
      "     '' index 2 using 1:2 with points pt 6 ps 2 lw 2 lc rgb 'black' title \"the study's designs\", \\\n"
      "     '' index 2 using 1:2:3 with labels offset -1,1 right font 'Sans,18' noenhanced notitle\n",
      postproc::gnuplot_terminal(o), name, axis_label(x), axis_label(y), log_axis(x) ? "set logscale x\nset format x '10^{%L}'\n" : "",
      log_axis(y) ? "set logscale y\nset format y '10^{%L}'\n" : "", name, front_elements(space, front));
  postproc::render_gnuplot(dir.string(), name, pair_data(space, s, front, x, y), script, o);
  return {name + ".svg", fmt::format("{} against {}: every feasible design evaluated (grey), the front (of all the objectives, "
                                     "seen in these two) coloured by the number of blocks with a symbol per top-block material, "
                                     "the study's designs (circles)",
                                     to_string(y), to_string(x))};
}

model::StackSpec worst_run(const Evaluation& e) {
  if (e.scenarios.empty()) return e.spec;
  const auto force = [](const ScenarioRun& r) {
    const auto it = r.measures.find("peak_wall_force");
    return it == r.measures.end() ? 0.0 : it->second;
  };
  return std::max_element(e.scenarios.begin(), e.scenarios.end(), [&](const auto& a, const auto& b) { return force(a) < force(b); })->spec;
}

std::vector<Rerun> rerun_shown(const Snapshot& s, const std::vector<Evaluation>& front, int jobs) {
  std::vector<Rerun> out;
  std::vector<model::StackSpec> specs;
  for (std::size_t i = 0; i < front.size(); ++i) {
    out.push_back({fmt::format("front {}: {}", i + 1, front[i].description), {}, 0.0, i < kFiguredFront});
    specs.push_back(worst_run(front[i]));
  }
  for (const auto& [name, e] : s.studies) {
    out.push_back({name, {}, 0.0, true});
    specs.push_back(worst_run(e));
  }
  // Each its own refsim run, `jobs` at a time; none starts once a signal came.
  os::for_each(out.size(), jobs, [&](std::size_t i) {
    if (os::interrupt_signal() != 0) return;
    const auto stack = model::Stack::build(specs[i]);
    out[i].r = refsim::run_in_situ(stack, refsim::particles_from(generator::data_file(stack, "report")));
    out[i].striker_speed = specs[i].striker_speed;
  });
  if (os::interrupt_signal() != 0) throw refsim::InSituStopped("stopped by a signal while the report ran the front's designs again");
  return out;
}

// The force on the protected object against time.
postproc::Figure force_figure(const std::vector<Rerun>& shown, const fs::path& dir) {
  std::string data, plots;
  double peak = 0.0;  // the y axis spans three decades below the largest force shown
  std::size_t index = 0;  // of the figure's data sets
  for (const auto& one : shown) {
    if (!one.figured) continue;
    const std::size_t k = index++;
    const auto& r = one.r;
    peak = std::max(peak, r.peak_wall_force.value_or(0.0));
    data += fmt::format("# {}: t (s) F (N)\n", one.name);
    for (std::size_t j = 0; j < r.wall_force.size(); ++j) {
      data += fmt::format("{:.9g} {:.9g}\n", static_cast<double>(j + 1) * r.wall_force_interval, r.wall_force[j]);
    }
    data += "\n\n";
    plots += fmt::format("{}'force.dat' index {} using ($1*1e3):2 with lines lw {} title '{}'", k == 0 ? "plot " : ", \\\n     ", k,
                         k < kFiguredFront ? 2 : 1, one.name);
  }
  postproc::PlotOptions o;
  o.format = "svg";
  const auto script = fmt::format("{}\nset output 'force.svg'\nset xlabel 't (ms)'\nset ylabel 'F on the wall (N)'\n"
                                  "set key below noenhanced\nset logscale y\nset yrange [1e-3 * {}:*]\nset format y '%g'\n{}\n",
                                  postproc::gnuplot_terminal(o), fmt::format("{:.6g}", peak), plots);
  postproc::render_gnuplot(dir.string(), "force", data, script, o);
  return {"force.svg", "The force on the protected object (the bottom wall) against time (log scale), each run to its blow's end (with "
                       "scenarios, the one with the largest peak): the front's first three designs (thick) and the study's "
                       "designs at the same footprint"};
}

// Where the energy is when each run ends, over E_in: the striker, each block, the part of the
// blocks' that moves sideways, where the contact law yields the work it dissipated (each block's
// and in all), and the rest (elastic energy in the contacts, less what damping and friction took);
// and the striker's and (free bottom) the output sphere's speed then, over the striker's speed at
// impact.
postproc::Table energy_table(const std::vector<Rerun>& shown, bool wall) {
  std::size_t blocks = 0;
  bool yields = false;
  for (const auto& x : shown) {
    blocks = std::max(blocks, x.r.end_block_ke.size());
    yields = yields || !x.r.end_block_dissipated.empty();
  }
  postproc::Table t{"Where the energy is when the blow has ended, over E_in; and how fast the striker comes back up "
                    "(and, with a free bottom, the output sphere leaves), over the striker's speed",
                    {"design", "ended at (s)", "striker"},
                    {}};
  for (std::size_t k = 0; k < blocks; ++k) t.header.push_back(fmt::format("block {}", k + 1));
  t.header.push_back("of the blocks', sideways");
  if (yields) {
    t.header.push_back("dissipated by yield, per block from the top");
    t.header.push_back("dissipated by yield, in all");
  }
  t.header.push_back(yields ? "the rest (contacts)" : "the rest (contacts, dissipated)");
  t.header.push_back("v_striker up / v_0");
  if (!wall) t.header.push_back("v_out / v_0");
  for (const auto& x : shown) {
    const auto& r = x.r;
    std::vector<std::string> row{x.name, r.blow_end_time ? fmt::format("{:.4g}", *r.blow_end_time) : "not ended",
                                 fmt::format("{:.3g}", r.end_striker_ke / r.e_in)};
    double sum = r.end_striker_ke;
    for (std::size_t k = 0; k < blocks; ++k) {
      row.push_back(k < r.end_block_ke.size() ? fmt::format("{:.3g}", r.end_block_ke[k] / r.e_in) : "");
      if (k < r.end_block_ke.size()) sum += r.end_block_ke[k];
    }
    row.push_back(fmt::format("{:.3g}", r.end_sideways_ke / r.e_in));
    if (yields) {
      std::vector<std::string> per_block;
      for (const double w : r.end_block_dissipated) per_block.push_back(fmt::format("{:.3g}", w / r.e_in));
      row.push_back(per_block.empty() ? "-" : fmt::format("{}", fmt::join(per_block, ", ")));
      row.push_back(per_block.empty() ? "-" : fmt::format("{:.3g}", r.end_dissipated / r.e_in));
      sum += r.end_dissipated;
    }
    row.push_back(fmt::format("{:.3g}", 1.0 - sum / r.e_in));
    row.push_back(fmt::format("{:.3g}", r.end_striker_vz / x.striker_speed));
    if (!wall) row.push_back(fmt::format("{:.3g}", r.end_output_speed / x.striker_speed));
    t.rows.push_back(std::move(row));
  }
  return t;
}

postproc::Figure hypervolume_figure(const Snapshot& s, const fs::path& dir) {
  std::string data = "# generation hypervolume (a block per seed's run)\n";
  std::string plots;
  for (const auto& r : s.runs) {
    data += fmt::format("# seed {}\n", r.seed);
    for (const auto& g : s.generations) {
      if (g.run == r.run) data += fmt::format("{} {:.10g}\n", g.index, g.hypervolume);
    }
    data += "\n\n";
    plots += fmt::format("{}'hypervolume.dat' index {} using 1:2 with linespoints pt 7 title 'seed {}'", plots.empty() ? "" : ", ", r.run, r.seed);
  }
  postproc::PlotOptions o;
  o.format = "svg";
  const auto script = fmt::format("{}\nset output 'hypervolume.svg'\nset xlabel 'generation'\nset ylabel 'hypervolume'\n"
                                  "set key bottom right\nplot {}\n",
                                  postproc::gnuplot_terminal(o), plots);
  postproc::render_gnuplot(dir.string(), "hypervolume", data, script, o);
  return {"hypervolume.svg", "The hypervolume of each generation's front: it grows while the search still finds better designs"};
}

// Figures: each seed's hypervolume and IGD+ (against the front of all runs) after each
// generation's worth of distinct designs.
std::vector<postproc::Figure> convergence_figures(const std::vector<Progress>& progress, const fs::path& dir) {
  std::string data = "# distinct designs, hypervolume, IGD+ (a block per seed's run)\n";
  for (const auto& p : progress) {
    data += fmt::format("# seed {}\n", p.seed);
    for (const auto& x : p.points) data += fmt::format("{} {:.10g} {:.10g}\n", x.designs, x.hypervolume, x.igd_plus);
    data += "\n\n";
  }
  postproc::PlotOptions o;
  o.format = "svg";
  // One image per render: hypervolume.dat and igd_plus.dat hold the same table.
  for (const auto& [name, column, ylabel, key] : {std::tuple{"hypervolume", 2, "hypervolume (normalised box)", "bottom right"},
                                                  std::tuple{"igd_plus", 3, "IGD+ to the front of all runs", "top right"}}) {
    std::string plots;
    for (std::size_t r = 0; r < progress.size(); ++r) {
      plots += fmt::format("{}'{}.dat' index {} using 1:{} with linespoints pt 7 title 'seed {}'", plots.empty() ? "" : ", ", name, r,
                           column, progress[r].seed);
    }
    postproc::render_gnuplot(dir.string(), name, data,
                             fmt::format("{}\nset output '{}.svg'\nset xlabel 'distinct designs'\nset ylabel '{}'\nset key {}\nplot {}\n",
                                         postproc::gnuplot_terminal(o), name, ylabel, key, plots),
                             o);
  }
  return {{"hypervolume.svg", "Each seed's hypervolume against the distinct designs it has run: it grows while the search still "
                              "finds better designs"},
          {"igd_plus.svg", "Each seed's IGD+ to the front of all runs (0: it has found every point of that front)"}};
}

}  // namespace granstack::design::report_parts
