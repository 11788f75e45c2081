#include <granstack/formats/case.hpp>
#include <granstack/formats/files.hpp>
#include <granstack/formats/manifest.hpp>
#include <granstack/formats/series.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/os/process.hpp>
#include <granstack/postproc/plot.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace granstack::postproc {

namespace fs = std::filesystem;

namespace {

}  // namespace

std::string gnuplot_terminal(const PlotOptions& o) {
  // Greek letters as UTF-8, never {/Symbol m}: an SVG viewer without the Symbol font draws an 'm'.
  if (o.format == "svg") return "set encoding utf8\nset terminal svg size 1600,1000 dynamic enhanced font 'Sans,26' linewidth 2";
  if (o.format == "png") return "set encoding utf8\nset terminal pngcairo size 1600,1000 enhanced font 'Sans,26' linewidth 3";
  throw std::invalid_argument(fmt::format("plot format '{}' is not png or svg", o.format));
}

std::string render_gnuplot(const std::string& dir_name, const std::string& name, const std::string& data,
                           const std::string& script, const PlotOptions& o) {
  const fs::path dir(dir_name);
  fs::create_directories(dir);
  formats::write_file_atomically(dir / (name + ".dat"), data);
  formats::write_file_atomically(dir / (name + ".gp"), script);
  const auto image = dir / (name + "." + o.format);
  const auto log = dir / (name + ".gnuplot.log");
  os::StartOptions start;
  start.cwd = dir;
  start.output = log;
  std::string start_error;
  // Bounded: a figure takes gnuplot seconds; one that hangs (a broken terminal driver) cannot hold granstack.
  constexpr double kGnuplotSeconds = 600.0;
  const auto end = os::run({o.gnuplot, name + ".gp"}, start, &start_error, kGnuplotSeconds);
  std::error_code ec;
  if (!start_error.empty()) {
    throw std::runtime_error(fmt::format("{}; gnuplot comes with scripts/setup.sh (Debian package gnuplot-nox)", start_error));
  }
  if (!end.ok() || !fs::exists(image) || fs::file_size(image, ec) == 0) {
    std::string what;
    try {
      what = formats::read_file(log);
    } catch (const std::exception&) {
    }
    throw std::runtime_error(fmt::format("gnuplot failed on {} ({}). Its output: {}", (dir / (name + ".gp")).string(),
                                         end.timed_out ? fmt::format("it did not end within {:g} s, and was killed", kGnuplotSeconds)
                                         : end.stopped  ? std::string("stopped: granstack was asked to stop")
                                         : end.signal != 0 ? fmt::format("signal {}", end.signal)
                                                           : fmt::format("exit code {}", end.code),
                                         what.substr(0, 400)));
  }
  fs::remove(log, ec);
  return image.string();
}

namespace {

std::string safe_name(std::string s) {
  for (auto& c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
  }
  return s;
}

}  // namespace

std::string energy_plot_name(const std::string& label) { return "energy_" + safe_name(label); }

std::vector<std::string> plot_files(const std::string& name, const PlotOptions& o) {
  return {name + ".dat", name + ".gp", name + "." + o.format};
}

std::string plot_block_energy(const std::string& case_dir, const std::string& label, const std::string& out_dir,
                              const PlotOptions& o) {
  const auto c = formats::Case::open(case_dir);
  const double dt = c.derived().dt;
  const auto series = formats::read_series(formats::find_dump(c.dir(), c.files().series));
  const int nb = c.spec().blocks;
  std::vector<int> trans, rot;
  for (int k = 1; k <= nb; ++k) {
    trans.push_back(series.column(fmt::format("ke_trans_block{}", k)));
    rot.push_back(series.column(fmt::format("ke_rot_block{}", k)));
    if (trans.back() < 0 || rot.back() < 0) {
      throw std::runtime_error(fmt::format("{}: the series has no columns for block {}", case_dir, k));
    }
  }
  if (series.rows.empty()) throw std::runtime_error(fmt::format("{}: the in-situ series is empty: run the case first", case_dir));
  double peak1 = 0.0;
  for (const auto& row : series.rows) {
    peak1 = std::max(peak1, row[static_cast<std::size_t>(trans[0])] + row[static_cast<std::size_t>(rot[0])]);
  }
  // At most about 4000 points per curve: enough for the eye, light for the plotter.
  const std::size_t stride = std::max<std::size_t>(1, series.rows.size() / 4000);
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  fmt::format_to(out, "# case {}: time (µs), then each block's KE / peak KE of block 1 ({:.6g} J)\n", safe_name(label), peak1);
  for (std::size_t r = 0; r < series.rows.size(); r += stride) {
    const auto& row = series.rows[r];
    fmt::format_to(out, "{:.6g}", row[0] * dt * 1e6);
    for (int k = 0; k < nb; ++k) {
      fmt::format_to(out, " {:.6g}",
                     (row[static_cast<std::size_t>(trans[static_cast<std::size_t>(k)])] +
                      row[static_cast<std::size_t>(rot[static_cast<std::size_t>(k)])]) / peak1);
    }
    fmt::format_to(out, "\n");
  }
  const auto name = energy_plot_name(label);
  const auto script = fmt::format(
      "# granstack: kinetic energy of each block of case {} (translational + rotational), normalised by the\n"
      "# peak of block 1 (docs/physics.md section 4). Data: {}.dat (time in µs, then block 1 = top, ...).\n"
      "# Restyle at will, then run: gnuplot {}.gp\n"
      "{}\nset output '{}.{}'\n"
      "set title \"Kinetic energy per block\\n{} block{}, e = {}, μ = {}, v = {} m/s\"\n"
      "set xlabel 'time t (µs)'\nset ylabel 'E_k / max E_k of block 1'\n"
      "# The key beside the plot covers no curve; 8 % head room keeps a curve that reaches 1 off the border.\n"
      "set grid\nset key outside right top\nset yrange [0:*]\nset offsets 0, 0, graph 0.08, 0\nset autoscale xfix\n"
      "plot for [k=1:{}] '{}.dat' using 1:(column(k+1)) with lines title sprintf('block %d', k)\n",
      safe_name(label), name, name, gnuplot_terminal(o), name, o.format, nb, nb == 1 ? "" : "s", c.spec().restitution.value,
      c.spec().friction.value, c.spec().striker_speed, nb, name);
  return render_gnuplot(out_dir, name, fmt::to_string(data), script, o);
}

std::string panel_plot_name(const std::string& label) { return "panels_" + safe_name(label); }

std::string plot_panel_energy(const CaseReduction& r, const std::string& label, const std::string& out_dir,
                              const PlotOptions& o) {
  if (r.panel_frames.empty()) throw std::runtime_error(fmt::format("{}: not a container (geometry = panels)", r.case_dir));
  const int panels = r.spec.panels;
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  fmt::format_to(out, "# case {}: time (µs), then panel 1 .. {} and the matrix: KE / E_in ({:.6g} J)\n", safe_name(label),
                 panels, r.e_in);
  for (const auto& frame : r.panel_frames) {
    fmt::format_to(out, "{:.6g}", frame[0] * 1e6);
    for (std::size_t i = 1; i < frame.size(); ++i) fmt::format_to(out, " {:.6g}", frame[i] / r.e_in);
    fmt::format_to(out, "\n");
  }
  const auto name = panel_plot_name(label);
  const std::string hit = r.spec.strikes_every_panel() ? "every panel" : fmt::format("panel {}", r.spec.measured_panel());
  std::string curves;
  const auto every = std::max<std::size_t>(1, r.panel_frames.size() / 12);
  for (int p = 1; p <= panels; ++p) {
    curves += fmt::format("'{}.dat' using 1:{} with linespoints pointtype {} pointinterval {} dashtype {} title 'panel {}', \\\n     ",
                          name, p + 1, p + 3, every, p > r.spec.measured_panel() ? 3 : 1, p);
  }
  const auto script = fmt::format(
      "# granstack: kinetic energy of each panel of the container {} and of its matrix, over E_in.\n"
      "# Data: {}.dat (time in µs, then panel 1 (smallest y) .. {}, then the matrix). The striker hits {}.\n"
      "# Restyle at will, then run: gnuplot {}.gp\n"
      "{}\nset output '{}.{}'\n"
      "set title \"Kinetic energy per panel\\n{} panels, {} block{}, separator {}, striker on {}\"\n"
      "set xlabel 'time t (µs)'\nset ylabel 'E_k / E_{{in}}'\n"
      "set grid\nset key outside right top\nset logscale y\nset format y '10^{{%L}}'\nset yrange [1e-6:2]\n"
      "set autoscale xfix\n"
      "# Panels beyond the struck one are dashed, each with its own marker: mirrored panels of a\n"
      "# symmetric container have the same curve, and neither hides the other.\n"
      "plot {}'{}.dat' using 1:{} with lines dashtype 2 linecolor 'black' title 'matrix'\n",
      safe_name(label), name, panels, hit, name, gnuplot_terminal(o), name, o.format, panels, r.spec.blocks,
      r.spec.blocks == 1 ? "" : "s", model::to_string(r.spec.separator), hit, curves, name, panels + 2);
  return render_gnuplot(out_dir, name, fmt::to_string(data), script, o);
}

std::string plot_decay(const OutputTable& t, const std::string& out_dir, const PlotOptions& o) {
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  std::string plots, functions;
  int index = 0;
  for (const auto& g : t.groups) {
    fmt::format_to(out, "# group {}: N_B, output fraction\n", g.label);
    for (const auto* c : g.cases) fmt::format_to(out, "{} {:.10g}\n", c->spec.blocks, c->output_fraction);
    fmt::format_to(out, "\n\n");
    const int lt = index + 1;
    plots += fmt::format("{}'decay.dat' index {} using 1:2 with points pointtype 7 pointsize 2 linecolor {} title '{}' noenhanced",
                         plots.empty() ? "" : ", \\\n     ", index, lt, g.label);
    if (g.fit) {
      functions += fmt::format("f{}(x) = {:.10g} * exp(-{:.10g} * x)  # fit of {}\n", index, g.fit->prefactor, g.fit->alpha,
                               g.label);
      plots += fmt::format(", \\\n     f{}(x) with lines linecolor {} dashtype 2 title sprintf('fit: α = %.3f', {:.6g})",
                           index, lt, g.fit->alpha);
    }
    ++index;
  }
  const int lo = t.blocks.empty() ? 1 : t.blocks.front();
  const int hi = t.blocks.empty() ? 1 : t.blocks.back();
  const auto script = fmt::format(
      "# granstack: output fraction E_out/E_in against the number of blocks, with the fits\n"
      "# E_out/E_in = A exp(-alpha N_B) (least squares on the logarithm). Data: decay.dat (one index per group).\n"
      "# Restyle at will, then run: gnuplot decay.gp\n"
      "{}\nset output 'decay.{}'\n"
      "set title 'Output fraction against depth'\n"
      "set xlabel 'number of blocks N_B'\nset ylabel 'E_{{out}} / E_{{in}}'\n"
      "# The key below the plot, one entry a line: long group names stay whole and cover nothing.\n"
      "set logscale y\nset format y '10^{{%L}}'\nset grid\nset key below left maxcols 1\n"
      "set xrange [{}:{}]\nset xtics 1\nset samples 200\n{}plot {}\n",
      gnuplot_terminal(o), o.format, lo - 0.3, hi + 0.3, functions, plots);
  return render_gnuplot(out_dir, "decay", fmt::to_string(data), script, o);
}

}  // namespace granstack::postproc
