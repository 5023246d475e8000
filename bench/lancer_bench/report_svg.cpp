#include "report_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace lancer::bench {

namespace {

// Layout in SVG user units (pixels).
constexpr double kLeft = 80, kRight = 200, kTop = 60, kBottom = 130, kPlotHeight = 320;
constexpr double kBarWidth = 16, kGroupGap = 24;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}


const char* colour(Mode m) {
  switch (m) {
    case Mode::Packet: return "#1f77b4";
    case Mode::Single: return "#ff7f0e";
    case Mode::Embree: return "#2ca02c";
  }
  return "#777777";
}

// A round axis maximum and tick step (1, 2 or 5 times a power of ten) above `top`.
std::pair<double, double> axis_scale(double top) {
  if (!(top > 0.0)) return {1.0, 0.2};
  const double raw = top / 5.0;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double f : {1.0, 2.0, 5.0, 10.0})
    if (f * power >= raw) {
      step = f * power;
      break;
    }
  return {std::ceil(top / step) * step, step};
}

std::string tick_label(double v, double step) {
  char buf[32];
  std::snprintf(buf, sizeof buf, step < 1.0 ? "%.1f" : "%.0f", v);
  return buf;
}

struct Group {
  std::string scene;
  const Row* row = nullptr;  // nullptr or failed: no bars
};

}  // namespace

PlotSelection default_plot_selection(const BenchRun& run) {
  PlotSelection s;
  if (!run.options.sets.empty()) s.set = run.options.sets.front();
  if (!run.options.isas.empty()) s.isa = run.options.isas.front();
  if (!run.threads.empty()) s.threads = run.threads.back();
  return s;
}

std::string plot_svg(const BenchRun& run, const PlotSelection& sel) {
  const std::vector<Mode>& modes = run.options.modes;
  std::vector<Group> groups;
  double top = 0.0;
  for (const SceneResult& s : run.scenes) {
    Group g{s.name, nullptr};
    for (const Row& r : s.rows)
      if (r.set == sel.set && r.isa == sel.isa && r.threads == sel.threads && r.failure.empty()) g.row = &r;
    if (g.row)
      for (const ModeTiming& t : g.row->modes) top = std::max(top, summarize(t.seconds, g.row->rays).max);
    groups.push_back(g);
  }
  const auto [y_max, y_step] = axis_scale(top);
  const double group_width = static_cast<double>(modes.size()) * kBarWidth + kGroupGap;
  const double plot_width = std::max(240.0, static_cast<double>(groups.size()) * group_width);
  const double width = kLeft + plot_width + kRight, height = kTop + kPlotHeight + kBottom;
  const double base = kTop + kPlotHeight;
  const auto y_of = [&](double v) { return base - v / y_max * kPlotHeight; };

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(width) << "\" height=\"" << num(height)
    << "\" viewBox=\"0 0 " << num(width) << " " << num(height)
    << "\" font-family=\"sans-serif\" font-size=\"12\" style=\"background:#ffffff\">\n";
  o << "<text x=\"" << num(kLeft)
    << "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">lancer-bench: " << ray_set_name(sel.set) << " rays, "
    << sel.threads << (sel.threads == 1 ? " thread" : " threads") << ", " << isa_name(sel.isa) << "</text>\n";
  o << "<text x=\"" << num(kLeft) << "\" y=\"42\" fill=\"#444444\">Median Mrays/s of " << run.options.reps
    << " runs (whiskers: min to max), " << run.options.size << "x" << run.options.size
    << " image; higher is better</text>\n";

  // Grid, ticks and axes.
  for (double v = 0.0; v <= y_max + 0.5 * y_step; v += y_step) {
    const double y = y_of(v);
    o << "<line x1=\"" << num(kLeft) << "\" y1=\"" << num(y) << "\" x2=\"" << num(kLeft + plot_width) << "\" y2=\""
      << num(y) << "\" stroke=\"#dddddd\"/>\n";
    o << "<text x=\"" << num(kLeft - 6) << "\" y=\"" << num(y + 4) << "\" text-anchor=\"end\">" << tick_label(v, y_step)
      << "</text>\n";
  }
  o << "<line x1=\"" << num(kLeft) << "\" y1=\"" << num(kTop) << "\" x2=\"" << num(kLeft) << "\" y2=\"" << num(base)
    << "\" stroke=\"#000000\"/>\n";
  o << "<line x1=\"" << num(kLeft) << "\" y1=\"" << num(base) << "\" x2=\"" << num(kLeft + plot_width) << "\" y2=\""
    << num(base) << "\" stroke=\"#000000\"/>\n";
  o << "<text transform=\"translate(" << num(kLeft - 52) << " " << num(kTop + kPlotHeight / 2)
    << ") rotate(-90)\" text-anchor=\"middle\">Mrays/s</text>\n";
  o << "<text x=\"" << num(kLeft + plot_width / 2) << "\" y=\"" << num(height - 8)
    << "\" text-anchor=\"middle\">scene</text>\n";

  // Bars, one group per scene.
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const double x0 = kLeft + kGroupGap / 2 + static_cast<double>(g) * group_width;
    const double label_x = x0 + static_cast<double>(modes.size()) * kBarWidth / 2;
    o << "<text transform=\"translate(" << num(label_x) << " " << num(base + 14)
      << ") rotate(40)\" text-anchor=\"start\">" << xml_escape(groups[g].scene) << "</text>\n";
    if (!groups[g].row) {
      o << "<text x=\"" << num(label_x) << "\" y=\"" << num(base - 6) << "\" text-anchor=\"middle\" fill=\"#aa0000\">"
        << "failed</text>\n";
      continue;
    }
    const Row& row = *groups[g].row;
    for (std::size_t m = 0; m < modes.size(); ++m) {
      const auto t =
          std::find_if(row.modes.begin(), row.modes.end(), [&](const ModeTiming& mt) { return mt.mode == modes[m]; });
      if (t == row.modes.end()) continue;
      const RateSummary s = summarize(t->seconds, row.rays);
      const double x = x0 + static_cast<double>(m) * kBarWidth;
      o << "<rect class=\"bar\" x=\"" << num(x) << "\" y=\"" << num(y_of(s.median)) << "\" width=\""
        << num(kBarWidth - 2) << "\" height=\"" << num(base - y_of(s.median)) << "\" fill=\"" << colour(modes[m])
        << "\"><title>" << xml_escape(groups[g].scene) << ", " << mode_name(modes[m]) << ": " << num(s.median)
        << " Mrays/s</title></rect>\n";
      const double cx = x + (kBarWidth - 2) / 2;
      o << "<line x1=\"" << num(cx) << "\" y1=\"" << num(y_of(s.min)) << "\" x2=\"" << num(cx) << "\" y2=\""
        << num(y_of(s.max)) << "\" stroke=\"#000000\"/>\n";
    }
  }

  // Legend: swatches drawn as paths, so every <rect> is a bar.
  const double lx = kLeft + plot_width + 20;
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const double ly = kTop + 10 + static_cast<double>(m) * 20;
    o << "<path d=\"M" << num(lx) << " " << num(ly) << "h12v12h-12z\" fill=\"" << colour(modes[m]) << "\"/>\n";
    o << "<text x=\"" << num(lx + 18) << "\" y=\"" << num(ly + 10) << "\">" << mode_name(modes[m])
      << (modes[m] == Mode::Packet && sel.set == RaySet::Shadow ? " (occluded per ray)" : "") << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace lancer::bench
