#include "scaling_options.h"

#include <charconv>
#include <ostream>
#include <stdexcept>
#include <string_view>

#include "scene/spd.h"

namespace lancer::bench {

namespace {

constexpr const char* kHelp = R"(lancer-spd-scaling: how Lancer's kd-tree grows with the scene, on Haines' SPD scenes

For each SPD generator and each decade from 10^4 to 10^7 triangles, the size nearest the
decade (default tessellation): kd-tree build time (one thread), kd-tree bytes, and primary
Mrays/s (the SPD view, one thread, packet and single-ray). Prints a markdown table.

Options:
  --generators LIST    comma-separated: balls, gears, mount, rings, tetra (default: all)
  --decades A-B        decades of triangle counts, 1..8 (default: 4-7)
  --max-triangles N    leave out sizes above N triangles (default: 12000000)
  --image N            image side in pixels, a multiple of 8 up to 4096 (default: 512)
  --reps N             timed runs per mode, 1..100 (default: 5)
  --isa NAME           scalar, sse4, avx2 or avx512 (default: the best this CPU runs)
  --markdown FILE      also write the table to FILE
  --plot FILE          write the log-log SVG plot to FILE
  --list               print the chosen scenes and exit
  -h, --help           this text

Exit status: 0 done, 1 a point failed (out of memory, a check), 2 bad options.
)";

struct BadOption : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

std::uint64_t parse_count(std::string_view option, std::string_view text, std::uint64_t lo, std::uint64_t hi) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    throw BadOption(std::string(option) + ": '" + std::string(text) + "' is not a whole number");
  if (v < lo || v > hi)
    throw BadOption(std::string(option) + ": " + std::string(text) + " is outside " + std::to_string(lo) + ".." +
                    std::to_string(hi));
  return v;
}

std::vector<std::string> split_commas(std::string_view text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    parts.emplace_back(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return parts;
}

void parse_generators(std::string_view text, ScalingOptions& o) {
  o.generators.clear();
  for (const std::string& g : split_commas(text)) {
    bool known = false;
    for (std::string_view name : spd_names()) known = known || name == g;
    if (!known)
      throw BadOption("--generators: unknown SPD generator '" + g + "' (known: balls, gears, mount, rings, tetra)");
    o.generators.push_back(g);
  }
}

void parse_decades(std::string_view text, ScalingOptions& o) {
  const std::size_t dash = text.find('-');
  if (dash == std::string_view::npos) throw BadOption("--decades: '" + std::string(text) + "' is not of the form A-B");
  o.first_decade = static_cast<int>(parse_count("--decades", text.substr(0, dash), 1, 8));
  o.last_decade = static_cast<int>(parse_count("--decades", text.substr(dash + 1), 1, 8));
  if (o.first_decade > o.last_decade) throw BadOption("--decades: " + std::string(text) + " runs backwards");
}

bool known_option(std::string_view option) {
  for (std::string_view known :
       {"--generators", "--decades", "--max-triangles", "--image", "--reps", "--isa", "--markdown", "--plot"})
    if (option == known) return true;
  return false;
}

void apply(std::string_view option, std::string_view value, ScalingOptions& o) {
  if (option == "--generators") {
    parse_generators(value, o);
  } else if (option == "--decades") {
    parse_decades(value, o);
  } else if (option == "--max-triangles") {
    o.max_triangles = parse_count(option, value, 1, kSpdMaxTriangles);
  } else if (option == "--image") {
    o.settings.image = static_cast<int>(parse_count(option, value, 8, 4096));
    if (o.settings.image % 8 != 0) throw BadOption("--image: " + std::string(value) + " is not a multiple of 8");
  } else if (option == "--reps") {
    o.settings.reps = static_cast<int>(parse_count(option, value, 1, 100));
  } else if (option == "--isa") {
    const std::optional<Isa> isa = parse_isa(value);
    if (!isa) throw BadOption("--isa: unknown ISA '" + std::string(value) + "' (scalar, sse4, avx2, avx512)");
    if (!cpu_supports(*isa)) throw BadOption("--isa: this CPU does not run " + std::string(value));
    o.settings.isa = *isa;
  } else if (option == "--markdown") {
    o.markdown = value;
  } else if (option == "--plot") {
    o.plot = value;
  } else {
    throw BadOption("unknown option '" + std::string(option) + "' (see --help)");
  }
}

}  // namespace

std::optional<ScalingOptions> parse_scaling_options(int argc, const char* const* argv, std::ostream& out,
                                                    std::ostream& err, int& exit_code) {
  ScalingOptions o;
  try {
    for (int i = 1; i < argc; ++i) {
      std::string_view arg = argv[i];
      if (arg == "-h" || arg == "--help") {
        out << kHelp;
        exit_code = 0;
        return std::nullopt;
      }
      if (arg == "--list") {
        o.list = true;
        continue;
      }
      if (arg.substr(0, 2) != "--") throw BadOption("unexpected argument '" + std::string(arg) + "' (see --help)");
      std::string_view option = arg, value;
      if (const std::size_t eq = arg.find('='); eq != std::string_view::npos) {
        option = arg.substr(0, eq);
        value = arg.substr(eq + 1);
      }
      if (!known_option(option)) throw BadOption("unknown option '" + std::string(option) + "' (see --help)");
      if (option == arg) {
        if (i + 1 >= argc) throw BadOption(std::string(arg) + ": missing value");
        value = argv[++i];
      }
      if (value.empty()) throw BadOption(std::string(option) + ": empty value");
      apply(option, value, o);
    }
  } catch (const BadOption& e) {
    err << "lancer-spd-scaling: " << e.what() << "\n";
    exit_code = 2;
    return std::nullopt;
  }
  return o;
}

}  // namespace lancer::bench
