#include "render/checkpoint_file.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string_view>

#include "render/content_hash.h"
#include "render/image_io.h"

namespace lancer {
namespace {

constexpr std::string_view kPrefix = "lancer.";
constexpr std::array<const char*, 3> kRgb = {"R", "G", "B"};
// The names that are not facts: the format, the passes, the digest.
constexpr std::array<std::string_view, 6> kReserved = {"resume",     "passes",     "digest",
                                                       "lightPasses", "lightPaths", "lightPending"};

// The channels of per-pixel double sums `what` ("sum", "light", "pending"): channel c's high
// and low 32 bits, lancer.<what>Hi.<c> and lancer.<what>Lo.<c>.
std::string hi_name(const char* what, int c) {
  return std::string(kPrefix) + what + "Hi." + kRgb[static_cast<std::size_t>(c)];
}
std::string lo_name(const char* what, int c) {
  return std::string(kPrefix) + what + "Lo." + kRgb[static_cast<std::size_t>(c)];
}

// Each double of `sums` as its high and low 32 bits, exact.
void add_double_channels(const std::vector<glm::dvec3>& sums, const char* what, ExrExtras& extras) {
  for (int c = 0; c < 3; ++c) {
    std::vector<std::uint32_t> hi(sums.size()), lo(sums.size());
    for (std::size_t p = 0; p < sums.size(); ++p) {
      std::uint64_t bits;
      std::memcpy(&bits, &sums[p][c], sizeof bits);
      hi[p] = static_cast<std::uint32_t>(bits >> 32);
      lo[p] = static_cast<std::uint32_t>(bits);
    }
    extras.uint_channels.emplace_back(hi_name(what, c), std::move(hi));
    extras.uint_channels.emplace_back(lo_name(what, c), std::move(lo));
  }
}

// Whether the state holds the light tracer's sums (the file then has their channels).
bool has_light(const RenderState& state) { return state.light_passes > 0 || !state.pending.empty(); }
std::string count_name() { return std::string(kPrefix) + "count"; }

CheckpointFacts sorted(CheckpointFacts facts) {
  std::sort(facts.begin(), facts.end());
  return facts;
}

// Everything the file says about the render, in one hash: a change anywhere shows.
std::string digest(const RenderState& state, const CheckpointFacts& sorted_facts) {
  ContentHash h;
  h.add_u64(static_cast<std::uint64_t>(kCheckpointFormat));
  h.add_u64(static_cast<std::uint64_t>(state.passes));
  h.add_u64(static_cast<std::uint64_t>(state.width));
  h.add_u64(static_cast<std::uint64_t>(state.height));
  for (const auto& [key, value] : sorted_facts) {
    h.add(key);
    h.add(value);
  }
  h.add(state.count.data(), state.count.size() * sizeof(std::uint32_t));
  h.add(state.sum.data(), state.sum.size() * sizeof(glm::dvec3));
  if (has_light(state)) {
    h.add_u64(static_cast<std::uint64_t>(state.light_passes));
    h.add_u64(state.light_paths);
    h.add(state.light.data(), state.light.size() * sizeof(glm::dvec3));
    h.add_u64(state.pending.size());
    h.add(state.pending.data(), state.pending.size() * sizeof(glm::dvec3));
  }
  return h.hex();
}

}  // namespace

void write_checkpoint(const RenderState& state, const CheckpointFacts& facts, const std::filesystem::path& file) {
  if (state.empty()) throw std::invalid_argument("write_checkpoint: empty render state");
  const CheckpointFacts in_order = sorted(facts);
  if (has_light(state) &&
      ((state.light_passes > 0 && state.light.size() != state.pixels()) ||
       (!state.pending.empty() && state.pending.size() != state.pixels()) || state.light_paths == 0 ||
       state.light_paths > static_cast<std::uint64_t>(std::numeric_limits<int>::max())))
    throw std::invalid_argument("write_checkpoint: light sums that are not one per pixel, or paths out of range");
  ExrExtras extras;
  add_double_channels(state.sum, "sum", extras);
  extras.uint_channels.emplace_back(count_name(), state.count);
  extras.ints = {{std::string(kPrefix) + "resume", kCheckpointFormat}, {std::string(kPrefix) + "passes", state.passes}};
  if (has_light(state)) {
    if (state.light_passes > 0) add_double_channels(state.light, "light", extras);
    if (!state.pending.empty()) add_double_channels(state.pending, "pending", extras);
    extras.ints.emplace_back(std::string(kPrefix) + "lightPasses", state.light_passes);
    extras.ints.emplace_back(std::string(kPrefix) + "lightPaths", static_cast<int>(state.light_paths));
    extras.ints.emplace_back(std::string(kPrefix) + "lightPending", state.pending.empty() ? 0 : 1);
  }
  for (const auto& [key, value] : in_order) {
    if (key.empty() || std::find(kReserved.begin(), kReserved.end(), key) != kReserved.end())
      throw std::invalid_argument("write_checkpoint: '" + key + "' cannot be a fact's key");
    extras.strings.emplace_back(std::string(kPrefix) + key, value);
  }
  extras.strings.emplace_back(std::string(kPrefix) + "digest", digest(state, in_order));
  write_exr(state.mean(), file, extras);
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  ExrExtras extras;
  const ImageRGB image = read_exr(file, extras, kPrefix);
  auto int_of = [&](std::string_view key) -> const int* {
    for (const auto& [name, value] : extras.ints)
      if (name.substr(kPrefix.size()) == key) return &value;
    return nullptr;
  };
  const int* format = int_of("resume");
  if (format == nullptr)
    throw ImageError(file, "has no resume data (it was not written by lancer render, or by its sppm integrator)");
  if (*format != kCheckpointFormat)
    throw ImageError(file, "its resume data is of format " + std::to_string(*format) + ", this program reads format " +
                               std::to_string(kCheckpointFormat));
  auto damaged = [&](const std::string& what) { return ImageError(file, "damaged resume data: " + what); };
  const int* passes = int_of("passes");
  if (passes == nullptr) throw damaged("no lancer.passes attribute");

  Checkpoint cp;
  RenderState& st = cp.state;
  st.width = image.width, st.height = image.height, st.passes = *passes;
  auto channel = [&](const std::string& name) -> const std::vector<std::uint32_t>& {
    for (const auto& [n, values] : extras.uint_channels)
      if (n == name) return values;
    throw damaged("no " + name + " channel");
  };
  auto read_doubles = [&](std::vector<glm::dvec3>& sums, const char* what) {
    sums.assign(st.pixels(), glm::dvec3(0.0));
    for (int c = 0; c < 3; ++c) {
      const std::vector<std::uint32_t>& hi = channel(hi_name(what, c));
      const std::vector<std::uint32_t>& lo = channel(lo_name(what, c));
      for (std::size_t p = 0; p < st.pixels(); ++p) {
        const std::uint64_t bits = std::uint64_t{hi[p]} << 32 | lo[p];
        std::memcpy(&sums[p][c], &bits, sizeof bits);
      }
    }
  };
  st.count = channel(count_name());
  read_doubles(st.sum, "sum");
  const int* light_passes = int_of("lightPasses");
  const int* light_paths = int_of("lightPaths");
  const int* light_pending = int_of("lightPending");
  if ((light_passes == nullptr) != (light_paths == nullptr) || (light_passes == nullptr) != (light_pending == nullptr))
    throw damaged("some but not all of lightPasses, lightPaths and lightPending");
  if (light_passes != nullptr) {
    if (*light_passes < 0 || *light_paths <= 0 || (*light_pending != 0 && *light_pending != 1) ||
        (*light_passes == 0 && *light_pending == 0))
      throw damaged("light passes, paths or pending out of range");
    st.light_passes = *light_passes;
    st.light_paths = static_cast<std::uint64_t>(*light_paths);
    if (st.light_passes > 0) read_doubles(st.light, "light");
    if (*light_pending == 1) read_doubles(st.pending, "pending");
  }
  // Light sums the attributes do not account for: written by something else.
  for (const auto& [name, values] : extras.uint_channels) {
    const bool light = name.rfind(std::string(kPrefix) + "light", 0) == 0;
    const bool pending = name.rfind(std::string(kPrefix) + "pending", 0) == 0;
    if ((light && st.light_passes == 0) || (pending && st.pending.empty()))
      throw damaged("a " + name + " channel its light attributes do not account for");
  }
  std::string stored_digest;
  for (const auto& [name, value] : extras.strings) {
    const std::string key = name.substr(kPrefix.size());
    if (key == "digest") stored_digest = value;
    else cp.facts.emplace_back(key, value);
  }
  cp.facts = sorted(std::move(cp.facts));
  if (stored_digest.empty()) throw damaged("no lancer.digest attribute");
  if (stored_digest != digest(st, cp.facts)) throw damaged("its digest does not match its contents (edited or corrupted?)");
  // The digest vouches for the state; the picture must also be its mean, bit for bit.
  const ImageRGB mean = st.mean();
  if (std::memcmp(mean.rgb.data(), image.rgb.data(), mean.rgb.size() * sizeof(float)) != 0)
    throw damaged("the picture is not the mean of the saved sums");
  return cp;
}

}  // namespace lancer
