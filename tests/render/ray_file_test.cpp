// Ray, hit and occlusion files: the byte layout, round trips, and every refusal.
#include "render/ray_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "simd/splitmix64.h"
#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

// This process's folder, removed when it exits.
fs::path temp_dir() {
  static const test::TempDir dir("lancer_ray_file_test");
  return dir.path();
}

std::vector<unsigned char> file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& file, const std::vector<unsigned char>& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// The little-endian bytes of a float or uint32, written out by hand (not through ray_file.cpp).
void append_u32(std::vector<unsigned char>& bytes, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<unsigned char>((v >> (8 * i)) & 0xFFu));
}
void append_f32(std::vector<unsigned char>& bytes, float f) { append_u32(bytes, std::bit_cast<std::uint32_t>(f)); }

std::vector<unsigned char> encode_ray(const float (&f)[8]) {
  std::vector<unsigned char> bytes;
  for (float v : f) append_f32(bytes, v);
  return bytes;
}

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// The message of the RayFileError that `read` throws; fails the test when it throws nothing.
template <typename Read>
std::string refusal(Read&& read) {
  try {
    read();
  } catch (const RayFileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no RayFileError";
  return {};
}

std::vector<Ray> varied_rays(std::size_t n) {
  SplitMix64 rng(7);
  std::vector<Ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    Ray& r = rays[i];
    r.org = glm::vec3(rng.uniform() * 200.0f - 100.0f, rng.uniform() - 0.5f, -rng.uniform() * 1e30f);
    r.tnear = i % 3 == 0 ? 0.0f : rng.uniform();
    r.dir = glm::vec3(rng.uniform() - 0.5f, -0.0f, std::ldexp(rng.uniform(), -140));  // a denormal
    r.tfar = i % 2 == 0 ? kInfinity : rng.uniform() * 1e30f;
  }
  if (n < 5) return rays;
  rays[1].org.x = -kInfinity;  // infinities are valid rays
  rays[2].dir.y = kInfinity;
  rays[3].tnear = 10.0f;  // tnear > tfar: valid, never hits
  rays[3].tfar = 1.0f;
  rays[4].dir = glm::vec3(0.0f);  // zero direction: valid, never hits
  return rays;
}

TEST(RayFile, RaysRoundTripByteExact) {
  const fs::path file = temp_dir() / "round_trip.rays";
  const std::vector<Ray> rays = varied_rays(1000);
  write_rays(file, rays);

  std::vector<unsigned char> expected;
  for (const Ray& r : rays) {
    const std::vector<unsigned char> one = encode_ray({r.org.x, r.org.y, r.org.z, r.tnear, r.dir.x, r.dir.y, r.dir.z, r.tfar});
    expected.insert(expected.end(), one.begin(), one.end());
  }
  EXPECT_EQ(file_bytes(file), expected);

  const std::vector<Ray> back = read_rays(file);
  ASSERT_EQ(back.size(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(bits(back[i].org[k]), bits(rays[i].org[k])) << "ray " << i;
      EXPECT_EQ(bits(back[i].dir[k]), bits(rays[i].dir[k])) << "ray " << i;
    }
    EXPECT_EQ(bits(back[i].tnear), bits(rays[i].tnear)) << "ray " << i;
    EXPECT_EQ(bits(back[i].tfar), bits(rays[i].tfar)) << "ray " << i;
  }
  write_rays(file, back);
  EXPECT_EQ(file_bytes(file), expected);
  EXPECT_FALSE(fs::exists(fs::path(file) += ".tmp"));
}

TEST(RayFile, TfarAtOrAbove34e38IsUnbounded) {
  const fs::path file = temp_dir() / "tfar.rays";
  const float largest = std::numeric_limits<float>::max();
  const float below = std::nextafter(3.4e38f, 0.0f);
  const float tfars[] = {3.4e38f, largest, kInfinity, below, 1.0f, -kInfinity};
  std::vector<unsigned char> bytes;
  for (float tfar : tfars) {
    const std::vector<unsigned char> one = encode_ray({0, 0, 0, 0, 0, 0, 1, tfar});
    bytes.insert(bytes.end(), one.begin(), one.end());
  }
  write_bytes(file, bytes);
  const std::vector<Ray> rays = read_rays(file);
  ASSERT_EQ(rays.size(), 6u);
  EXPECT_EQ(rays[0].tfar, kInfinity);
  EXPECT_EQ(rays[1].tfar, kInfinity);
  EXPECT_EQ(rays[2].tfar, kInfinity);
  EXPECT_EQ(rays[3].tfar, below);
  EXPECT_EQ(rays[4].tfar, 1.0f);
  EXPECT_EQ(rays[5].tfar, -kInfinity);
}

TEST(RayFile, SizeNotAMultipleOf32IsRefused) {
  const fs::path file = temp_dir() / "cut.rays";
  for (std::size_t size : {1u, 31u, 33u, 63u, 100u}) {
    write_bytes(file, std::vector<unsigned char>(size, 0));
    const std::string msg = refusal([&] { read_rays(file); });
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("size " + std::to_string(size) + " bytes is not a multiple of 32"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ray " + std::to_string(size / 32) + ", at byte offset " + std::to_string(size / 32 * 32)),
              std::string::npos)
        << msg;
  }
}

TEST(RayFile, NanAnywhereIsRefusedWithRayIndexFieldAndOffset) {
  const fs::path file = temp_dir() / "nan.rays";
  const char* fields[] = {"ox", "oy", "oz", "tnear", "dx", "dy", "dz", "tfar"};
  const float nans[] = {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
                        std::numeric_limits<float>::signaling_NaN(), std::bit_cast<float>(0x7F800001u),
                        std::bit_cast<float>(0xFFFFFFFFu)};
  // 70001 rays: the last ones lie past the reader's first chunk of 65536.
  const std::size_t count = 70001;
  const std::vector<unsigned char> good = encode_ray({1, 2, 3, 0, 0, 0, -1, kInfinity});
  std::vector<unsigned char> bytes;
  for (std::size_t i = 0; i < count; ++i) bytes.insert(bytes.end(), good.begin(), good.end());

  int n = 0;
  for (std::size_t index : {std::size_t{0}, std::size_t{5}, std::size_t{65535}, std::size_t{65536}, count - 1}) {
    for (int k = 0; k < 8; ++k, ++n) {
      std::vector<unsigned char> bad = bytes;
      const std::size_t offset = index * 32 + static_cast<std::size_t>(k) * 4;
      const std::uint32_t nan_bits = bits(nans[n % 5]);
      for (int b = 0; b < 4; ++b) bad[offset + static_cast<std::size_t>(b)] = static_cast<unsigned char>(nan_bits >> (8 * b));
      write_bytes(file, bad);
      const std::string msg = refusal([&] { read_rays(file); });
      EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find("ray " + std::to_string(index) + " (byte offset " + std::to_string(offset) + "): " +
                         fields[k] + " is NaN"),
                std::string::npos)
          << msg;
    }
  }
  write_bytes(file, bytes);
  EXPECT_EQ(read_rays(file).size(), count);
}

TEST(RayFile, EmptyMissingAndNonRegularFilesAreRefused) {
  const fs::path dir = temp_dir();
  write_bytes(dir / "empty.rays", {});
  std::string msg = refusal([&] { read_rays(dir / "empty.rays"); });
  EXPECT_NE(msg.find("empty.rays"), std::string::npos) << msg;
  EXPECT_NE(msg.find("empty"), std::string::npos) << msg;

  msg = refusal([&] { read_rays(dir / "missing.rays"); });
  EXPECT_NE(msg.find("missing.rays"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot open"), std::string::npos) << msg;

  msg = refusal([&] { read_rays(dir); });
  EXPECT_NE(msg.find("not a regular file"), std::string::npos) << msg;
}

TEST(RayFile, MoreThan2To31RaysAreRefusedBeforeAllocating) {
  // A sparse file: 2^31 + 1 rays of zeros take no disk space, and must take no memory.
  const fs::path file = temp_dir() / "huge.rays";
  write_bytes(file, {});
  std::error_code ec;
  fs::resize_file(file, ((std::uint64_t{1} << 31) + 1) * 32, ec);
  if (ec) GTEST_SKIP() << "cannot make a 64 GiB sparse file here: " << ec.message();
  const std::string msg = refusal([&] { read_rays(file); });
  fs::remove(file);
  EXPECT_NE(msg.find("huge.rays"), std::string::npos) << msg;
  EXPECT_NE(msg.find("2147483649 rays, more than the limit of 2^31"), std::string::npos) << msg;
}

TEST(RayFile, WriteIntoAMissingDirectoryNamesTheFile) {
  const fs::path file = temp_dir() / "no_such_dir" / "out.rays";
  const std::vector<Ray> rays(3);
  try {
    write_rays(file, rays);
    ADD_FAILURE() << "no RayFileError";
  } catch (const RayFileError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_NE(e.problem().find("cannot create 'out.rays.tmp'"), std::string::npos) << e.what();
  }
}

TEST(RayFile, WritingReplacesAnExistingFileWhole) {
  const fs::path file = temp_dir() / "replace.rays";
  write_rays(file, varied_rays(100));
  write_rays(file, varied_rays(3));
  EXPECT_EQ(fs::file_size(file), 3u * 32u);
  EXPECT_FALSE(fs::exists(fs::path(file) += ".tmp"));
}

TEST(HitFile, EightBytesPerRayWithTheDocumentedEncoding) {
  const fs::path file = temp_dir() / "layout.hits";
  const std::vector<HitRecord> hits = {{1.5f, 7u}, {kInfinity, kNoHit}, {0.25f, 0x01020304u}};
  write_hits(file, hits);
  const std::vector<unsigned char> expected = {0x00, 0x00, 0xC0, 0x3F, 0x07, 0x00, 0x00, 0x00,   // 1.5f, 7
                                               0x00, 0x00, 0x80, 0x7F, 0xFF, 0xFF, 0xFF, 0xFF,   // +inf, none
                                               0x00, 0x00, 0x80, 0x3E, 0x04, 0x03, 0x02, 0x01};  // 0.25f
  EXPECT_EQ(file_bytes(file), expected);
  EXPECT_EQ(read_hits(file), hits);

  write_bytes(file, std::vector<unsigned char>(12, 0));
  const std::string msg = refusal([&] { read_hits(file); });
  EXPECT_NE(msg.find("not a multiple of 8"), std::string::npos) << msg;
}

TEST(HitFile, RecordsCarrySourceIdsAndMissesAreInfinity) {
  const std::vector<std::uint32_t> source_ids = {0, 2, 5};  // triangles 1, 3, 4 of the file were dropped
  Hit hit;
  hit.t = 2.0f;
  hit.prim = 2;
  EXPECT_EQ(make_hit_record(hit, source_ids), (HitRecord{2.0f, 5u}));
  Hit miss;
  miss.t = 3.0f;  // whatever t a miss carries, the file says +inf
  EXPECT_EQ(make_hit_record(miss, source_ids), (HitRecord{kInfinity, kNoHit}));
  hit.prim = 3;
  EXPECT_THROW(make_hit_record(hit, source_ids), std::out_of_range);
}

TEST(OcclusionFile, OneBytePerRay) {
  const fs::path file = temp_dir() / "occ.bin";
  const std::vector<std::uint8_t> occluded = {0, 1, 2, 0, 255};
  write_occlusion(file, occluded);
  EXPECT_EQ(file_bytes(file), (std::vector<unsigned char>{0, 1, 1, 0, 1}));
  EXPECT_EQ(read_occlusion(file), (std::vector<std::uint8_t>{0, 1, 1, 0, 1}));
}

}  // namespace
}  // namespace lancer
