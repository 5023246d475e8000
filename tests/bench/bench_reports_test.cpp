// lancer-bench's reports from a hand-made run: markdown rows and Lancer / Embree ratios,
// JSON holding every repetition, and an SVG with one <rect> per bar.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "report_json.h"
#include "report_markdown.h"
#include "report_svg.h"

namespace lancer::bench {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

ModeTiming timing(Mode mode, std::vector<double> seconds) {
  ModeTiming t;
  t.mode = mode;
  t.call = std::string(mode_name(mode)) + " call";
  t.seconds = std::move(seconds);
  return t;
}

// Two scenes with primary rows on 1 and 2 threads; the second scene's 2-thread row failed.
BenchRun sample_run() {
  BenchRun run;
  run.options.modes = {Mode::Packet, Mode::Single, Mode::Embree};
  run.options.sets = {RaySet::Primary};
  run.options.isas = {Isa::Avx2};
  run.options.reps = 3;
  run.options.size = 64;
  run.threads = {1, 2};
  run.hardware_threads = 2;
  run.embree = "Embree test";
  for (const char* name : {"a&b", "c"}) {
    SceneResult s;
    s.name = name;
    s.origin = "spd";
    s.triangles = 1000;
    IsaBuild b;
    b.isa = Isa::Avx2;
    b.lancer_ms = {{1, 20.0}, {2, 12.0}};
    b.embree_ms = {{1, 10.0}, {2, 8.0}};
    b.lancer_bytes = 50000;
    b.embree_bytes = 100000;
    s.builds.push_back(b);
    SetCheck c;
    c.set = RaySet::Primary;
    c.isa = Isa::Avx2;
    c.rays = 1000000;
    c.work_counted = std::string(name) == "a&b";  // scene c: counts missing
    c.work = {12.25, 3.0, 40.5};
    s.checks.push_back(c);
    for (int threads : {1, 2}) {
      Row r;
      r.set = RaySet::Primary;
      r.isa = Isa::Avx2;
      r.threads = threads;
      r.rays = 1000000;
      // Packet 2 Mrays/s (median), single 0.4, embree 4: ratios 0.50 and 0.10.
      r.modes = {timing(Mode::Packet, {0.5, 0.4, 0.6}), timing(Mode::Single, {2.5, 2.5, 2.5}),
                 timing(Mode::Embree, {0.25, 0.25, 0.2})};
      if (std::string(name) == "c" && threads == 2) {
        r.modes.clear();
        r.failure = "Lancer and Embree disagree";
      }
      s.rows.push_back(r);
    }
    run.scenes.push_back(s);
  }
  return run;
}

TEST(BenchReports, MarkdownHasARowPerSceneSetIsaThreadsWithRatios) {
  std::ostringstream out;
  write_markdown(sample_run(), out);
  const std::string md = out.str();
  EXPECT_NE(md.find("| scene | set | rays | isa | threads | packet | single | embree | embree call | packet / embree | "
                    "single / embree | single-ray work per ray: steps / leaves / tests |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| a&b | primary | 1000000 | avx2 | 1 | 2.00 [1.67-2.50] | 0.40 [0.40-0.40] | 4.00 [4.00-5.00] | "
                    "embree call | 0.50 | 0.10 | 12.2 / 3.0 / 40.5 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| c | primary | 1000000 | avx2 | 1 | 2.00 [1.67-2.50] | 0.40 [0.40-0.40] | 4.00 [4.00-5.00] | "
                    "embree call | 0.50 | 0.10 | n/a |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| c | primary | 1000000 | avx2 | 2 | failed | failed | failed | | | | |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("- c primary avx2 2 threads: Lancer and Embree disagree"), std::string::npos) << md;
  // Scenes: build 12 / 8 ms at 2 threads (1.50), 50 and 100 bytes per triangle (0.50).
  EXPECT_NE(md.find("| 20.0 / 12.0 | 10.0 / 8.0 | 1.50 | 50.0 | 100.0 | 0.50 |"), std::string::npos) << md;
}

TEST(BenchReports, JsonHoldsEveryRepetition) {
  const nlohmann::json j = nlohmann::json::parse(run_to_json(sample_run()));
  ASSERT_EQ(j.at("scenes").size(), 2u);
  const nlohmann::json& row = j.at("scenes")[0].at("rows")[0];
  EXPECT_EQ(row.at("modes").at("packet").at("seconds_per_pass"), (std::vector<double>{0.5, 0.4, 0.6}));
  EXPECT_DOUBLE_EQ(row.at("modes").at("embree").at("mrays_median").get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(row.at("modes").at("embree").at("mrays_max").get<double>(), 5.0);
  EXPECT_EQ(j.at("scenes")[1].at("rows")[1].at("failure"), "Lancer and Embree disagree");
  EXPECT_EQ(j.at("scenes")[0].at("builds")[0].at("embree_bytes"), 100000);
  EXPECT_EQ(j.at("scenes")[0].at("name"), "a&b");
  const auto& work = j.at("scenes")[0].at("checks")[0].at("single_work_per_ray");
  EXPECT_DOUBLE_EQ(work.at("inner_steps").get<double>(), 12.25);
  EXPECT_DOUBLE_EQ(work.at("leaves").get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(work.at("triangle_tests").get<double>(), 40.5);
  EXPECT_FALSE(j.at("scenes")[1].at("checks")[0].contains("single_work_per_ray"));
}

TEST(BenchReports, SvgHasOneRectPerBarAndNamesTheSelection) {
  const BenchRun run = sample_run();
  const PlotSelection sel = default_plot_selection(run);
  EXPECT_EQ(sel.threads, 2);
  EXPECT_EQ(sel.set, RaySet::Primary);
  std::string svg = plot_svg(run, sel);
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  EXPECT_EQ(count(svg, "<rect"), 3u);  // scene c failed on 2 threads: a label, no bars
  EXPECT_EQ(count(svg, ">failed</text>"), 1u);
  EXPECT_NE(svg.find("primary rays, 2 threads, avx2"), std::string::npos);
  EXPECT_NE(svg.find("a&amp;b"), std::string::npos);  // names are escaped
  EXPECT_EQ(svg.find("a&b"), std::string::npos);
  for (const char* legend : {">packet</text>", ">single</text>", ">embree</text>"})
    EXPECT_NE(svg.find(legend), std::string::npos) << legend;

  svg = plot_svg(run, PlotSelection{RaySet::Primary, Isa::Avx2, 1});
  EXPECT_EQ(count(svg, "<rect"), 6u);
  EXPECT_EQ(count(svg, "<svg"), 1u);
  EXPECT_EQ(count(svg, "</svg>"), 1u);
}

}  // namespace
}  // namespace lancer::bench
