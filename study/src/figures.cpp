#include "figures.hpp"

#include <granstack/formats/manifest.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/plot.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace granstack::study {

namespace {

Figure render(const std::string& dir, const std::string& name, const std::string& data, const std::string& body,
              const std::string& gnuplot, const std::string& caption) {
  postproc::PlotOptions o;
  o.format = "svg";
  o.gnuplot = gnuplot;
  const auto script = fmt::format("# granstack reproduce: {}\n# Data: {}.dat. Restyle at will, then run: gnuplot {}.gp\n{}\n"
                                  "set output '{}.svg'\n{}",
                                  caption, name, name, postproc::gnuplot_terminal(o), name, body);
  postproc::render_gnuplot(dir, name, data, script, o);
  return {"figures/" + name + ".svg", caption};
}

}  // namespace

Figure energy_figure(const postproc::CaseReduction& r, const std::string& dir, const std::string& name,
                     const std::string& gnuplot, const std::string& caption, bool impact_column) {
  const int nb = r.spec.blocks;
  const auto curves = impact_column ? impact_column_energies(r) : block_energies(r);
  const double top = curves.front().max();
  const std::size_t stride = std::max<std::size_t>(1, curves.front().t.size() / 3000);
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  fmt::format_to(out, "# time (us), then E_k of each block's {} (top block first) / its peak in block 1 ({:.6g} J)\n",
                 impact_column ? "impact column" : "spheres", top);
  double lower = 0.0;
  for (std::size_t i = 0; i < curves.front().t.size(); i += stride) {
    fmt::format_to(out, "{:.6g}", curves.front().t[i] * 1e6);
    for (int k = 0; k < nb; ++k) {
      const double v = curves[static_cast<std::size_t>(k)].y[i] / top;
      if (k > 0) lower = std::max(lower, v);
      fmt::format_to(out, " {:.6g}", v);
    }
    fmt::format_to(out, "\n");
  }
  std::string materials;
  for (int k = 1; k <= nb; ++k) materials += fmt::format("{}{}", k > 1 ? "/" : "", r.spec.block_material(k));
  // Fixed margins, so the inset sits in the empty band above the curves (the y axis reaches 1.75,
  // the curves 1): it covers no curve, and the key sits at the top left, beside it.
  const auto body = fmt::format(
      "set title '{} block{} ({}), e = {}, {}{}' noenhanced\n"
      "set xlabel 'time t (µs)'\nset ylabel '{}'\n"
      "set lmargin at screen 0.09\nset rmargin at screen 0.97\nset bmargin at screen 0.11\nset tmargin at screen 0.92\n"
      "set grid\nset key at graph 0.02, graph 0.97 left top box opaque\nset yrange [0:1.75]\nset ytics 0, 0.2, 1.0\n"
      "set autoscale xfix\nset multiplot\n"
      "plot for [k=1:{}] '{}.dat' using 1:(column(k+1)) with lines linewidth 2 linecolor k title sprintf('block %d', k)\n"
      "# The inset: the lower blocks, magnified.\n"
      "set lmargin at screen 0.47\nset rmargin at screen 0.95\nset bmargin at screen 0.645\nset tmargin at screen 0.895\n"
      "unset title\nunset xlabel\nunset ylabel\nunset key\nset ytics autofreq\n"
      "set object 1 rectangle from graph 0, graph 0 to graph 1, graph 1 behind fillcolor rgb 'white' fillstyle solid noborder\n"
      "set yrange [0:{:.3g}]\n"
      "plot for [k=2:{}] '{}.dat' using 1:(column(k+1)) with lines linewidth 2 linecolor k notitle\n"
      "unset multiplot\n",
      nb, nb == 1 ? "" : "s", materials, r.spec.restitution.value,
      r.spec.bottom == model::Boundary::wall ? "bottom wall" : "free bottom", impact_column ? ", impact column" : "",
      impact_column ? "E_k of the impact column / its peak in block 1" : "E_k / max E_k of block 1", nb, name,
      lower > 0.0 ? 1.15 * lower : 1.0, nb, name);
  return render(dir, name, fmt::to_string(data), body, gnuplot, caption);
}

Figure decay_figure(const std::map<double, std::vector<std::pair<int, double>>, std::greater<>>& by_e, double alpha,
                    const std::string& dir, const std::string& gnuplot) {
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  std::string plots;
  int index = 0, hi = 1;
  for (auto it = by_e.begin(); it != by_e.end(); ++it, ++index) {
    const double e = it->first;
    fmt::format_to(out, "# e = {}: N_B, E_out/E_in\n", e);
    for (const auto& [nb, f] : it->second) {
      fmt::format_to(out, "{} {:.10g}\n", nb, f);
      hi = std::max(hi, nb);
    }
    fmt::format_to(out, "\n\n");
    plots += fmt::format("{}'decay.dat' index {} using 1:2 with points pointtype 7 pointsize 1.6 linecolor {} title 'e = {}', \\\n"
                         "     exp(-({:.6g}/{})*x) with lines dashtype 2 linecolor {} notitle",
                         plots.empty() ? "" : ", \\\n     ", index, index + 1, e, alpha, e, index + 1);
  }
  const auto body = fmt::format(
      "set title 'Fig. 3 re-made: output against depth; dashed: exp(-(α/e) N_B), α = {:.3f} for all e'\n"
      "set xlabel 'number of blocks N_B'\nset ylabel 'E_{{out}} / E_{{in}}'\n"
      "set logscale y\nset format y '10^{{%L}}'\nset grid\nset key below maxcols 4\nset xrange [0.7:{}]\nset xtics 1\n"
      "set samples 200\nplot {}\n",
      alpha, hi + 0.3, plots);
  return render(dir, "decay", fmt::to_string(data), body, gnuplot,
                "Fig. 3 re-made: output fraction against the number of blocks for each e, with the single-alpha law "
                "exp(-(alpha/e) N_B) fitted to all of them through the origin");
}

Figure bar_figure(const std::vector<BarGroup>& groups, const std::vector<std::string>& series, const BarStyle& style,
                  const std::string& dir, const std::string& gnuplot) {
  const auto& name = style.name;
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  fmt::format_to(out, "# group, then one value per series ({})\n", fmt::join(series, ", "));
  for (const auto& g : groups) {
    fmt::format_to(out, "\"{}\"", g.label);
    for (std::size_t s = 0; s < series.size(); ++s) fmt::format_to(out, " {:.6g}", s < g.values.size() ? 100.0 * g.values[s] : 0.0);
    fmt::format_to(out, "\n");
  }
  std::string plots;
  for (std::size_t s = 0; s < series.size(); ++s) {
    plots += fmt::format("{}'{}.dat' using {}{} title '{}' noenhanced", s == 0 ? "" : ", ", name, s + 2, s == 0 ? ":xtic(1)" : "",
                         series[s]);
  }
  std::string references;
  for (std::size_t i = 0; i < style.references.size(); ++i) {
    const auto& [label, value] = style.references[i];
    references += fmt::format("set arrow {} from graph 0, first {:.6g} to graph 1, first {:.6g} nohead dashtype 2 linecolor {}\n"
                              "set label {} '{}' at graph 0.99, first {:.6g} right offset 0, 0.6 textcolor lt {} noenhanced\n",
                              i + 1, 100.0 * value, 100.0 * value, i + 1, i + 1, label, 100.0 * value, i + 1);
  }
  const auto body = fmt::format(
      "set title '{}' noenhanced\nset ylabel '{} (%)' noenhanced\nset yrange [0:100]\nset grid ytics\n"
      "set style data histogram\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
      "set boxwidth 0.9\nset xtics noenhanced\nset key top left\nset bmargin 5\n"
      "# Room on the right for the reference lines' labels.\nset xrange [-0.6:{:.1f}]\n{}plot {}\n",
      style.title, style.ylabel, static_cast<double>(groups.size()) + 1.2, references, plots);
  return render(dir, name, fmt::to_string(data), body, gnuplot, style.caption);
}

Figure output_figure(const postproc::CaseReduction& r, const Curve& output, const std::vector<Kick>& kicks,
                     const std::string& dir, const std::string& name, const std::string& gnuplot, const std::string& caption) {
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  fmt::format_to(out, "# time (us), output sphere E_k / E_in\n");
  const std::size_t stride = std::max<std::size_t>(1, output.t.size() / 3000);
  for (std::size_t i = 0; i < output.t.size(); i += stride) fmt::format_to(out, "{:.6g} {:.6g}\n", output.t[i] * 1e6, output.y[i] / r.e_in);
  std::string marks;
  for (std::size_t i = 0; i < kicks.size(); ++i) {
    marks += fmt::format("set label {} 'kick {}' at {:.6g}, {:.6g} offset 0.5, 0.8\n", i + 1, i + 1, kicks[i].end * 1e6,
                         kicks[i].after / r.e_in);
  }
  const double arrival = model::resolve(model::Stack::build(r.spec)).arrival_estimate * 1e6;
  std::string materials;
  for (int k = 1; k <= r.spec.blocks; ++k) materials += fmt::format("{}{}", k > 1 ? "/" : "", r.spec.block_material(k));
  marks += fmt::format("set label 100 'estimated arrival' at {:.6g}, graph 0.05 offset 0.5, 0 textcolor rgb 'gray40'\n", arrival);
  const auto body = fmt::format(
      "set title 'Output sphere, {}, e = {}' noenhanced\nset xlabel 'time t (µs)'\nset ylabel 'E_k / E_{{in}}'\n"
      "set grid\nset key top left\nset yrange [0:*]\nset offsets 0, 0, graph 0.15, 0\n"
      "set arrow 100 from {:.6g}, graph 0 to {:.6g}, graph 1 nohead dashtype 2 linecolor rgb 'gray40'\n{}"
      "plot '{}.dat' using 1:2 with lines linewidth 2 title 'output sphere'\n",
      materials, r.spec.restitution.value, arrival, arrival, marks, name);
  return render(dir, name, fmt::to_string(data), body, gnuplot, caption);
}

}  // namespace granstack::study
