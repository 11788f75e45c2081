#include "figures.hpp"

#include <granstack/formats/manifest.hpp>
#include <granstack/model/resolution.hpp>
#include <granstack/model/stack.hpp>
#include <granstack/postproc/plot.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

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

std::string gp_quote(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

namespace {
// From the first time any curve exceeds `start_level` of its largest value to the last sample a
// curve's `active(curve, i, top)` holds at, with a margin of 8 % of that stretch either side.
template <typename Active>
std::pair<double, double> window(const std::vector<Curve>& curves, double start_level, Active active) {
  double first = INFINITY, last = 0.0;
  for (const auto& c : curves) {
    const double top = c.max();
    if (!(top > 0.0)) continue;
    for (std::size_t i = 0; i < c.y.size(); ++i) {
      if (c.y[i] > start_level * top) first = std::min(first, c.t[i]);
      if (active(c, i, top)) last = std::max(last, c.t[i]);
    }
  }
  if (!(first < last)) return {0.0, 0.0};
  const double margin = 0.08 * (last - first);
  return {std::max(0.0, first - margin), last + margin};
}
}  // namespace

std::pair<double, double> action_window(const std::vector<Curve>& curves, double start_level, double end_level) {
  return window(curves, start_level, [&](const Curve& c, std::size_t i, double top) { return c.y[i] > end_level * top; });
}

std::pair<double, double> settle_window(const std::vector<Curve>& curves, double start_level, double tolerance) {
  return window(curves, start_level,
                [&](const Curve& c, std::size_t i, double top) { return std::fabs(c.y[i] - c.y.back()) > tolerance * top; });
}

// An inset magnifies the lower blocks only where they stay below this fraction of the scale.
constexpr double kInsetBelow = 0.3;

Figure energy_plot(const EnergyPlot& p, const std::string& dir, const std::string& gnuplot) {
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  const auto nb = static_cast<int>(p.curves.size());
  const std::vector<Curve> lower_curves(p.curves.begin() + std::min(nb, p.inset_from - 1), p.curves.end());
  const auto [t0, t1] = p.window ? *p.window : action_window(p.curves, 0.01, 0.2);
  auto [i0, i1] = action_window(lower_curves, 0.01, 0.2);
  if (p.window) i1 = t1;
  double lower = 0.0, lower_blocks = 0.0;  // the inset's largest value; its blocks' alone
  for (int k = 0; k < nb; ++k) {
    const auto& c = p.curves[static_cast<std::size_t>(k)];
    fmt::format_to(out, "# block {}: time (µs), E_k / {:.6g} J\n", k + 1, p.scale);
    const std::size_t stride = std::max<std::size_t>(1, c.t.size() / 4000);
    for (std::size_t i = 0; i < c.t.size(); i += stride) {
      const double v = c.y[i] / p.scale;
      if (k + 1 >= p.inset_from) {
        lower = std::max(lower, v);
        lower_blocks = std::max(lower_blocks, v);
      }
      fmt::format_to(out, "{:.6g} {:.6g}\n", c.t[i] * 1e6, v);
    }
    fmt::format_to(out, "\n\n");
  }
  std::string compared, compared_inset;
  for (std::size_t i = 0; i < p.compare.size(); ++i) {
    const auto& [title, c] = p.compare[i];
    fmt::format_to(out, "# {}: time (µs), E_k / {:.6g} J\n", title, p.scale);
    const std::size_t stride = std::max<std::size_t>(1, c.t.size() / 4000);
    for (std::size_t j = 0; j < c.t.size(); j += stride) {
      lower = std::max(lower, c.y[j] / p.scale);
      fmt::format_to(out, "{:.6g} {:.6g}\n", c.t[j] * 1e6, c.y[j] / p.scale);
    }
    fmt::format_to(out, "\n\n");
    const auto line = fmt::format(", '{}.dat' index {} using 1:2 with lines dashtype 2 linewidth 1.5 linecolor rgb 'gray40'",
                                  p.name, static_cast<std::size_t>(nb) + i);
    compared += line + " title " + gp_quote(title) + " noenhanced";
    compared_inset += line + " notitle";
  }
  // The paper's values as dashed lines with their labels in the inset's own key (top right, in
  // the room the inset's y range leaves above its curves): no label is written over a curve.
  std::string references;
  for (std::size_t i = 0; i < p.references.size(); ++i) {
    const auto& [label, value] = p.references[i];
    lower = std::max(lower, value);
    references += fmt::format(", {:.6g} with lines dashtype {} linewidth 1.5 linecolor rgb 'black' title {} noenhanced", value,
                              i + 2, gp_quote(label));
  }
  // Without an inset (the lower blocks as large as the scale): the curves on [0, 1.1], the key below.
  if (lower_blocks >= kInsetBelow) {
    const auto body = fmt::format(
        "set title {} noenhanced\nset xlabel 'time t (µs)'\nset ylabel {} noenhanced\nset grid\n"
        "set key below maxrows 1 box\nset bmargin 6\nset yrange [0:1.1]\nset ytics 0, 0.2, 1.0\nset xrange [{:.6g}:{:.6g}]\n"
        "plot for [k=1:{}] '{}.dat' index (k-1) using 1:2 with lines linewidth 2 linecolor k title sprintf('block %d', k){}{}\n",
        gp_quote(p.title), gp_quote(p.ylabel), t0 * 1e6, t1 * 1e6, nb, p.name, compared, references);
    return render(dir, p.name, fmt::to_string(data), body, gnuplot, p.caption);
  }
  // Fixed margins, so the inset sits in the empty band above the curves (the y axis reaches 1.75,
  // the curves 1): it covers no curve, and the key sits at the top left, beside it.
  const auto body = fmt::format(
      "set title {} noenhanced\nset xlabel 'time t (µs)'\nset ylabel {} noenhanced\n"
      "set lmargin at screen 0.09\nset rmargin at screen 0.97\nset bmargin at screen 0.11\nset tmargin at screen 0.92\n"
      "set grid\nset key at graph 0.02, graph 0.97 left top box opaque\nset yrange [0:1.75]\nset ytics 0, 0.2, 1.0\n"
      "set xrange [{:.6g}:{:.6g}]\nset multiplot\n"
      "plot for [k=1:{}] '{}.dat' index (k-1) using 1:2 with lines linewidth 2 linecolor k title sprintf('block %d', k){}\n"
      "# The inset: blocks {} to {}, magnified on their own scales, the paper's values dashed.\n"
      "set lmargin at screen 0.40\nset rmargin at screen 0.95\nset bmargin at screen 0.62\nset tmargin at screen 0.895\n"
      "unset title\nunset xlabel\nunset ylabel\n{}set ytics autofreq\n"
      "set object 1 rectangle from graph 0, graph 0 to graph 1, graph 1 behind fillcolor rgb 'white' fillstyle solid noborder\n"
      "set xrange [{:.6g}:{:.6g}]\nset yrange [0:{:.3g}]\n"
      "plot for [k={}:{}] '{}.dat' index (k-1) using 1:2 with lines linewidth 2 linecolor k notitle{}{}\n"
      "unset multiplot\n",
      gp_quote(p.title), gp_quote(p.ylabel), t0 * 1e6, t1 * 1e6, nb, p.name, compared, p.inset_from, nb,
      // The inset's key holds the paper's values; none, no key.
      p.references.empty() ? "unset key\n" : "set key default\nset key inside right top box opaque samplen 2\n", i0 * 1e6, i1 * 1e6,
      lower > 0.0 ? (1.3 + 0.2 * static_cast<double>(p.references.size())) * lower : 1.0, p.inset_from, nb, p.name,
      compared_inset, references);
  return render(dir, p.name, fmt::to_string(data), body, gnuplot, p.caption);
}

Figure decay_figure(const std::map<double, std::vector<std::pair<int, double>>, std::greater<>>& by_e, double alpha,
                    const std::vector<std::pair<int, double>>& paper, double alpha_paper, const std::string& dir,
                    const std::string& gnuplot) {
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
    // Each e its own marker, the first (the largest e) an open ring around the others: nearly equal
    // outputs (e = 1 and 0.99) would otherwise hide one under the other.
    static constexpr int kPointTypes[] = {6, 7, 9, 13, 5, 11};
    static constexpr double kPointSizes[] = {2.6, 1.4, 1.4, 1.6, 1.2, 1.4};
    const auto style = static_cast<std::size_t>(index) % std::size(kPointTypes);
    plots += fmt::format("{}'decay.dat' index {} using 1:2 with points pointtype {} pointsize {:g} linewidth 2 linecolor {} "
                         "title 'e = {}', \\\n     exp(-({:.6g}/{})*x) with lines dashtype 2 linecolor {} notitle",
                         plots.empty() ? "" : ", \\\n     ", index, kPointTypes[style], kPointSizes[style], index + 1, e, alpha,
                         e, index + 1);
    // The paper's own law for this e, exp(-(alpha_paper / e) N_B), dotted in the same colour (e = 1's
    // is drawn with the paper's points below).
    if (e != 1.0) {
      plots += fmt::format(", \\\n     exp(-({:.6g}/{})*x) with lines dashtype 3 linewidth 2 linecolor {} notitle", alpha_paper,
                           e, index + 1);
    }
  }
  if (!paper.empty()) {
    fmt::format_to(out, "# the paper: N_B, E_out/E_in\n");
    for (const auto& [nb, f] : paper) fmt::format_to(out, "{} {:.6g}\n", nb, f);
    fmt::format_to(out, "\n\n");
    plots += fmt::format(", \\\n     'decay.dat' index {} using 1:2 with points pointtype 4 pointsize 2.4 linewidth 2 linecolor "
                         "rgb 'black' title 'paper, e = 1', \\\n     exp(-{:.6g}*x) with lines dashtype 3 linewidth 2 linecolor "
                         "rgb 'black' title 'paper: exp(-{:g} N_B)'",
                         index, alpha_paper, alpha_paper);
  }
  const auto body = fmt::format(
      "set title 'Fig. 3 re-made: output against depth; dashed: exp(-(α/e) N_B), α = {:.3f} for all e; dotted: the "
      "paper, α = {:g}'\n"
      "set xlabel 'number of blocks N_B'\nset ylabel 'E_{{out}} / E_{{in}}'\n"
      "set logscale y\nset format y '10^{{%L}}'\nset grid\nset key below maxcols 4\nset xrange [0.7:{}]\nset xtics 1\n"
      "set samples 200\nplot {}\n",
      alpha, alpha_paper, hi + 0.3, plots);
  return render(dir, "decay", fmt::to_string(data), body, gnuplot,
                fmt::format("Fig. 3 re-made: output fraction against the number of blocks for each e, with the "
                            "single-alpha law exp(-(alpha/e) N_B) fitted to all of them through the origin (dashed) and "
                            "the paper's law with its alpha = {:g} for each e (dotted)", alpha_paper));
}

Figure decay_series_figure(const std::vector<DecaySeries>& series, const std::string& name, const std::string& caption,
                           const std::string& dir, const std::string& gnuplot) {
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  std::string plots;
  int hi = 1;
  static constexpr int kPointTypes[] = {6, 7, 9, 13, 5, 11, 4};
  // Drawn last first: the first series (the reference) on top, an open ring around what it equals.
  for (std::size_t k = series.size(); k-- > 0;) {
    const auto& s = series[k];
    fmt::format_to(out, "# {}: N_B, E_out/E_in\n", s.title);
    for (const auto& [nb, f] : s.points) {
      fmt::format_to(out, "{} {:.10g}\n", nb, f);
      hi = std::max(hi, nb);
    }
    fmt::format_to(out, "\n\n");
    plots += fmt::format("{}'{}.dat' index {} using 1:2 with points pointtype {} pointsize {:g} linewidth 2 linecolor {} "
                         "title {}, \\\n     {:.6g}*exp(-{:.6g}*x) with lines dashtype 2 linecolor {} notitle",
                         plots.empty() ? "" : ", \\\n     ", name, series.size() - 1 - k,
                         kPointTypes[k % std::size(kPointTypes)], k == 0 ? 2.8 : 1.6, k + 1, gp_quote(s.title), s.prefactor,
                         s.alpha, k + 1);
  }
  const auto body = fmt::format(
      "set title 'Output against depth; dashed: A exp(-α N_B) fitted to each'\n"
      "set xlabel 'number of blocks N_B'\nset ylabel 'E_{{out}} / E_{{in}}'\n"
      "set logscale y\nset format y '10^{{%L}}'\nset grid\nset key below maxcols 2\nset xrange [0.7:{}]\nset xtics 1\n"
      "set samples 200\nplot {}\n",
      hi + 0.3, plots);
  return render(dir, name, fmt::to_string(data), body, gnuplot, caption);
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
  // The reference values as dashed lines named in the key (a label on the plot would need room
  // beside the bars or stand over them).
  std::string references;
  for (std::size_t i = 0; i < style.references.size(); ++i) {
    const auto& [label, value] = style.references[i];
    plots += fmt::format(", {:.6g} with lines dashtype 2 linewidth 1.5 linecolor {} title '{}' noenhanced", 100.0 * value, i + 1, label);
  }
  for (std::size_t i = 0; i < style.bands.size(); ++i) {
    const auto& [low, high] = style.bands[i];
    references += fmt::format("set object {} rectangle from graph 0, first {:.6g} to graph 1, first {:.6g} behind "
                              "fillstyle transparent solid 0.15 noborder fillcolor lt {}\n",
                              i + 1, 100.0 * low, 100.0 * high, i + 1);
  }
  const auto body = fmt::format(
      "set title '{}' noenhanced\nset ylabel '{} (%)' noenhanced\nset yrange [0:100]\nset grid ytics\n"
      "set style data histogram\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
      "set boxwidth 0.9\nset xtics noenhanced\nset key below maxcols 3 box\nset bmargin 9\n"
      "set xrange [-0.6:{:.1f}]\n{}plot {}\n",
      style.title, style.ylabel, static_cast<double>(groups.size()) - 0.4, references, plots);
  return render(dir, name, fmt::to_string(data), body, gnuplot, style.caption);
}

Figure output_figure(const postproc::CaseReduction& r, const Curve& output, const OutputFigure& f, const std::string& dir,
                     const std::string& name, const std::string& gnuplot, const std::string& caption) {
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  auto write = [&](const std::string& title, const Curve& c) {
    fmt::format_to(out, "# {}: time (µs), output sphere E_k / E_in\n", title);
    const std::size_t stride = std::max<std::size_t>(1, c.t.size() / 3000);
    for (std::size_t i = 0; i < c.t.size(); i += stride) fmt::format_to(out, "{:.6g} {:.6g}\n", c.t[i] * 1e6, c.y[i] / r.e_in);
    fmt::format_to(out, "\n\n");
  };
  write("output sphere", output);
  std::string plots = fmt::format("'{}.dat' index 0 using 1:2 with lines linewidth 2 title 'e = {:g}'", name, f.restitution);
  double t_last = r.blow_end_time.value_or(output.t.empty() ? 0.0 : output.t.back()), y_max = output.max() / r.e_in;
  for (std::size_t i = 0; i < f.damped.size(); ++i) {
    write(f.damped[i].first, f.damped[i].second);
    plots += fmt::format(", '{}.dat' index {} using 1:2 with lines linewidth 2 dashtype {} title {} noenhanced", name, i + 1, i + 2,
                         gp_quote(f.damped[i].first));
    y_max = std::max(y_max, f.damped[i].second.max() / r.e_in);
    if (!f.damped[i].second.t.empty()) t_last = std::max(t_last, f.damped[i].second.t.back());
  }
  std::string materials;
  for (int k = 1; k <= r.spec.blocks; ++k) materials += fmt::format("{}{}", k > 1 ? "/" : "", r.spec.block_material(k));
  const double readout = f.readout_time * 1e6;
  // The fixed read-out time, where a curve reaches it; after every run had stopped, it is said, not drawn.
  double data_end = output.t.empty() ? 0.0 : output.t.back();
  for (const auto& [title, c] : f.damped) data_end = std::max(data_end, c.t.empty() ? 0.0 : c.t.back());
  const bool readout_in_data = readout <= data_end * 1e6;
  std::string marks =
      readout_in_data
          ? fmt::format("set arrow 100 from {0:.6g}, graph 0 to {0:.6g}, graph 1 nohead dashtype 2 linecolor rgb 'gray40'\n"
                        "set label 100 '2 arrivals' at {0:.6g}, graph 0.05 offset 0.5, 0 textcolor rgb 'gray40' front\n",
                        readout)
          : fmt::format("set label 100 '2 arrivals ({:.0f} µs) come after every run had stopped' at graph 0.98, graph 0.05 "
                        "right textcolor rgb 'gray40' front\n",
                        readout);
  if (r.blow_end_time) {
    marks += fmt::format("set arrow 102 from {0:.6g}, graph 0 to {0:.6g}, graph 1 nohead dashtype 3 linecolor rgb 'gray20'\n"
                         "set label 102 'blow ended (e = 1)' at {0:.6g}, graph 0.12 right offset -0.5, 0 textcolor rgb 'gray20' front\n",
                         *r.blow_end_time * 1e6);
  }
  marks += fmt::format("set arrow 101 from graph 0, first {0:.6g} to graph 1, first {0:.6g} nohead dashtype 2 linewidth 1.5 "
                       "linecolor rgb 'black'\nset label 101 'paper: {1}' at graph 0.98, first {0:.6g} right offset 0, 0.6 front\n",
                       f.paper, fmt::format("{:g} %", 100.0 * f.paper));
  const double t_end = 1.1 * std::max(t_last * 1e6, readout_in_data ? readout : 0.0);
  const double y_top = 1.25 * std::max(y_max, f.paper);
  // The key below the plot: inside, it would cover a curve (they run the plot's width).
  const auto body = fmt::format(
      "set title 'Output sphere, {}' noenhanced\nset xlabel 'time t (µs)'\nset ylabel 'E_k / E_{{in}}'\n"
      "set grid\nset key below maxcols 2 box\nset bmargin 8\n"
      "set xrange [0:{:.6g}]\nset yrange [0:{:.6g}]\n{}plot {}\n",
      materials, t_end, y_top, marks, plots);
  return render(dir, name, fmt::to_string(data), body, gnuplot, caption);
}

Figure scan_figure(const std::vector<ScanSeries>& series, const std::vector<ScanBand>& bands, const std::string& dir,
                   const std::string& gnuplot, const std::string& caption) {
  const std::string name = "teflon_restitution_scan";
  fmt::memory_buffer data;
  auto out = std::back_inserter(data);
  std::string plots, shading;
  for (std::size_t i = 0; i < series.size(); ++i) {
    fmt::format_to(out, "# {}: e, E_out/E_in\n", series[i].title);
    for (const auto& [e, f] : series[i].by_e) fmt::format_to(out, "{:g} {:.6g}\n", e, f);
    fmt::format_to(out, "\n\n");
    plots += fmt::format("{}'{}.dat' index {} using 1:2 with linespoints linewidth 2 pointtype {} linecolor {} dashtype {} title {} "
                         "noenhanced",
                         i == 0 ? "" : ", ", name, i, 7 + 2 * static_cast<int>(i % 3), series[i].band + 1, i % 2 + 1,
                         gp_quote(series[i].title));
  }
  const char* colours[] = {"#9400d3", "#009e73", "#56b4e9", "#e69f00"};  // gnuplot's line types 1 to 4
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const auto* c = colours[b % 4];
    shading += fmt::format("set object {0} rectangle from graph 0, first {1:.6g} to graph 1, first {2:.6g} behind fillcolor rgb '{3}' "
                           "fillstyle transparent solid 0.15 noborder\n"
                           "set arrow {0} from graph 0, first {4:.6g} to graph 1, first {4:.6g} nohead dashtype 3 linewidth 1.5 "
                           "linecolor rgb '{3}'\nset label {0} {5} at graph 0.01, first {4:.6g} left offset 0, 0.6 textcolor rgb '{3}' "
                           "noenhanced\n",
                           b + 1, bands[b].low, bands[b].high, c, bands[b].paper, gp_quote(bands[b].label));
  }
  const auto body = fmt::format(
      "set title 'The output against the restitution of the Teflon contacts, by read-out'\n"
      "set xlabel 'restitution e of the steel/Teflon and Teflon/Teflon contacts'\nset ylabel 'E_{{out}} / E_{{in}}'\n"
      "set logscale y\nset grid\nset key below maxcols 2 spacing 1.2\nset bmargin 7\nset xrange [0.48:1.02]\n{}plot {}\n",
      shading, plots);
  return render(dir, name, fmt::to_string(data), body, gnuplot, caption);
}

namespace {

// A tic step of 1, 2 or 5 times a power of ten giving about `count` tics over `span`.
double nice_step(double span, double count) {
  const double raw = span / count, decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * decade >= raw) return m * decade;
  }
  return 10.0 * decade;
}

// One view of the spheres: data block `index` of the drawing's file, (h, z, radius, colour) in mm.
struct View {
  std::string title, axis;
  double lo = INFINITY, hi = -INFINITY, bottom = INFINITY, top = -INFINITY;
};

// The drawings' colours by number: 1 striker, 2 steel, 3 Teflon, 4 other materials, then the marks
// (5: a block's middle-row sphere of the impact path, 6: the output sphere).
constexpr std::array<const char*, 7> kColours{"", "red", "gray50", "orange", "skyblue", "blue", "web-green"};

std::string palette() {
  std::string entries;
  for (std::size_t k = 1; k < kColours.size(); ++k) entries += fmt::format("{}{} '{}'", k > 1 ? ", " : "", k, kColours[k]);
  return fmt::format("set palette defined ({})\nset cbrange [1:{}]\nunset colorbox\n", entries, kColours.size() - 1);
}

int material_colour(const std::string& material) { return material == "steel" ? 2 : material == "teflon" ? 3 : 4; }

// `materials`: the stack's type_materials().
int sphere_colour(const model::Stack& stack, const std::vector<std::string>& materials, const model::Sphere& s,
                  const std::vector<DrawingMark>& marks) {
  for (const auto& m : marks) {
    if (m.id == s.id) return m.colour;
  }
  if (s.id <= stack.strikers()) return 1;
  return material_colour(materials.at(static_cast<std::size_t>(s.atom_type - 1)));
}

// The spheres of one view; `z_window` (m) keeps those whose centres lie in it.
void add_view(const model::Stack& stack, bool along_x, bool one_panel, const std::vector<DrawingMark>& marks,
              const std::optional<std::pair<double, double>>& z_window, View& v, fmt::memory_buffer& data) {
  auto out = std::back_inserter(data);
  const auto materials = stack.type_materials();
  for (const auto& s : stack.spheres()) {
    const bool striker = s.id <= stack.strikers();
    if (one_panel && !striker && (stack.is_matrix(s) || s.column_y != stack.impact_panel())) continue;
    if (one_panel && striker && s.id != stack.impact_panel() && stack.strikers() > 1) continue;
    if (z_window && (s.z < z_window->first || s.z > z_window->second)) continue;
    const double h = (along_x ? s.y : s.x) * 1e3, z = s.z * 1e3, rad = s.radius * 1e3;
    fmt::format_to(out, "{:.6g} {:.6g} {:.6g} {}\n", h, z, rad, sphere_colour(stack, materials, s, marks));
    v.lo = std::min(v.lo, h - rad);
    v.hi = std::max(v.hi, h + rad);
    v.top = std::max(v.top, z + rad);
    v.bottom = std::min(v.bottom, z - rad);
  }
  fmt::format_to(out, "\n\n");
}

// `z_span` (mm): the height every panel shows from its lowest sphere up, so that panels side by
// side share one scale.
std::string view_script(const View& v, int index, const std::string& name, double z_span = 0.0) {
  const double height = std::max(v.top - v.bottom, z_span);
  const double pad = 0.04 * std::max(v.hi - v.lo, height);
  return fmt::format("set title {} noenhanced\nset xlabel '{} (mm)'\nset xrange [{:.6g}:{:.6g}]\nset yrange [{:.6g}:{:.6g}]\n"
                     "set xtics {:g}\nset ytics {:g}\n"
                     "plot '{}.dat' index {} using 1:2:3:4 with circles linewidth 0.3 fillcolor palette\n",
                     gp_quote(v.title), v.axis, v.lo - pad, v.hi + pad, v.bottom - pad, v.bottom + height + pad,
                     nice_step(v.hi - v.lo + 2 * pad, z_span > 0.0 ? 3 : 4), nice_step(height + 2 * pad, 6), name, index);
}

constexpr const char* kDrawingStyle =
    "set size ratio -1\nunset key\nset style fill transparent solid 0.6 border lc rgb 'black'\n";

// The colours' meanings beside a stack's panels (right of screen 0.69): the striker, the blocks'
// materials, the marks (5: a block's middle-row sphere of the impact path, 6: the output sphere).
std::string drawing_legend(const model::Stack& stack, const std::vector<DrawingMark>& marks) {
  std::vector<std::pair<int, std::string>> rows{{1, "the striker"}};
  std::vector<std::string> seen;
  for (const auto& b : stack.blocks()) {
    if (std::find(seen.begin(), seen.end(), b.material) != seen.end()) continue;
    seen.push_back(b.material);
    rows.emplace_back(material_colour(b.material), b.material + " spheres");
  }
  const auto marked = [&](int colour) {
    return std::any_of(marks.begin(), marks.end(), [&](const DrawingMark& m) { return m.colour == colour; });
  };
  if (marked(5)) rows.emplace_back(5, "middle-row sphere (impact path)");
  if (marked(6)) rows.emplace_back(6, "the output sphere");
  std::string out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double y = 0.85 - 0.06 * static_cast<double>(i);
    out += fmt::format("set object {} circle at screen 0.705, screen {:.3f} size screen 0.012 fillcolor rgb '{}' "
                       "fillstyle transparent solid 0.6 border lc rgb 'black' front\n"
                       "set label {} {} at screen 0.725, screen {:.3f} left front noenhanced\n",
                       100 + i, y, kColours.at(static_cast<std::size_t>(rows[i].first)), 100 + i, gp_quote(rows[i].second), y);
  }
  // Drawn with an empty plot, so the objects and labels appear once.
  return out + "unset title\nunset xlabel\nunset ylabel\nunset border\nunset tics\nset lmargin at screen 0.69\n"
               "set rmargin at screen 0.99\nset xrange [0:1]\nset yrange [0:1]\nplot NaN notitle\n";
}

}  // namespace

Figure stack_drawing(const model::Stack& stack, const std::string& dir, const std::string& name, const std::string& gnuplot,
                     const std::string& caption, const std::vector<DrawingMark>& marks) {
  fmt::memory_buffer data;
  fmt::format_to(std::back_inserter(data), "# per view: h (mm, x or y), z (mm), radius (mm), colour: 1 striker, 2 steel, 3 Teflon, 4 other, 5 and 6 marked\n");
  View side{stack.container() ? "the panel hit, x-z plane" : "the simulated stack, x-z plane", "x"};
  add_view(stack, false, true, marks, std::nullopt, side, data);
  std::string plots = view_script(side, 0, name);
  std::string layout = "set multiplot\n";
  const int nb = stack.spec().blocks;
  if (stack.container()) {
    View across{"the container seen along x (every sphere)", "y"};
    add_view(stack, true, false, marks, std::nullopt, across, data);
    layout = "set multiplot layout 1, 2\n";
    plots += view_script(across, 1, name);
  } else if (nb >= 2) {
    // A stack is tall and narrow, its lowest spheres small: beside it, its lowest blocks magnified
    // (the output sphere's mark among them), each panel on its own scale.
    const int from = std::max(2, nb - 1);
    const auto& upper = stack.block(from);
    const double top = upper.bottom_row_z + 2.0 * upper.radius * (upper.rows - 1) + 0.5 * upper.radius;
    View low{from == nb ? fmt::format("block {}, magnified", nb) : fmt::format("blocks {} and {}, magnified", from, nb), "x"};
    add_view(stack, false, true, marks, std::pair{-INFINITY, top}, low, data);
    plots = "set lmargin at screen 0.09\nset rmargin at screen 0.30\n" + plots +
            "set lmargin at screen 0.36\nset rmargin at screen 0.68\n" + view_script(low, 1, name) + drawing_legend(stack, marks);
  }
  const auto body = fmt::format("set ylabel 'z (mm)'\n{}{}{}{}unset multiplot\n", kDrawingStyle, palette(), layout, plots);
  return render(dir, name, fmt::to_string(data), body, gnuplot, caption);
}

Figure panels_drawing(const std::vector<DrawingPanel>& panels, const std::string& dir, const std::string& name,
                      const std::string& gnuplot, const std::string& caption) {
  fmt::memory_buffer data;
  fmt::format_to(std::back_inserter(data), "# per panel: x (mm), z (mm), radius (mm), colour: 1 striker, 2 steel, 3 Teflon, 4 other, 5 and 6 marked\n");
  std::vector<View> views;
  double span = 0.0;
  for (const auto& p : panels) {
    views.push_back({p.title, "x"});
    add_view(p.stack, false, true, p.marks, p.z_window, views.back(), data);
    span = std::max(span, views.back().top - views.back().bottom);
  }
  std::string plots;
  for (std::size_t i = 0; i < views.size(); ++i) plots += view_script(views[i], static_cast<int>(i), name, span);
  const auto body = fmt::format("set ylabel 'z (mm)'\n{}{}set multiplot layout 1, {}\n{}unset multiplot\n", kDrawingStyle,
                                palette(), panels.size(), plots);
  return render(dir, name, fmt::to_string(data), body, gnuplot, caption);
}

}  // namespace granstack::study
