#include <CLI/CLI.hpp>
#include <ostream>

#include "caustic_bench.h"

namespace lancer::bench {

std::optional<CausticBenchOptions> parse_caustic_bench_options(int argc, const char* const* argv, std::ostream& out,
                                                               std::ostream& err, int& exit_code) {
  CLI::App app{
      "lancer bench --caustics: photon mapping (sppm) against path tracing at equal time. Each integrator renders "
      "for the same wall time; its mean squared error against a long path-traced reference (two independent "
      "halves, whose own noise is taken out) is measured at log-spaced times, over the whole image and inside a "
      "region (default: the caustic under the glass sphere of cornell-box-spheres). A markdown table on stdout.",
      "lancer bench --caustics"};
  CausticBenchOptions o;
  app.add_option("--scene", o.scene, "A glTF scene of scenes/ (its name without .gltf)")->capture_default_str();
  app.add_option("--size", o.size, "Image side in pixels")->check(CLI::Range(8, 4096))->capture_default_str();
  app.add_option("--seconds", o.seconds, "Render time per integrator")->check(CLI::Range(0.1, 1e6))->capture_default_str();
  app.add_option("--max-depth", o.max_depth, "Bounce limit")->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--threads", o.threads, "Render threads (0: all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  app.add_option("--reference-spp", o.reference_spp, "Samples per pixel of each half of the reference")
      ->check(CLI::Range(1, 1 << 20))->capture_default_str();
  app.add_option("--integrators", o.integrators, "Integrators compared (each later one's error over the first's)")
      ->delimiter(',')->capture_default_str();
  app.add_option("--region", o.region, "x0,y0,x1,y1 in pixels of a 256-pixel image, scaled to --size")
      ->delimiter(',')->expected(4)->capture_default_str();
  app.add_option("--cache", o.cache, "Folder for the reference renders, reused between runs")->capture_default_str();
  app.add_option("--json", o.json, "Also write the results as JSON to this file");
  app.add_option("--plot", o.plot, "Also write the error-against-time curves as an SVG to this file");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    exit_code = 0;
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    err << "lancer bench --caustics: " << e.what() << "\n";
    exit_code = 2;
    return std::nullopt;
  }
  return o;
}

}  // namespace lancer::bench
