// lancer-spd-scaling: which SPD sizes stand for each decade, one real (tiny) measurement,
// the skip and failure paths, the markdown table, the log-log SVG and the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scaling_measure.h"
#include "scaling_options.h"
#include "simd/isa.h"
#include "scaling_points.h"
#include "scaling_report.h"
#include "scene/spd.h"

namespace lancer::bench {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

const std::vector<std::string> kAll{"balls", "gears", "mount", "rings", "tetra"};

std::vector<std::string> names(const std::vector<ScalingPoint>& points) {
  std::vector<std::string> out;
  for (const ScalingPoint& p : points) out.push_back(p.name());
  return out;
}

TEST(SpdScalingPoints, DefaultCapGivesTheNearestSizePerDecade) {
  // Counts from spd.h's formulas, worked out by hand: balls steps 9x, so its 10^7 point
  // (21 million) is over the cap and 2.4 million is more than half a decade from 10^7.
  const std::vector<ScalingPoint> p = choose_scaling_points(kAll, 4, 7, 12'000'000);
  EXPECT_EQ(names(p), (std::vector<std::string>{"balls-2", "balls-3", "balls-4", "gears-3", "gears-6", "gears-12",
                                                "gears-26", "mount-6", "mount-8", "mount-9", "mount-11", "rings-1",
                                                "rings-3", "rings-6", "rings-13", "tetra-7", "tetra-8", "tetra-10",
                                                "tetra-11"}));
  for (const ScalingPoint& q : p) EXPECT_EQ(q.triangles, spd_triangle_count(q.spd, q.size)) << q.name();
  EXPECT_EQ(p[6].triangles, 576u * 26 * 26 * 26 + 2);
}

TEST(SpdScalingPoints, EveryPointIsTheNearestUnderTheCapWithinHalfADecade) {
  for (std::uint64_t cap : {std::uint64_t{20'000}, std::uint64_t{3'000'000}, std::uint64_t{50'000'000}}) {
    const std::vector<ScalingPoint> p = choose_scaling_points(kAll, 4, 7, cap);
    for (const ScalingPoint& q : p) {
      ASSERT_LE(q.triangles, cap) << q.name();
      const double l = std::log10(static_cast<double>(q.triangles));
      const int decade = static_cast<int>(std::lround(l));
      ASSERT_LE(std::fabs(l - decade), kMaxDecadeDistance) << q.name();
      // No other size under the cap is nearer that decade.
      const SpdSizeRange range = spd_size_range(q.spd);
      for (int s = range.min; s <= range.max; ++s) {
        const std::uint64_t n = spd_triangle_count(q.spd, s);
        if (n > cap) break;
        EXPECT_GE(std::fabs(std::log10(static_cast<double>(n)) - decade), std::fabs(l - decade) - 1e-12)
            << q.name() << " against size " << s << " (cap " << cap << ")";
      }
    }
    // Sorted by generator in the given order, then by count, no duplicates.
    for (std::size_t i = 1; i < p.size(); ++i)
      if (p[i].spd == p[i - 1].spd) {
        EXPECT_LT(p[i - 1].triangles, p[i].triangles);
      }
  }
  // A small cap leaves only the small decades.
  EXPECT_EQ(names(choose_scaling_points({"tetra"}, 4, 7, 20'000)), (std::vector<std::string>{"tetra-7"}));
  EXPECT_EQ(names(choose_scaling_points({"tetra", "gears"}, 5, 5, 50'000'000)),
            (std::vector<std::string>{"tetra-8", "gears-6"}));
}

TEST(SpdScalingPoints, UnknownGeneratorAndBackwardDecadesThrow) {
  EXPECT_THROW(choose_scaling_points({"teapot"}, 4, 7, 1000), std::invalid_argument);
  EXPECT_THROW(choose_scaling_points({"balls"}, 6, 5, 1000), std::invalid_argument);
}

TEST(SpdScalingMeasure, TinyTetraIsMeasuredAndChecked) {
  ScalingSettings settings;
  settings.image = 32;
  settings.reps = 3;
  settings.peak_program = LANCER_SPD_SCALING_BINARY;
  std::ostringstream log;
  const ScalingResult r = measure_scaling_point({"tetra", 4, 256}, settings, -1, log);
  ASSERT_TRUE(r.failure.empty()) << r.failure;
  EXPECT_FALSE(r.skipped);
  EXPECT_EQ(r.build_runs, 3);
  EXPECT_GT(r.build_ms, 0.0);
  EXPECT_GT(r.accel_bytes, 256u * 9 * sizeof(float)) << "the tree holds at least the triangles";
  EXPECT_DOUBLE_EQ(r.bytes_per_triangle(), static_cast<double>(r.accel_bytes) / 256.0);
  // Measured in a child process (256 triangles may fit in what the warm-up left resident).
  EXPECT_GE(r.peak_load_build_bytes, 0);
  EXPECT_EQ(r.rays, 32u * 32u);
  EXPECT_GT(r.hits, r.rays / 10) << "the SPD view looks at the tetrahedra";
  EXPECT_LT(r.hits, r.rays);
  for (const RateSummary& s : {r.packet, r.single}) {
    EXPECT_GT(s.min, 0.0);
    EXPECT_LE(s.min, s.median);
    EXPECT_LE(s.median, s.max);
  }
  EXPECT_GE(r.passes, 1);
  EXPECT_NE(log.str().find("[done] tetra-4"), std::string::npos) << log.str();
}

// Issue 15's memory bound on a quarter-million-triangle scene: the peak of generating it
// and building its tree, above a process that has built a tree before, in a child.
// The smallest points of the series (one-thread lean builds) and two mid-sized ones built
// on every thread; rings-1, mount-6 and rings-3 were over the bound before the lean build
// and before release_free_memory worked.
TEST(SpdScalingMeasure, PeakOfGenerationAndBuildIsWithinTheBound) {
  std::string error;
  int measured = 0;
  // The trees of the AVX2 and AVX-512 kernels differ (block width, leaf sizes): each ISA
  // this CPU runs.
  for (Isa isa : {Isa::Avx2, Isa::Avx512}) {
    if (!cpu_supports(isa)) {
      std::cout << "[ SKIPPED  ] " << isa_name(isa) << ": this CPU lacks it\n";
      continue;
    }
    for (const ScalingPoint& point : {ScalingPoint{"rings", 1, 11'522}, ScalingPoint{"mount", 6, 9'472},
                                      ScalingPoint{"rings", 3, 161'282}, ScalingPoint{"balls", 3, 262'402}}) {
      const std::int64_t peak = measure_peak_in_child(LANCER_SPD_SCALING_BINARY, point, isa, error);
      ASSERT_GT(peak, 0) << error;
      EXPECT_LE(static_cast<double>(peak) / static_cast<double>(point.triangles), kPeakBoundBytesPerTriangle)
          << point.name() << ", " << isa_name(isa) << ": " << peak << " bytes at the peak";
      ++measured;
    }
  }
  if (measured == 0) GTEST_SKIP() << "this CPU runs neither AVX2 nor AVX-512";
  EXPECT_LT(measure_peak_in_child("", ScalingPoint{"balls", 3, 262'402}, best_supported_isa(), error), 0);
  EXPECT_NE(error.find("no program"), std::string::npos) << error;
}

TEST(SpdScalingMeasure, TooLittleMemoryIsASkipNotAnAttempt) {
  std::ostringstream log;
  // 300 bytes per triangle: 3.04e9 bytes, 2.8 GiB.
  const ScalingResult r = measure_scaling_point({"gears", 26, 10'123'778}, {}, 1'000'000'000, log);
  EXPECT_TRUE(r.skipped);
  EXPECT_NE(r.failure.find("skipped: needs about 2.8 GiB, 0.9 GiB available"), std::string::npos) << r.failure;
  EXPECT_EQ(r.build_runs, 0);
  EXPECT_NE(log.str().find("[skip] gears-26"), std::string::npos);
  // Enough memory: no skip (a point that fails for another reason shows it is attempted).
  EXPECT_FALSE(measure_scaling_point({"tetra", 2, 17}, {}, 1'000'000'000, log).skipped);
}

TEST(SpdScalingMeasure, FailuresAreRecordedNotThrown) {
  ScalingSettings settings;
  settings.image = 12;  // not a multiple of 8: primary_rays refuses it
  std::ostringstream log;
  const ScalingResult r = measure_scaling_point({"tetra", 2, 16}, settings, -1, log);
  EXPECT_FALSE(r.skipped);
  EXPECT_FALSE(r.failure.empty());
  EXPECT_NE(log.str().find("[FAILED] tetra-2"), std::string::npos) << log.str();
  // A point whose stated count is not what the generator makes is refused too.
  const ScalingResult wrong = measure_scaling_point({"tetra", 2, 17}, {}, -1, log);
  EXPECT_NE(wrong.failure.find("generated 16 triangles, spd_triangle_count says 17"), std::string::npos)
      << wrong.failure;
}

TEST(SpdScalingMeasure, AvailableMemoryIsRead) {
  const std::int64_t bytes = available_memory_bytes();
  if (bytes < 0) GTEST_SKIP() << "no /proc/meminfo here";
  EXPECT_GT(bytes, 16 << 20);
}

ScalingResult made(const char* spd, int size, std::uint64_t triangles, double build_ms, double mrays) {
  ScalingResult r;
  r.point = {spd, size, triangles};
  r.build_ms = build_ms;
  r.build_runs = 1;
  r.accel_bytes = static_cast<std::size_t>(triangles) * 100;
  r.peak_load_build_bytes = static_cast<std::int64_t>(triangles) * 150;
  r.packet = {mrays, mrays * 0.9, mrays * 1.1};
  r.single = {mrays / 4, mrays / 4, mrays / 4};
  return r;
}

std::vector<ScalingResult> sample_results() {
  std::vector<ScalingResult> v{made("tetra", 7, 10'000, 5, 40), made("tetra", 8, 100'000, 60, 30),
                               made("tetra", 10, 1'000'000, 700, 20), made("gears", 3, 10'000, 6, 30),
                               made("gears", 6, 100'000, 70, 25)};
  ScalingResult skipped = made("gears", 26, 10'123'778, 0, 0);
  skipped.skipped = true;
  skipped.failure = "skipped: needs about 5.7 GiB, 2.0 GiB available";
  v.push_back(skipped);
  return v;
}

TEST(SpdScalingReport, MarkdownRowPerPointWithReasonsForTheMissingOnes) {
  std::ostringstream o;
  write_scaling_markdown(sample_results(), ScalingSettings{}, o);
  const std::string md = o.str();
  EXPECT_EQ(count(md, "\n| "), 7u) << md;  // header and six rows
  EXPECT_NE(md.find("| tetra-8 | 100,000 | 0.00 | 0.060 | 9.5 | 100.0 | 14.3 | 150.0 | 30.00 (27.00-33.00) | "
                    "7.50 (7.50-7.50) | 4.00x |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| gears-26 | 10,123,778 | skipped: needs about 5.7 GiB, 2.0 GiB available |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("512 x 512, one thread"), std::string::npos) << md;
  EXPECT_NE(md.find("per CPU second of the tracing thread"), std::string::npos) << md;
}

TEST(SpdScalingReport, LogAxisCoversTheValuesInWholeDecades) {
  EXPECT_EQ(log_axis({15, 900}).lo, 1);
  EXPECT_EQ(log_axis({15, 900}).hi, 3);
  EXPECT_EQ(log_axis({10, 100}).lo, 1);
  EXPECT_EQ(log_axis({10, 100}).hi, 2);
  EXPECT_EQ(log_axis({0.05, 0.2}).lo, -2);
  EXPECT_EQ(log_axis({0.05, 0.2}).hi, 0);
  EXPECT_EQ(log_axis({5}).lo, 0);
  EXPECT_EQ(log_axis({5}).hi, 1);
  EXPECT_EQ(log_axis({1000}).hi, 4) << "a single decade value still gets an axis of one decade";
  const LogAxis ignored = log_axis({0.0, -3.0, std::numeric_limits<double>::quiet_NaN(), 30.0});
  EXPECT_EQ(ignored.lo, 1);
  EXPECT_EQ(ignored.hi, 2);
}

std::vector<double> attribute_values(const std::string& svg, const std::string& element, const std::string& attr) {
  std::vector<double> out;
  const std::regex re("<" + element + "[^>]* " + attr + "=\"([-0-9.]+)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back(std::stod((*it)[1]));
  return out;
}

TEST(SpdScalingReport, SvgHasThreeLogLogPanelsWithASeriesPerGenerator) {
  const std::string svg = scaling_svg(sample_results(), ScalingSettings{});
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // Two generators with two or more measured points: build, kd-tree memory, peak memory,
  // packet and single.
  EXPECT_EQ(count(svg, "<polyline class=\"series\""), 2u * 5);
  EXPECT_EQ(count(svg, "stroke-dasharray"), 4u) << "single-ray and peak-memory series are dashed";
  // Five measured points, each drawn as build, kd-tree memory, peak memory, packet, single.
  EXPECT_EQ(count(svg, "<circle class=\"point\""), 5u * 5);
  EXPECT_NE(svg.find("not measured: gears-26 (10,123,778): skipped"), std::string::npos);
  for (const char* title : {"kd-tree build, 1 thread", "memory per triangle", "primary rays, 1 thread"})
    EXPECT_NE(svg.find(title), std::string::npos) << title;
  EXPECT_NE(svg.find("10⁴"), std::string::npos);
  EXPECT_NE(svg.find("10⁶"), std::string::npos);

  // Log x: in the first panel, tetra's 10^4, 10^5 and 10^6 points are equally spaced,
  // and gears' points share their x. The kd-tree holds 100 bytes per triangle at every
  // size and the peak 150: two flat lines in the second panel, the peak above.
  const std::vector<double> cx = attribute_values(svg, "circle", "cx"), cy = attribute_values(svg, "circle", "cy");
  ASSERT_EQ(cx.size(), 25u);
  ASSERT_EQ(cy.size(), 25u);
  EXPECT_NEAR(cx[1] - cx[0], cx[2] - cx[1], 0.11);
  EXPECT_GT(cx[1] - cx[0], 20.0);
  EXPECT_NEAR(cx[3], cx[0], 0.01);  // gears-3 and tetra-7: both 10^4 triangles
  EXPECT_NEAR(cx[4], cx[1], 0.01);
  EXPECT_NEAR(cy[6], cy[5], 0.01);  // memory panel, kd-tree, tetra
  EXPECT_NEAR(cy[7], cy[5], 0.01);
  EXPECT_LT(cy[10], cy[5]) << "the peak (150) is drawn above the kd-tree (100)";
  EXPECT_LT(cy[15], cy[16]) << "larger values are drawn higher (packet rates 40 and 30)";
  EXPECT_GT(cx[5], cx[2]) << "the second panel is to the right of the first";
  // The escaping of the left-out line.
  const std::string escaped = scaling_svg({made("tetra", 7, 10'000, 5, 40), [] {
                                             ScalingResult r = made("tetra", 8, 100'000, 0, 0);
                                             r.failure = "a<b & c";
                                             return r;
                                           }()},
                                          ScalingSettings{});
  EXPECT_NE(escaped.find("a&lt;b &amp; c"), std::string::npos);
}

struct Parsed {
  std::optional<ScalingOptions> options;
  int code = -1;
  std::string out, err;
};

Parsed parse(std::vector<const char*> args) {
  args.insert(args.begin(), "lancer-spd-scaling");
  std::ostringstream out, err;
  Parsed p;
  p.options = parse_scaling_options(static_cast<int>(args.size()), args.data(), out, err, p.code);
  p.out = out.str();
  p.err = err.str();
  return p;
}

TEST(SpdScalingOptions, DefaultsAndValues) {
  const Parsed d = parse({});
  ASSERT_TRUE(d.options);
  EXPECT_EQ(d.options->generators, kAll);
  EXPECT_EQ(d.options->first_decade, 4);
  EXPECT_EQ(d.options->last_decade, 7);
  EXPECT_EQ(d.options->max_triangles, kDefaultScalingMaxTriangles);
  EXPECT_EQ(d.options->settings.image, 512);
  EXPECT_EQ(d.options->settings.isa, best_supported_isa());

  const Parsed p = parse({"--generators", "tetra,gears", "--decades=5-6", "--max-triangles", "2000000", "--image",
                          "64", "--reps", "2", "--isa", "scalar", "--markdown", "t.md", "--plot", "p.svg", "--list"});
  ASSERT_TRUE(p.options) << p.err;
  EXPECT_EQ(p.options->generators, (std::vector<std::string>{"tetra", "gears"}));
  EXPECT_EQ(p.options->first_decade, 5);
  EXPECT_EQ(p.options->last_decade, 6);
  EXPECT_EQ(p.options->max_triangles, 2'000'000u);
  EXPECT_EQ(p.options->settings.image, 64);
  EXPECT_EQ(p.options->settings.reps, 2);
  EXPECT_EQ(p.options->settings.isa, Isa::Scalar);
  EXPECT_EQ(p.options->markdown, "t.md");
  EXPECT_EQ(p.options->plot, "p.svg");
  EXPECT_TRUE(p.options->list);

  const Parsed help = parse({"--help"});
  EXPECT_FALSE(help.options);
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--max-triangles N"), std::string::npos);
}

TEST(SpdScalingOptions, BadValuesExitTwoNamingTheOption) {
  const struct {
    std::vector<const char*> args;
    const char* message;
  } cases[] = {
      {{"--generators", "balls,teapot"}, "--generators: unknown SPD generator 'teapot'"},
      {{"--generators", "balls,"}, "--generators: unknown SPD generator ''"},
      {{"--decades", "7-4"}, "--decades: 7-4 runs backwards"},
      {{"--decades", "4"}, "--decades: '4' is not of the form A-B"},
      {{"--decades", "0-4"}, "--decades: 0 is outside 1..8"},
      {{"--max-triangles", "-5"}, "--max-triangles: '-5' is not a whole number"},
      {{"--max-triangles", "60000000"}, "--max-triangles: 60000000 is outside 1..50000000"},
      {{"--image", "100"}, "--image: 100 is not a multiple of 8"},
      {{"--image", "12x"}, "--image: '12x' is not a whole number"},
      {{"--reps", "0"}, "--reps: 0 is outside 1..100"},
      {{"--isa", "neon"}, "--isa: unknown ISA 'neon'"},
      {{"--reps"}, "--reps: missing value"},
      {{"--plot="}, "--plot: empty value"},
      {{"--frobnicate"}, "unknown option '--frobnicate'"},
      {{"tetra"}, "unexpected argument 'tetra'"},
  };
  for (const auto& c : cases) {
    const Parsed p = parse(c.args);
    EXPECT_FALSE(p.options) << c.message;
    EXPECT_EQ(p.code, 2) << c.message;
    EXPECT_NE(p.err.find(std::string("lancer-spd-scaling: ") + c.message), std::string::npos) << p.err;
  }
}

}  // namespace
}  // namespace lancer::bench
