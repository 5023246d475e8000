#include "render/camera_emission.h"

#include <algorithm>
#include <cmath>

#include "render/path_rules.h"
#include "render/shading_inputs.h"
#include "render/sobol_sampler.h"

namespace lancer {

namespace {

constexpr int kCell = kBlockSide;  // cells of the image's 8x8 grid
// The estimate's own sample streams: the pixel's, with this seed instead of the render's.
constexpr std::uint64_t kSeedSalt = 0x7A3D95C2E8F14B61ull;

}  // namespace

CameraEmission::CameraEmission(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                               const PixelFilter& filter, int width, int height, int samples, TileRunner& runner)
    : scene_(scene), accel_(accel), camera_(camera), filter_(filter), samples_(std::max(1, samples)) {
  cells_x_ = (std::max(width, 0) + kCell - 1) / kCell;
  cells_y_ = (std::max(height, 0) + kCell - 1) / kCell;
  const auto count = static_cast<std::size_t>(cells_x_) * static_cast<std::size_t>(cells_y_);
  cells_.assign(count, 0);
  if (std::none_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.emissive(); }))
    return;
  // A cell shows an emitter when a camera ray through the top-left corner of one of its
  // pixels meets an emissive material first (whichever side, whatever its coverage: only
  // the choice of cells depends on it). One packet per cell: a ray per pixel in all.
  std::vector<std::uint8_t> sees(count, 0);
  setup_rays_ = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  runner.run_ranges(count, 16, [&](std::size_t begin, std::size_t end) {
    Ray rays[kBlockPixels];
    Hit hits[kBlockPixels];
    for (std::size_t c = begin; c < end; ++c) {
      const int x0 = static_cast<int>(c % static_cast<std::size_t>(cells_x_)) * kCell;
      const int y0 = static_cast<int>(c / static_cast<std::size_t>(cells_x_)) * kCell;
      const int x1 = std::min(x0 + kCell, width), y1 = std::min(y0 + kCell, height);
      int n = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          Ray& ray = rays[n++];
          ray = camera.generate(static_cast<float>(x), static_cast<float>(y));
          if (camera.shutter_open()) {
            ray.time = 0.5f;
            ray = camera.moved(ray);
          }
        }
      accel.intersect_packet(rays, hits, n);  // the hits are the same however they are traced
      for (int i = 0; i < n && !sees[c]; ++i)
        if (hits[i].valid() && scene.materials[scene.material_id[hits[i].prim]].emissive()) sees[c] = 1;
    }
  });
  // With the cells around each.
  for (int cy = 0; cy < cells_y_; ++cy)
    for (int cx = 0; cx < cells_x_; ++cx) {
      if (!sees[static_cast<std::size_t>(cy) * cells_x_ + cx]) continue;
      for (int ny = std::max(cy - 1, 0); ny <= std::min(cy + 1, cells_y_ - 1); ++ny)
        for (int nx = std::max(cx - 1, 0); nx <= std::min(cx + 1, cells_x_ - 1); ++nx)
          cells_[static_cast<std::size_t>(ny) * cells_x_ + nx] = 1;
    }
}

bool CameraEmission::covers(int x, int y) const {
  if (x < 0 || y < 0) return false;
  const int cx = x / kCell, cy = y / kCell;
  return cx < cells_x_ && cy < cells_y_ && cells_[static_cast<std::size_t>(cy) * cells_x_ + cx];
}

bool CameraEmission::mark(const PixelBlock& block, PrimaryBlock& primary, int first) const {
  bool any = false;
  for (int y = block.y0, i = first; y < block.y1; ++y)
    for (int x = block.x0; x < block.x1; ++x, ++i) {
      const bool apart = covers(x, y);
      primary.set_emission_apart(i, apart);
      any |= apart;
    }
  return any;
}

std::size_t CameraEmission::covered_cells() const {
  return static_cast<std::size_t>(std::count(cells_.begin(), cells_.end(), std::uint8_t{1}));
}

glm::vec3 CameraEmission::emission_at(const Ray& ray, const Hit& hit) const {
  if (!hit.valid() || !scene_.materials[scene_.material_id[hit.prim]].emissive()) return glm::vec3(0.0f);
  const ShadingInputs si = evaluate_shading(scene_, ray, hit);
  // A surface of coverage below 1 is the path's to count (see the top of the header).
  if (!(si.alpha >= 1.0f) || !emits_toward(*si.material, si.front_face)) return glm::vec3(0.0f);
  return si.emission;
}

void CameraEmission::add(const PixelBlock& block, const bool* apart, int sample, std::uint64_t seed, TraceMode mode,
                         glm::vec3* L, std::uint64_t& rays, Scratch& scratch) const {
  // The block's marked pixels, by their index in the block.
  scratch.pixels.clear();
  for (int i = 0; i < block.pixel_count(); ++i)
    if (apart[i]) scratch.pixels.push_back(i);
  const int n = static_cast<int>(scratch.pixels.size());
  if (n == 0) return;
  const std::size_t total = static_cast<std::size_t>(n) * static_cast<std::size_t>(samples_);
  scratch.rays.resize(total);
  scratch.hits.resize(total);
  // Ray j * n + k: covered pixel k's j-th, so that each j is one packet.
  const int width = block.width();
  for (int j = 0; j < samples_; ++j) {
    const auto index = static_cast<std::uint32_t>(sample) * static_cast<std::uint32_t>(samples_) +
                       static_cast<std::uint32_t>(j);
    for (int k = 0; k < n; ++k) {
      const int x = block.x0 + scratch.pixels[static_cast<std::size_t>(k)] % width;
      const int y = block.y0 + scratch.pixels[static_cast<std::size_t>(k)] / width;
      SobolSampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), index, seed ^ kSeedSalt);
      scratch.rays[static_cast<std::size_t>(j) * n + k] = camera_ray(camera_, filter_, x, y, sampler);
    }
  }
  if (mode == TraceMode::Packet) {
    for (int j = 0; j < samples_; ++j)
      accel_.intersect_packet(scratch.rays.data() + static_cast<std::size_t>(j) * n,
                              scratch.hits.data() + static_cast<std::size_t>(j) * n, n);
  } else {
    for (std::size_t r = 0; r < total; ++r) scratch.hits[r] = accel_.intersect(scratch.rays[r]);
  }
  rays += total;
  const float weight = 1.0f / static_cast<float>(samples_);
  for (int k = 0; k < n; ++k) {
    glm::vec3 sum(0.0f);
    for (int j = 0; j < samples_; ++j) {
      const std::size_t r = static_cast<std::size_t>(j) * n + k;
      sum += emission_at(scratch.rays[r], scratch.hits[r]);
    }
    // As the path tracer drops a non-finite sample, so is this estimate.
    if (path_rules::is_finite(sum)) L[scratch.pixels[static_cast<std::size_t>(k)]] += sum * weight;
  }
}

}  // namespace lancer
