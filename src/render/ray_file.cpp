// Ray, hit and occlusion files through plain POSIX calls, so every OS failure is reported
// with its errno text. Records are encoded byte by byte in little-endian order, so the
// files are the same on every host. Reading allocates exactly what the file size says
// (after checking it) and reads in fixed-size chunks; writing streams fixed-size chunks
// into "<file>.tmp", flushes it and renames it over the target, as image_io.cpp does.
#include "render/ray_file.h"
#include "simd/out_of_memory.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <new>
#include <string>
#include <system_error>

namespace lancer {
namespace {

namespace fs = std::filesystem;

// Records per read or write call: a 2 MiB buffer for rays, whatever the file size.
constexpr std::size_t kChunkRecords = 1 << 16;

constexpr std::array<const char*, 8> kRayFieldNames = {"ox", "oy", "oz", "tnear", "dx", "dy", "dz", "tfar"};

std::string os_error(int err) { return std::generic_category().message(err); }

void put_u32(unsigned char* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
std::uint32_t get_u32(const unsigned char* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
void put_f32(unsigned char* p, float f) { put_u32(p, std::bit_cast<std::uint32_t>(f)); }
float get_f32(const unsigned char* p) { return std::bit_cast<float>(get_u32(p)); }

// Closes a POSIX descriptor once, on whichever path leaves the scope first.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }
  // Returns 0 or the errno of close (a delayed write error can surface only here).
  int close() {
    const int result = ::close(fd_);
    fd_ = -1;
    return result == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

// Reads exactly `size` bytes at the current position; a file that shrank is an error.
void read_exactly(int fd, unsigned char* data, std::size_t size, const fs::path& file) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw RayFileError(file, "read failed: " + os_error(errno));
    if (n == 0) throw RayFileError(file, "the file became shorter while it was read");
    done += static_cast<std::size_t>(n);
  }
}

// How read_records describes the records of one kind of file in its messages.
struct RecordKind {
  std::size_t bytes;
  const char* name;    // "ray"
  const char* layout;  // "8 float32: ..."
  bool allow_empty;
};

// Reads a file of fixed-size records: checks the size, calls allocate(count) once, then
// decode(bytes, first, n) for each chunk of n whole records.
template <typename Allocate, typename Decode>
void read_records(const fs::path& file, const RecordKind& kind, Allocate&& allocate, Decode&& decode) {
  FileDescriptor fd(::open(file.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) throw RayFileError(file, "cannot open: " + os_error(errno));
  struct stat info {};
  if (::fstat(fd.get(), &info) != 0) throw RayFileError(file, "cannot stat: " + os_error(errno));
  if (!S_ISREG(info.st_mode)) throw RayFileError(file, "not a regular file");
  const auto size = static_cast<std::uint64_t>(info.st_size);
  if (const std::uint64_t rest = size % kind.bytes; rest != 0)
    throw RayFileError(file, "size " + std::to_string(size) + " bytes is not a multiple of " +
                                 std::to_string(kind.bytes) + " (one " + kind.name + " is " + kind.layout + "): " +
                                 kind.name + " " + std::to_string(size / kind.bytes) + ", at byte offset " +
                                 std::to_string(size - rest) + ", is cut off after " + std::to_string(rest) +
                                 " byte(s)");
  const std::uint64_t count = size / kind.bytes;
  if (count == 0 && !kind.allow_empty) throw RayFileError(file, std::string("the file is empty: no ") + kind.name + "s");
  if (count > kMaxRayFileRays)
    throw RayFileError(file, "holds " + std::to_string(count) + " " + kind.name + "s, more than the limit of 2^31");
  try {
    allocate(static_cast<std::size_t>(count));
    std::vector<unsigned char> buffer(static_cast<std::size_t>(std::min<std::uint64_t>(count, kChunkRecords)) *
                                      kind.bytes);
    for (std::uint64_t first = 0; first < count; first += kChunkRecords) {
      const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(count - first, kChunkRecords));
      read_exactly(fd.get(), buffer.data(), n * kind.bytes, file);
      decode(buffer.data(), static_cast<std::size_t>(first), n);
    }
  } catch (const std::bad_alloc& e) {
    throw RayFileError(file, out_of_memory_message(e) + " for " + std::to_string(count) + " " + kind.name + "s");
  }
}

// Writes "<file>.tmp" chunk by chunk, then flushes it and renames it over `file`: rename(2)
// replaces the target atomically, so readers see the old file or the whole new one. The
// temporary is removed on any failure, including destruction before commit().
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const fs::path& file)
      : file_(file), temporary_(fs::path(file) += ".tmp"), temporary_name_(temporary_.filename().string()),
        fd_(::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666)) {
    if (fd_.get() < 0) throw RayFileError(file_, "cannot create '" + temporary_name_ + "': " + os_error(errno));
  }
  ~AtomicFileWriter() {
    if (!committed_) {
      if (fd_.get() >= 0) fd_.close();
      ::unlink(temporary_.c_str());
    }
  }
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void write(const unsigned char* data, std::size_t size) {
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(fd_.get(), data + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw RayFileError(file_, "cannot write '" + temporary_name_ + "': " + os_error(errno));
      done += static_cast<std::size_t>(n);
    }
  }

  void commit() {
    if (::fsync(fd_.get()) != 0) throw RayFileError(file_, "cannot flush '" + temporary_name_ + "': " + os_error(errno));
    if (const int err = fd_.close(); err != 0)
      throw RayFileError(file_, "cannot close '" + temporary_name_ + "': " + os_error(err));
    if (::rename(temporary_.c_str(), file_.c_str()) != 0)
      throw RayFileError(file_, "cannot rename '" + temporary_name_ + "' to it: " + os_error(errno));
    committed_ = true;
  }

 private:
  fs::path file_;
  fs::path temporary_;
  std::string temporary_name_;
  FileDescriptor fd_;
  bool committed_ = false;
};

// Encodes records chunk by chunk with encode(record, bytes) and writes them atomically.
template <typename T, typename Encode>
void write_records(const fs::path& file, std::span<const T> records, std::size_t record_bytes, Encode&& encode) {
  AtomicFileWriter out(file);
  std::vector<unsigned char> buffer(std::min(records.size(), kChunkRecords) * record_bytes);
  for (std::size_t first = 0; first < records.size(); first += kChunkRecords) {
    const std::size_t n = std::min(records.size() - first, kChunkRecords);
    for (std::size_t i = 0; i < n; ++i) encode(records[first + i], buffer.data() + i * record_bytes);
    out.write(buffer.data(), n * record_bytes);
  }
  out.commit();
}

}  // namespace

HitRecord make_hit_record(const Hit& hit, std::span<const std::uint32_t> source_triangle_id) {
  if (!hit.valid()) return {};
  if (hit.prim >= source_triangle_id.size())
    throw std::out_of_range("hit on triangle " + std::to_string(hit.prim) + " but the scene maps only " +
                            std::to_string(source_triangle_id.size()) + " triangles to source ids");
  return {hit.t, source_triangle_id[hit.prim]};
}

std::vector<Ray> read_rays(const fs::path& file) {
  std::vector<Ray> rays;
  read_records(
      file, {kRayRecordBytes, "ray", "8 float32: ox oy oz tnear dx dy dz tfar", false},
      [&](std::size_t count) { rays.resize(count); },
      [&](const unsigned char* bytes, std::size_t first, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) {
          float f[8];
          for (std::size_t k = 0; k < 8; ++k) {
            f[k] = get_f32(bytes + i * kRayRecordBytes + 4 * k);
            if (std::isnan(f[k])) {
              const std::size_t index = first + i;
              throw RayFileError(file, "ray " + std::to_string(index) + " (byte offset " +
                                           std::to_string(index * kRayRecordBytes + 4 * k) + "): " +
                                           kRayFieldNames[k] + " is NaN");
            }
          }
          Ray& r = rays[first + i];
          r.org = glm::vec3(f[0], f[1], f[2]);
          r.tnear = f[3];
          r.dir = glm::vec3(f[4], f[5], f[6]);
          r.tfar = f[7] >= kUnboundedTfar ? kInfinity : f[7];
        }
      });
  return rays;
}

void write_rays(const fs::path& file, std::span<const Ray> rays) {
  write_records(file, rays, kRayRecordBytes, [](const Ray& r, unsigned char* p) {
    const float f[8] = {r.org.x, r.org.y, r.org.z, r.tnear, r.dir.x, r.dir.y, r.dir.z, r.tfar};
    for (std::size_t k = 0; k < 8; ++k) put_f32(p + 4 * k, f[k]);
  });
}

void write_hits(const fs::path& file, std::span<const HitRecord> hits) {
  write_records(file, hits, kHitRecordBytes, [](const HitRecord& h, unsigned char* p) {
    put_f32(p, h.t);
    put_u32(p + 4, h.id);
  });
}

std::vector<HitRecord> read_hits(const fs::path& file) {
  std::vector<HitRecord> hits;
  read_records(
      file, {kHitRecordBytes, "hit", "float32 t then uint32 triangle id", true},
      [&](std::size_t count) { hits.resize(count); },
      [&](const unsigned char* bytes, std::size_t first, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i)
          hits[first + i] = {get_f32(bytes + i * kHitRecordBytes), get_u32(bytes + i * kHitRecordBytes + 4)};
      });
  return hits;
}

void write_occlusion(const fs::path& file, std::span<const std::uint8_t> occluded) {
  write_records(file, occluded, 1, [](std::uint8_t o, unsigned char* p) { *p = o != 0 ? 1 : 0; });
}

std::vector<std::uint8_t> read_occlusion(const fs::path& file) {
  std::vector<std::uint8_t> occluded;
  read_records(
      file, {1, "answer", "one byte", true}, [&](std::size_t count) { occluded.resize(count); },
      [&](const unsigned char* bytes, std::size_t first, std::size_t n) {
        std::copy_n(bytes, n, occluded.begin() + static_cast<std::ptrdiff_t>(first));
      });
  return occluded;
}

}  // namespace lancer
