#include "scaling_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <ostream>
#include <sstream>

#include "report_svg.h"
#include "scaling_measure.h"

namespace lancer::bench {

namespace {

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string num(double v) { return fmt("%.1f", v); }


// 1234567 -> "1,234,567".
std::string grouped(std::uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string rate(const RateSummary& s) {
  return fmt("%.2f", s.median) + " (" + fmt("%.2f", s.min) + "-" + fmt("%.2f", s.max) + ")";
}

constexpr double kMiB = 1024.0 * 1024.0;

// Layout in SVG user units (pixels).
constexpr double kPanelWidth = 250, kPanelHeight = 220, kPanelLeft = 64, kPanelGap = 34;
constexpr double kTop = 76, kBottom = 56, kLegendWidth = 150;

const char* colour(const std::string& spd) {
  if (spd == "balls") return "#1f77b4";
  if (spd == "gears") return "#ff7f0e";
  if (spd == "mount") return "#2ca02c";
  if (spd == "rings") return "#d62728";
  if (spd == "tetra") return "#9467bd";
  return "#777777";
}

// "10⁴" for decade 4, with the superscript digits of Unicode.
std::string power_of_ten(int decade) {
  static const char* const kSuper[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string out = "10";
  if (decade < 0) out += "⁻";
  for (char c : std::to_string(std::abs(decade))) out += kSuper[c - '0'];
  return out;
}

// A y tick's label: plain numbers (0.01, 0.1, 1, 10, 100, ...).
std::string plain_label(double v) {
  if (v >= 1.0) return fmt("%.0f", v);
  const int decimals = static_cast<int>(std::ceil(-std::log10(v) - 1e-9));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

struct Quantity {
  std::function<double(const ScalingResult&)> value;
  const char* unit;  // in the point titles
  bool dashed;
};

struct Panel {
  std::string title, axis;
  std::vector<Quantity> quantities;
};

std::vector<std::string> generators_in_order(const std::vector<ScalingResult>& results) {
  std::vector<std::string> names;
  for (const ScalingResult& r : results)
    if (std::find(names.begin(), names.end(), r.point.spd) == names.end()) names.push_back(r.point.spd);
  return names;
}

bool measured(const ScalingResult& r) { return r.failure.empty() || r.over_bound; }

std::string peak_cells(const ScalingResult& r) {
  if (r.peak_load_build_bytes < 0) return "n/a | n/a";
  return fmt("%.1f", static_cast<double>(r.peak_load_build_bytes) / kMiB) + " | " +
         fmt("%.1f", r.peak_bytes_per_triangle()) + (r.over_bound ? " (over the bound)" : "");
}

void draw_panel(std::ostringstream& o, const Panel& panel, double x0, const LogAxis& xa,
                const std::vector<ScalingResult>& results, const std::vector<std::string>& generators) {
  std::vector<double> ys;
  for (const ScalingResult& r : results)
    if (measured(r))
      for (const Quantity& q : panel.quantities) ys.push_back(q.value(r));
  const LogAxis ya = log_axis(ys);
  const double base = kTop + kPanelHeight;
  const auto x_of = [&](double v) { return x0 + (std::log10(v) - xa.lo) / (xa.hi - xa.lo) * kPanelWidth; };
  const auto y_of = [&](double v) { return base - (std::log10(v) - ya.lo) / (ya.hi - ya.lo) * kPanelHeight; };

  o << "<text x=\"" << num(x0 + kPanelWidth / 2) << "\" y=\"" << num(kTop - 10)
    << "\" text-anchor=\"middle\" font-weight=\"bold\">" << panel.title << "</text>\n";
  // Grid: a line per decade, lighter ones at 2x and 5x when the axis spans few decades.
  const bool minor = ya.hi - ya.lo <= 2;
  for (int d = ya.lo; d <= ya.hi; ++d)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, d);
      if ((m > 1.0 && (!minor || d == ya.hi)) || v > std::pow(10.0, ya.hi) * 1.0001) continue;
      const double y = y_of(v);
      o << "<line x1=\"" << num(x0) << "\" y1=\"" << num(y) << "\" x2=\"" << num(x0 + kPanelWidth) << "\" y2=\""
        << num(y) << "\" stroke=\"" << (m == 1.0 ? "#cccccc" : "#eeeeee") << "\"/>\n";
      o << "<text x=\"" << num(x0 - 5) << "\" y=\"" << num(y + 4) << "\" text-anchor=\"end\">" << plain_label(v)
        << "</text>\n";
    }
  for (int d = xa.lo; d <= xa.hi; ++d) {
    const double x = x_of(std::pow(10.0, d));
    o << "<line x1=\"" << num(x) << "\" y1=\"" << num(kTop) << "\" x2=\"" << num(x) << "\" y2=\"" << num(base)
      << "\" stroke=\"#cccccc\"/>\n";
    o << "<text x=\"" << num(x) << "\" y=\"" << num(base + 16) << "\" text-anchor=\"middle\">" << power_of_ten(d)
      << "</text>\n";
  }
  o << "<path d=\"M" << num(x0) << " " << num(kTop) << "V" << num(base) << "H" << num(x0 + kPanelWidth)
    << "\" fill=\"none\" stroke=\"#000000\"/>\n";
  o << "<text transform=\"translate(" << num(x0 - 46) << " " << num(kTop + kPanelHeight / 2)
    << ") rotate(-90)\" text-anchor=\"middle\">" << panel.axis << "</text>\n";
  o << "<text x=\"" << num(x0 + kPanelWidth / 2) << "\" y=\"" << num(base + 36)
    << "\" text-anchor=\"middle\">triangles</text>\n";

  for (const Quantity& q : panel.quantities)
    for (const std::string& g : generators) {
      std::string points;
      std::ostringstream circles;
      int count = 0;
      for (const ScalingResult& r : results) {
        if (r.point.spd != g || !measured(r) || !(q.value(r) > 0.0)) continue;
        const double x = x_of(static_cast<double>(r.point.triangles)), y = y_of(q.value(r));
        if (!points.empty()) points += ' ';
        points += num(x);
        points += ',';
        points += num(y);
        circles << "<circle class=\"point\" cx=\"" << num(x) << "\" cy=\"" << num(y) << "\" r=\"3\" fill=\""
                << (q.dashed ? "#ffffff" : colour(g)) << "\" stroke=\"" << colour(g) << "\"><title>" << r.point.name()
                << ", " << grouped(r.point.triangles) << " triangles: " << fmt("%.3g", q.value(r)) << " " << q.unit
                << "</title></circle>\n";
        ++count;
      }
      if (count >= 2)
        o << "<polyline class=\"series\" points=\"" << points << "\" fill=\"none\" stroke=\"" << colour(g)
          << "\" stroke-width=\"1.5\"" << (q.dashed ? " stroke-dasharray=\"5,3\"" : "") << "/>\n";
      o << circles.str();
    }
}

}  // namespace

LogAxis log_axis(const std::vector<double>& values) {
  double lo = 0.0, hi = 0.0;
  bool any = false;
  for (double v : values) {
    if (!(v > 0.0) || !std::isfinite(v)) continue;
    const double l = std::log10(v);
    lo = any ? std::min(lo, l) : l;
    hi = any ? std::max(hi, l) : l;
    any = true;
  }
  if (!any) return {};
  LogAxis a{static_cast<int>(std::floor(lo + 1e-9)), static_cast<int>(std::ceil(hi - 1e-9))};
  if (a.hi <= a.lo) a.hi = a.lo + 1;
  return a;
}

void write_scaling_markdown(const std::vector<ScalingResult>& results, const ScalingSettings& settings,
                            std::ostream& out) {
  out << "Primary rays of the SPD view, " << settings.image << " x " << settings.image << ", one thread, "
      << isa_name(settings.isa) << ": median (min-max) of " << settings.reps
      << " runs per mode, in millions of rays per CPU second of the tracing thread. kd-tree build: one thread, "
         "CPU seconds, median of "
      << settings.builds << " builds up to " << grouped(settings.single_build_above)
      << " triangles, one build above. Generation: wall seconds. Peak: resident memory of generating the scene "
         "and building the tree, above what the process held before (Linux VmHWM, a child process per point); the "
         "bound is "
      << fmt("%.0f", kPeakBoundBytesPerTriangle) << " bytes per triangle.\n\n";
  out << "| scene | triangles | generate s | build CPU s | kd-tree MiB | bytes / triangle | peak MiB | peak bytes / "
         "triangle | packet Mrays/CPU-s | single Mrays/CPU-s | packet / single |\n";
  out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const ScalingResult& r : results) {
    out << "| " << r.point.name() << " | " << grouped(r.point.triangles) << " | ";
    if (!measured(r)) {
      out << r.failure << " | | | | | | | | |\n";
      continue;
    }
    const double ratio = r.single.median > 0.0 ? r.packet.median / r.single.median : 0.0;
    out << fmt("%.2f", r.generate_ms / 1000.0) << " | " << fmt("%.3f", r.build_ms / 1000.0) << " | "
        << fmt("%.1f", static_cast<double>(r.accel_bytes) / kMiB) << " | " << fmt("%.1f", r.bytes_per_triangle())
        << " | " << peak_cells(r) << " | " << rate(r.packet) << " | " << rate(r.single) << " | " << fmt("%.2f", ratio) << "x |\n";
  }
}

std::string scaling_svg(const std::vector<ScalingResult>& results, const ScalingSettings& settings) {
  const std::vector<std::string> generators = generators_in_order(results);
  std::vector<double> xs;
  for (const ScalingResult& r : results)
    if (measured(r)) xs.push_back(static_cast<double>(r.point.triangles));
  const LogAxis xa = log_axis(xs);

  const std::vector<Panel> panels = {
      {"kd-tree build, 1 thread",
       "CPU seconds",
       {{[](const ScalingResult& r) { return r.build_ms / 1000.0; }, "CPU s", false}}},
      {"memory per triangle", "bytes",
       {{[](const ScalingResult& r) { return r.bytes_per_triangle(); }, "bytes/triangle (kd-tree)", false},
        {[](const ScalingResult& r) { return r.peak_bytes_per_triangle(); },
         "bytes/triangle (peak of generation + build)", true}}},
      {"primary rays, 1 thread", "Mrays per CPU second",
       {{[](const ScalingResult& r) { return r.packet.median; }, "Mrays/CPU-s (packet)", false},
        {[](const ScalingResult& r) { return r.single.median; }, "Mrays/CPU-s (single)", true}}},
  };
  std::vector<std::string> left_out;
  for (const ScalingResult& r : results)
    if (!measured(r)) left_out.push_back(r.point.name() + " (" + grouped(r.point.triangles) + "): " + r.failure);

  const double n = static_cast<double>(panels.size());
  const double width = n * (kPanelLeft + kPanelWidth) + (n - 1) * kPanelGap + kLegendWidth + 20;
  const double height = kTop + kPanelHeight + kBottom + 16.0 * static_cast<double>(left_out.size()) + 10;
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(width) << "\" height=\"" << num(height)
    << "\" viewBox=\"0 0 " << num(width) << " " << num(height)
    << "\" font-family=\"sans-serif\" font-size=\"12\" style=\"background:#ffffff\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  o << "<text x=\"" << num(kPanelLeft) << "\" y=\"22\" font-size=\"15\" font-weight=\"bold\">"
    << "Haines' SPD scenes, 10⁴ to 10⁷ triangles: Lancer's kd-tree (log-log)</text>\n";
  o << "<text x=\"" << num(kPanelLeft) << "\" y=\"40\" fill=\"#444444\">" << isa_name(settings.isa) << "; primary rays "
    << settings.image << " x " << settings.image << ", median of " << settings.reps
    << " runs; CPU time of the one working thread; rays: packet solid, single-ray dashed (open circles); memory: "
       "kd-tree solid, peak of generation + build dashed</text>\n";
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const double x0 = kPanelLeft + static_cast<double>(p) * (kPanelLeft + kPanelWidth + kPanelGap);
    draw_panel(o, panels[p], x0, xa, results, generators);
  }
  // Legend: swatches drawn as paths.
  const double lx = n * (kPanelLeft + kPanelWidth) + (n - 1) * kPanelGap + 20;
  for (std::size_t g = 0; g < generators.size(); ++g) {
    const double ly = kTop + 6 + static_cast<double>(g) * 20;
    o << "<path d=\"M" << num(lx) << " " << num(ly + 6) << "h20\" stroke=\"" << colour(generators[g])
      << "\" stroke-width=\"3\"/>\n";
    o << "<text x=\"" << num(lx + 26) << "\" y=\"" << num(ly + 10) << "\">" << generators[g] << "</text>\n";
  }
  for (std::size_t i = 0; i < left_out.size(); ++i)
    o << "<text x=\"" << num(kPanelLeft) << "\" y=\"" << num(kTop + kPanelHeight + kBottom + 16.0 * double(i))
      << "\" fill=\"#aa0000\">not measured: " << xml_escape(left_out[i]) << "</text>\n";
  o << "</svg>\n";
  return o.str();
}

}  // namespace lancer::bench
