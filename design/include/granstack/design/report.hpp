#pragma once
// What a design search found, for people: `design status`'s summary, the report (md, html and
// json, the front's designs as ready-to-run spec files, figures), the study's designs placed on
// the same axes, and the front's best confirmed on LIGGGHTS.
#include <granstack/design/search.hpp>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace granstack::design {

// A confirmation's spread between LIGGGHTS's law and the search's, per objective:
// "peak_wall_force -47.9 %, crush +69.3 %" (empty where LIGGGHTS ran the search's law).
std::string spread_text(const Confirmation& c);

// Generations run, hypervolume, designs evaluated and the front's first designs.
std::string status_text(const Space& space, const Store& store);

// DIR/design.md, design.html, design.json, front/*.toml and the figures (gnuplot SVG); returns
// the html's path. The front's designs run again for the figures and the energy table, `jobs` at
// a time; a signal meanwhile throws refsim::InSituStopped before the md, html and json are written.
std::filesystem::path write_report(const Space& space, const Store& store, const std::filesystem::path& dir, int jobs = 1);

// The front's `top` best designs (first objective first) generated as cases under `dir`, run on
// LIGGGHTS (`liggghts_exe`: its executable, "" for the one on PATH) and on refsim (validate's
// copies), reduced and compared; stored and returned. A run that fails throws ConfirmRunFailed.
// A design agrees when its objectives and its whole runs (the same stopping frame, every frame
// within validate's tolerance) do; otherwise its verdict says what differs. `on_plan` is told,
// before anything runs, how many runs confirm makes and the most they can write. `jobs` runs go at
// once (each LIGGGHTS on one rank, each refsim on one thread).
std::vector<Confirmation> confirm_front(const Space& space, Store& store, const std::filesystem::path& dir, int top,
                                        const std::function<void(const std::string&)>& on_progress = {},
                                        const std::string& liggghts_exe = "",
                                        const std::function<void(const std::string&)>& on_plan = {}, int jobs = 1);

class ConfirmRunFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The report's file of the front's `rank`th design (1: best first objective) after `generation`:
// front/gGGG_NN_DIGEST8.toml, the run the store measured (to its blow's end); with scenarios, one
// file per scenario that decided an objective, front/gGGG_NN_DIGEST8_sK.toml (K: the scenario's
// place in the space, from 1).
std::string front_file_name(int generation, std::size_t rank, const std::string& digest, int scenario = 0);

}  // namespace granstack::design
