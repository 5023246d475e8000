#include "caustic_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "accel/accel_factory.h"
#include "render/image_io.h"
#include "render/renderer.h"
#include "scene/load_scene.h"

namespace lancer::bench {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr std::uint64_t kSeed = 0;
constexpr std::uint64_t kReferenceSeeds[2] = {101, 102};
// Error samples per render: at seconds x 2^-k, k = kCurvePoints - 1 ... 0.
constexpr int kCurvePoints = 6;

struct Region {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// Mean over the region's pixels and channels of (a - b)^2, or of (a - (b + c) / 2)^2.
double mse(const ImageRGB& a, const ImageRGB& b, const Region& r, const ImageRGB* c = nullptr) {
  double sum = 0.0;
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * a.width + static_cast<std::size_t>(x)) + ch;
        const double ref = c ? 0.5 * (double(b.rgb[i]) + double(c->rgb[i])) : double(b.rgb[i]);
        const double d = double(a.rgb[i]) - ref;
        sum += d * d;
      }
  return sum / (3.0 * (r.x1 - r.x0) * (r.y1 - r.y0));
}

struct Reference {
  ImageRGB a, b;
  // The noise of (a + b) / 2 over each region: E|a - b|^2 / 4.
  double noise_whole = 0.0, noise_region = 0.0;
};

struct Point {
  double seconds = 0.0;
  int passes = 0;
  double mse_whole = 0.0, mse_region = 0.0;  // the reference's noise taken out
};

struct Run {
  std::string integrator;
  std::vector<Point> curve;  // the last point is the end of the render
  double slope_whole = 0.0, slope_region = 0.0;
};

RenderSettings settings_for(const CausticBenchOptions& o, IntegratorKind kind, int spp, std::uint64_t seed) {
  RenderSettings s;
  s.width = s.height = o.size;
  s.spp = spp;
  s.integrator = kind;
  s.max_depth = o.max_depth;
  s.threads = o.threads;
  s.seed = seed;
  s.filter = PixelFilterType::Box;
  return s;
}

Reference make_reference(const CausticBenchOptions& o, const fs::path& file, const Scene& scene,
                         const Accelerator& accel, const PinholeCamera& camera, const Region& whole,
                         const Region& region, std::ostream& err) {
  Reference ref;
  ImageRGB* halves[2] = {&ref.a, &ref.b};
  for (int h = 0; h < 2; ++h) {
    const fs::path path = o.cache / (file.stem().string() + "-" + std::to_string(o.size) + "px-depth" +
                                     std::to_string(o.max_depth) + "-lancer-path-" + std::to_string(o.reference_spp) +
                                     "spp-" + (h == 0 ? "a" : "b") + ".exr");
    if (fs::exists(path)) {
      *halves[h] = read_image(path);
      continue;
    }
    fs::create_directories(o.cache);
    err << "lancer bench --caustics: rendering the reference half " << path.string() << "\n";
    RenderStats stats;
    *halves[h] = render_image(scene, accel, camera,
                              settings_for(o, IntegratorKind::Path, o.reference_spp, kReferenceSeeds[h]), stats);
    write_image(*halves[h], path);
  }
  ref.noise_whole = mse(ref.a, ref.b, whole) / 4.0;
  ref.noise_region = mse(ref.a, ref.b, region) / 4.0;
  return ref;
}

// Least-squares slope of log(error) over log(time), from the second point on (the first
// is still in the start-up transient of both estimators).
double slope(const std::vector<Point>& curve, double Point::*error) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  int n = 0;
  for (std::size_t i = 1; i < curve.size(); ++i) {
    const double e = curve[i].*error;
    if (!(e > 0.0) || !(curve[i].seconds > 0.0)) continue;
    const double x = std::log(curve[i].seconds), y = std::log(e);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
    ++n;
  }
  if (n < 2) return 0.0;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

std::string sci(double v) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(3) << v;
  return s.str();
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

// Error against time on log-log axes, one polyline per integrator and region (whole image
// solid, the region dashed), a plain SVG written by hand.
std::string plot_svg(const std::vector<Run>& runs, const std::string& title) {
  constexpr double kW = 640, kH = 420, kLeft = 70, kRight = 20, kTop = 40, kBottom = 50;
  double t0 = 1e300, t1 = 0, e0 = 1e300, e1 = 0;
  for (const Run& r : runs)
    for (const Point& p : r.curve)
      for (double e : {p.mse_whole, p.mse_region})
        if (e > 0.0 && p.seconds > 0.0) t0 = std::min(t0, p.seconds), t1 = std::max(t1, p.seconds),
                                        e0 = std::min(e0, e), e1 = std::max(e1, e);
  if (!(t1 > t0) || !(e1 > e0)) return {};
  const double lt0 = std::floor(std::log10(t0)), lt1 = std::ceil(std::log10(t1));
  const double le0 = std::floor(std::log10(e0)), le1 = std::ceil(std::log10(e1));
  auto x = [&](double t) { return kLeft + (std::log10(t) - lt0) / (lt1 - lt0) * (kW - kLeft - kRight); };
  auto y = [&](double e) { return kTop + (le1 - std::log10(e)) / (le1 - le0) * (kH - kTop - kBottom); };
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kW << "' height='" << kH
    << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
    << "<text x='" << kW / 2 << "' y='20' text-anchor='middle' font-size='14'>" << title << "</text>\n";
  for (double l = lt0; l <= lt1; ++l)
    s << "<line x1='" << x(std::pow(10, l)) << "' y1='" << kTop << "' x2='" << x(std::pow(10, l)) << "' y2='"
      << kH - kBottom << "' stroke='#ddd'/><text x='" << x(std::pow(10, l)) << "' y='" << kH - kBottom + 16
      << "' text-anchor='middle'>" << std::pow(10, l) << " s</text>\n";
  for (double l = le0; l <= le1; ++l)
    s << "<line x1='" << kLeft << "' y1='" << y(std::pow(10, l)) << "' x2='" << kW - kRight << "' y2='"
      << y(std::pow(10, l)) << "' stroke='#ddd'/><text x='" << kLeft - 6 << "' y='" << y(std::pow(10, l)) + 4
      << "' text-anchor='end'>1e" << int(l) << "</text>\n";
  s << "<text x='" << kW / 2 << "' y='" << kH - 10 << "' text-anchor='middle'>render time</text>\n"
    << "<text x='16' y='" << kH / 2 << "' transform='rotate(-90 16 " << kH / 2
    << ")' text-anchor='middle'>mean squared error</text>\n";
  const char* colours[] = {"#c0392b", "#2471a3", "#27ae60", "#8e44ad"};
  int legend = 0;
  for (std::size_t i = 0; i < runs.size(); ++i)
    for (int region = 0; region < 2; ++region) {
      s << "<polyline fill='none' stroke='" << colours[i % 4] << "' stroke-width='2'"
        << (region ? " stroke-dasharray='6 4'" : "") << " points='";
      for (const Point& p : runs[i].curve) {
        const double e = region ? p.mse_region : p.mse_whole;
        if (e > 0.0 && p.seconds > 0.0) s << x(p.seconds) << "," << y(e) << " ";
      }
      const double slope_value = region ? runs[i].slope_region : runs[i].slope_whole;
      s << "'/>\n<text x='" << kW - kRight - 230 << "' y='" << kTop + 16 + 16 * legend++ << "' fill='"
        << colours[i % 4] << "'>" << runs[i].integrator << (region ? ", caustic region" : ", whole image")
        << " (slope " << fixed(slope_value, 2) << ")</text>\n";
    }
  s << "</svg>\n";
  return s.str();
}

}  // namespace

int run_caustic_bench(const CausticBenchOptions& o, const fs::path& scenes_dir, std::ostream& out, std::ostream& err) {
  const fs::path file = scenes_dir / (o.scene + ".gltf");
  if (!fs::exists(file)) {
    err << "lancer bench --caustics: " << file.string() << " not found\n";
    return 2;
  }
  if (o.region.size() != 4) {
    err << "lancer bench --caustics: --region takes x0,y0,x1,y1\n";
    return 2;
  }
  const double scale = o.size / 256.0;
  Region region{int(o.region[0] * scale), int(o.region[1] * scale), int(o.region[2] * scale), int(o.region[3] * scale)};
  region.x1 = std::min(region.x1, o.size), region.y1 = std::min(region.y1, o.size);
  if (region.x0 < 0 || region.y0 < 0 || region.x1 <= region.x0 || region.y1 <= region.y0) {
    err << "lancer bench --caustics: the region is empty at this size\n";
    return 2;
  }
  for (const std::string& name : o.integrators)
    if (!parse_integrator(name)) {
      err << "lancer bench --caustics: unknown integrator " << name << "\n";
      return 2;
    }
  const Region whole{0, 0, o.size, o.size};
  const Scene scene = load_scene(file);
  const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", scene.triangles, scene.instancing);
  if (scene.cameras.empty()) {
    err << "lancer bench --caustics: " << file.string() << " has no camera\n";
    return 2;
  }
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.front(), o.size, o.size);
  const Reference ref = make_reference(o, file, scene, *accel, camera, whole, region, err);

  std::vector<Run> runs;
  for (const std::string& name : o.integrators) {
    const std::optional<IntegratorKind> kind = parse_integrator(name);
    if (!kind) {
      err << "lancer bench --caustics: unknown integrator " << name << "\n";
      return 2;
    }
    Run run;
    run.integrator = name;
    auto measure = [&](const ImageRGB& image, double seconds, int passes) {
      run.curve.push_back({seconds, passes, mse(image, ref.a, whole, &ref.b) - ref.noise_whole,
                           mse(image, ref.a, region, &ref.b) - ref.noise_region});
    };
    double next = o.seconds * std::ldexp(1.0, -(kCurvePoints - 1));
    const auto start = Clock::now();
    RenderControl control;
    control.time_limit_s = o.seconds;
    control.checkpoint_s = 1e-3;  // after every pass; only the log-spaced ones are measured
    control.on_checkpoint = [&](const ImageRGB& image, int passes) {
      const double t = std::chrono::duration<double>(Clock::now() - start).count();
      if (t < next) return;
      measure(image, t, passes);
      while (next <= t) next *= 2.0;
    };
    RenderStats stats;
    err << "lancer bench --caustics: " << name << " for " << o.seconds << " s\n";
    const ImageRGB image =
        render_image(scene, *accel, camera, settings_for(o, *kind, 1 << 20, kSeed), stats, {}, control);
    // The end of the render, unless the last checkpoint already measured that image.
    if (run.curve.empty() || run.curve.back().passes != stats.passes)
      measure(image, std::chrono::duration<double>(Clock::now() - start).count(), stats.passes);
    run.slope_whole = slope(run.curve, &Point::mse_whole);
    run.slope_region = slope(run.curve, &Point::mse_region);
    runs.push_back(run);
  }

  out << "## " << o.scene << ", " << o.size << "x" << o.size << ", " << o.seconds << " s per integrator, "
      << o.threads << " threads, max depth " << o.max_depth << "\n\n"
      << "Reference: two Lancer path-traced halves of " << o.reference_spp << " spp; their own noise (taken out of "
      << "every error below): " << sci(ref.noise_whole) << " whole image, " << sci(ref.noise_region)
      << " in the region [" << region.x0 << ", " << region.x1 << ") x [" << region.y0 << ", " << region.y1 << ").\n\n"
      << "| integrator | passes | seconds | MSE whole image | MSE region | slope whole | slope region |\n"
      << "|---|--:|--:|--:|--:|--:|--:|\n";
  for (const Run& r : runs) {
    const Point& end = r.curve.back();
    out << "| " << r.integrator << " | " << end.passes << " | " << fixed(end.seconds, 1) << " | "
        << sci(end.mse_whole) << " | " << sci(end.mse_region) << " | " << fixed(r.slope_whole, 2) << " | "
        << fixed(r.slope_region, 2) << " |\n";
  }
  for (std::size_t i = 1; i < runs.size(); ++i)
    if (runs[0].curve.back().mse_whole > 0.0 && runs[0].curve.back().mse_region > 0.0)
      out << (i == 1 ? "\n" : "") << runs[i].integrator << " / " << runs[0].integrator
          << " at equal time: MSE whole image " << fixed(runs[i].curve.back().mse_whole / runs[0].curve.back().mse_whole, 3)
          << "x, region " << fixed(runs[i].curve.back().mse_region / runs[0].curve.back().mse_region, 3) << "x\n";
  out << "\nError against time (log-spaced checkpoints):\n\n| integrator | seconds | passes | MSE whole | MSE region |\n"
      << "|---|--:|--:|--:|--:|\n";
  for (const Run& r : runs)
    for (const Point& p : r.curve)
      out << "| " << r.integrator << " | " << fixed(p.seconds, 2) << " | " << p.passes << " | " << sci(p.mse_whole)
          << " | " << sci(p.mse_region) << " |\n";
  if (!o.plot.empty()) {
    std::ofstream f(o.plot);
    f << plot_svg(runs, o.scene + ", " + std::to_string(o.size) + " px, " + std::to_string(o.threads) +
                            " threads: error against time");
    if (!f) {
      err << "lancer bench --caustics: cannot write " << o.plot << "\n";
      return 1;
    }
  }
  if (!o.json.empty()) {
    nlohmann::json j;
    j["scene"] = o.scene, j["size"] = o.size, j["seconds"] = o.seconds, j["threads"] = o.threads;
    j["max_depth"] = o.max_depth, j["reference_spp_per_half"] = o.reference_spp;
    j["region"] = {region.x0, region.y0, region.x1, region.y1};
    j["reference_noise"] = {{"whole", ref.noise_whole}, {"region", ref.noise_region}};
    for (const Run& r : runs) {
      nlohmann::json jr;
      jr["integrator"] = r.integrator;
      jr["slope_whole"] = r.slope_whole, jr["slope_region"] = r.slope_region;
      for (const Point& p : r.curve)
        jr["curve"].push_back({{"seconds", p.seconds}, {"passes", p.passes}, {"mse_whole", p.mse_whole},
                               {"mse_region", p.mse_region}});
      j["runs"].push_back(jr);
    }
    std::ofstream f(o.json);
    f << j.dump(2) << "\n";
    if (!f) {
      err << "lancer bench --caustics: cannot write " << o.json << "\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace lancer::bench
