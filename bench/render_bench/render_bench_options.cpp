#include <CLI/CLI.hpp>
#include <ostream>

#include "render_bench.h"

namespace lancer::bench {

std::vector<std::string> render_suite_names() {
  return {"cornell-box", "cornell-box-spheres", "still-life", "cornell-box-dof", "balls-3", "stanford-bunny"};
}

std::optional<RenderBenchOptions> parse_render_bench_options(int argc, const char* const* argv, std::ostream& out,
                                                             std::ostream& err, int& exit_code) {
  CLI::App app{
      "lancer bench --render: the path tracer's speed on whole renders. Per scene: paths/s, Mrays/s and the share "
      "of CPU time spent in ray traversal (the render's tracer calls recorded, then replayed alone and timed); "
      "with Blender's Cycles (when `blender` is found), each renderer's mean squared error against a long "
      "reference render and the speed at equal error, 1 / (MSE x seconds), Lancer / Cycles. A markdown table on "
      "stdout, progress on stderr.",
      "lancer bench --render"};
  RenderBenchOptions o;
  std::string names;
  for (const std::string& n : render_suite_names()) names += (names.empty() ? "" : ", ") + n;
  app.add_option("--scenes", o.scenes, "Scenes to render (default: " + names + ")")->delimiter(',');
  app.add_option("--size", o.size, "Image side in pixels")->check(CLI::Range(8, 4096))->capture_default_str();
  app.add_option("--spp", o.spp, "Samples per pixel")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  app.add_option("--max-depth", o.max_depth, "Bounce limit: Lancer's --max-depth, Cycles' max_bounces + 1")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--light-samples", o.light_samples, "Area-light samples per bounce (lancer render --light-samples)")
      ->check(CLI::Range(1, 4096))->capture_default_str();
  app.add_option("--threads", o.threads, "Render threads (0: all cores; both renderers)")
      ->check(CLI::Range(0, 4096))->capture_default_str();
  app.add_option("--reps", o.reps, "Timed renders per scene (the median is reported)")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  app.add_option("--trace-passes", o.trace_passes, "Passes recorded and replayed for the traversal share")
      ->check(CLI::Range(1, 1 << 16))->capture_default_str();
  std::string cycles = "auto";
  app.add_option("--cycles", cycles, "Render with Blender's Cycles beside Lancer: auto (when blender is found), on, off")
      ->check(CLI::IsMember({"auto", "on", "off"}))->capture_default_str();
  std::string reference = "cycles";
  app.add_option("--reference", reference,
                 "Which renderer makes the long reference the errors are measured against")
      ->check(CLI::IsMember({"cycles", "lancer"}))->capture_default_str();
  app.add_option("--reference-spp", o.reference_spp, "Samples per pixel of the reference render")
      ->check(CLI::Range(1, 1 << 20))->capture_default_str();
  app.add_option("--cache", o.cache, "Folder for the reference renders, reused between runs")->capture_default_str();
  app.add_option("--blender", o.blender, "The Blender program")->capture_default_str();
  app.add_option("--json", o.json, "Also write the results as JSON to this file");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    exit_code = 0;
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    err << "lancer bench --render: " << e.what() << "\n";
    exit_code = 2;
    return std::nullopt;
  }
  o.cycles = cycles == "on" ? CyclesUse::On : cycles == "off" ? CyclesUse::Off : CyclesUse::Auto;
  o.reference = reference == "lancer" ? ReferenceFrom::Lancer : ReferenceFrom::Cycles;
  return o;
}

}  // namespace lancer::bench
