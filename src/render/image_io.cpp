// Image files: OpenEXR through the general FrameBuffer interface (full 32-bit floats),
// PNG/JPEG/HDR through stb. Files are read into memory and written from memory with
// plain POSIX calls, so every OS failure is reported with its errno text and the
// atomic write (temporary + fsync + rename) lives in one place.
#include "render/image_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <system_error>
#include <vector>

#include <Imath/ImathBox.h>
#include <OpenEXR/IexBaseExc.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfVersion.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include "render/color.h"
#include "simd/out_of_memory.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;

enum class Format { kExr, kPng, kJpeg, kHdr };

std::string os_error(int err) { return std::generic_category().message(err); }

Format format_from_extension(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".exr") return Format::kExr;
  if (ext == ".png") return Format::kPng;
  if (ext == ".jpg" || ext == ".jpeg") return Format::kJpeg;
  if (ext == ".hdr") return Format::kHdr;
  throw ImageError(file, "unknown image extension '" + file.extension().string() +
                             "' (expected .exr, .png, .jpg, .jpeg or .hdr)");
}

void check_dimensions(std::int64_t width, std::int64_t height, const fs::path& file) {
  if (width < 1 || height < 1)
    throw ImageError(file, "invalid image size " + std::to_string(width) + "x" + std::to_string(height));
  // Each side is below 2^31 here (callers pass ints), so the product cannot overflow.
  if (static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) > kMaxImagePixels)
    throw ImageError(file, "image size " + std::to_string(width) + "x" + std::to_string(height) +
                               " is too large (more than 2^28 pixels)");
}

// ---------------------------------------------------------------------------------
// Whole-file I/O with errno reasons.

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

std::string read_whole_file(const fs::path& file) {
  FileDescriptor fd(::open(file.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) throw ImageError(file, "cannot open: " + os_error(errno));
  struct stat info {};
  if (::fstat(fd.get(), &info) != 0) throw ImageError(file, "cannot stat: " + os_error(errno));
  if (!S_ISREG(info.st_mode)) throw ImageError(file, "not a regular file");
  std::string bytes(static_cast<std::size_t>(info.st_size), '\0');
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd.get(), bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw ImageError(file, "read failed: " + os_error(errno));
    if (n == 0) break;  // the file shrank while we read it; decode what is there
    done += static_cast<std::size_t>(n);
  }
  bytes.resize(done);
  return bytes;
}

// Writes "<file>.tmp", flushes it to the disk, then renames it over `file`: rename(2)
// replaces the target atomically, so readers see the old file or the whole new one.
void write_file_atomically(const fs::path& file, const std::string& bytes) {
  fs::path temporary = file;
  temporary += ".tmp";
  const std::string temporary_name = temporary.filename().string();
  FileDescriptor fd(::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666));
  if (fd.get() < 0) throw ImageError(file, "cannot create '" + temporary_name + "': " + os_error(errno));
  try {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd.get(), bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw ImageError(file, "cannot write '" + temporary_name + "': " + os_error(errno));
      done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd.get()) != 0) throw ImageError(file, "cannot flush '" + temporary_name + "': " + os_error(errno));
    if (const int err = fd.close(); err != 0)
      throw ImageError(file, "cannot close '" + temporary_name + "': " + os_error(err));
    if (::rename(temporary.c_str(), file.c_str()) != 0)
      throw ImageError(file, "cannot rename '" + temporary_name + "' to it: " + os_error(errno));
  } catch (...) {
    ::unlink(temporary.c_str());
    throw;
  }
}

// ---------------------------------------------------------------------------------
// OpenEXR.

// OpenEXR input stream over bytes already in memory. Like Imf::StdIFStream, a read
// past the end throws Iex::InputExc, which the library turns into its own messages.
class MemoryIStream : public Imf::IStream {
 public:
  MemoryIStream(const std::string& bytes, const std::string& name) : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || static_cast<std::uint64_t>(n) > bytes_.size() || pos_ > bytes_.size() - static_cast<std::size_t>(n))
      throw Iex::InputExc("Unexpected end of file.");
    std::memcpy(c, bytes_.data() + pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return true;
  }
  std::uint64_t tellg() override { return pos_; }
  void seekg(std::uint64_t pos) override { pos_ = pos; }

 private:
  const std::string& bytes_;
  std::uint64_t pos_ = 0;
};

// OpenEXR output stream into memory; OutputFile seeks back to fill in the offset table.
class MemoryOStream : public Imf::OStream {
 public:
  explicit MemoryOStream(const std::string& name) : Imf::OStream(name.c_str()) {}
  void write(const char c[], int n) override {
    const std::size_t count = static_cast<std::size_t>(n);
    if (bytes_.size() < pos_ + count) bytes_.resize(pos_ + count);
    std::memcpy(bytes_.data() + pos_, c, count);
    pos_ += count;
  }
  std::uint64_t tellp() override { return pos_; }
  void seekp(std::uint64_t pos) override { pos_ = static_cast<std::size_t>(pos); }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
  std::size_t pos_ = 0;
};

constexpr std::array<const char*, 3> kRgbNames = {"R", "G", "B"};

std::string encode_exr(const ImageRGB& image, const fs::path& file, const ExrExtras& extras = {}) {
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;  // lossless for 32-bit floats
  Imf::FrameBuffer frame;
  const std::size_t x_stride = 3 * sizeof(float);
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(image.width);
  for (std::size_t c = 0; c < 3; ++c) {
    header.channels().insert(kRgbNames[c], Imf::Channel(Imf::FLOAT));
    frame.insert(kRgbNames[c], Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, header.dataWindow(),
                                                x_stride, y_stride));
  }
  for (const auto& [name, values] : extras.uint_channels) {
    if (values.size() != image.rgb.size() / 3)
      throw ImageError(file, "channel " + name + " holds " + std::to_string(values.size()) + " values, expected one per pixel");
    header.channels().insert(name, Imf::Channel(Imf::UINT));
    frame.insert(name, Imf::Slice::Make(Imf::UINT, values.data(), header.dataWindow(), sizeof(std::uint32_t),
                                        sizeof(std::uint32_t) * static_cast<std::size_t>(image.width)));
  }
  for (const auto& [name, value] : extras.strings) header.insert(name, Imf::StringAttribute(value));
  for (const auto& [name, value] : extras.ints) header.insert(name, Imf::IntAttribute(value));
  MemoryOStream stream(file.string());
  {
    Imf::OutputFile out(stream, header);
    out.setFrameBuffer(frame);
    out.writePixels(image.height);
  }  // the destructor writes the line offset table
  return stream.take();
}

// Reads only the first header, so the data window can be checked before OpenEXR
// allocates its offset tables (a corrupt window could ask for gigabytes).
Imath::Box2i peek_exr_data_window(const std::string& bytes, const fs::path& file) {
  if (bytes.size() < 8 || !Imf::isImfMagic(bytes.data())) throw ImageError(file, "not an OpenEXR file (bad magic number)");
  int version = 0;
  for (int i = 3; i >= 0; --i) version = (version << 8) | static_cast<unsigned char>(bytes[4 + i]);  // little-endian
  MemoryIStream stream(bytes, file.string());
  stream.seekg(8);
  Imf::Header header;
  try {
    header.readFrom(stream, version);
  } catch (const std::exception& e) {
    throw ImageError(file, std::string("cannot read the OpenEXR header: ") + e.what());
  }
  return header.dataWindow();
}

const Imf::Channel* full_resolution_channel(const Imf::ChannelList& channels, const char* name,
                                            const fs::path& file) {
  const Imf::Channel* channel = channels.findChannel(name);
  if (channel != nullptr && (channel->xSampling != 1 || channel->ySampling != 1))
    throw ImageError(file, std::string("channel ") + name + " is subsampled, which is not supported");
  return channel;
}

// The UINT channels and string and int attributes under `prefix`, for read_exr.
void decode_exr_extras(Imf::InputFile& in, ImageRGB& image, std::string_view prefix, ExrExtras& extras,
                       const fs::path& file) {
  const Imath::Box2i window = in.header().dataWindow();
  auto wanted = [&](const char* name) { return std::string_view(name).substr(0, prefix.size()) == prefix; };
  for (auto it = in.header().begin(); it != in.header().end(); ++it) {
    if (!wanted(it.name())) continue;
    if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) extras.strings.emplace_back(it.name(), s->value());
    if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&it.attribute())) extras.ints.emplace_back(it.name(), i->value());
  }
  Imf::FrameBuffer frame;
  const Imf::ChannelList& channels = in.header().channels();
  for (auto it = channels.begin(); it != channels.end(); ++it) {
    if (!wanted(it.name()) || it.channel().type != Imf::UINT) continue;
    // Each such channel costs a full image of memory: a file may not ask for more than a
    // writer of this program ever puts there.
    if (extras.uint_channels.size() >= kMaxExrExtraChannels)
      throw ImageError(file, "more than " + std::to_string(kMaxExrExtraChannels) + " '" + std::string(prefix) +
                                 "' integer channels");
    full_resolution_channel(channels, it.name(), file);
    auto& [name, values] = extras.uint_channels.emplace_back(it.name(), std::vector<std::uint32_t>(image.rgb.size() / 3));
    frame.insert(name, Imf::Slice::Make(Imf::UINT, values.data(), window, sizeof(std::uint32_t),
                                        sizeof(std::uint32_t) * static_cast<std::size_t>(image.width)));
  }
  if (extras.uint_channels.empty()) return;
  in.setFrameBuffer(frame);
  in.readPixels(window.min.y, window.max.y);
}

ImageRGB decode_exr(const std::string& bytes, const fs::path& file, ExrExtras* extras = nullptr,
                    std::string_view prefix = {}) {
  const Imath::Box2i peeked = peek_exr_data_window(bytes, file);
  check_dimensions(std::int64_t{peeked.max.x} - peeked.min.x + 1, std::int64_t{peeked.max.y} - peeked.min.y + 1, file);

  MemoryIStream stream(bytes, file.string());
  Imf::InputFile in(stream);
  const Imath::Box2i window = in.header().dataWindow();
  const std::int64_t width = std::int64_t{window.max.x} - window.min.x + 1;
  const std::int64_t height = std::int64_t{window.max.y} - window.min.y + 1;
  check_dimensions(width, height, file);
  if (!in.isComplete()) throw ImageError(file, "incomplete OpenEXR file (truncated?): some pixels are missing");

  const Imf::ChannelList& channels = in.header().channels();
  const Imf::Channel* r = full_resolution_channel(channels, "R", file);
  const Imf::Channel* g = full_resolution_channel(channels, "G", file);
  const Imf::Channel* b = full_resolution_channel(channels, "B", file);
  const bool rgb = r != nullptr && g != nullptr && b != nullptr;
  if (!rgb) {
    // Reading Y alone from a luminance/chroma file would silently drop its colour.
    if (channels.findChannel("RY") != nullptr || channels.findChannel("BY") != nullptr)
      throw ImageError(file, "luminance/chroma (Y, RY, BY) OpenEXR files are not supported");
    if (full_resolution_channel(channels, "Y", file) == nullptr) {
      std::string found;
      for (auto it = channels.begin(); it != channels.end(); ++it) found += (found.empty() ? "" : ", ") + std::string(it.name());
      throw ImageError(file, "no R, G, B channels and no Y channel (channels: " + (found.empty() ? "none" : found) + ")");
    }
  }

  ImageRGB image(static_cast<int>(width), static_cast<int>(height));
  Imf::FrameBuffer frame;
  const std::size_t x_stride = 3 * sizeof(float);
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(width);
  if (rgb) {
    for (std::size_t c = 0; c < 3; ++c)
      frame.insert(kRgbNames[c], Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, window, x_stride, y_stride));
  } else {
    frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, image.rgb.data(), window, x_stride, y_stride));
  }
  in.setFrameBuffer(frame);
  in.readPixels(window.min.y, window.max.y);
  if (!rgb) {
    for (std::size_t i = 0; i < image.rgb.size(); i += 3) image.rgb[i + 1] = image.rgb[i + 2] = image.rgb[i];
  }
  if (extras != nullptr) decode_exr_extras(in, image, prefix, *extras, file);
  return image;
}

// ---------------------------------------------------------------------------------
// PNG / JPEG / HDR through stb.

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

std::uint32_t read_be32(const std::string& bytes, std::size_t pos) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[pos + i]);
  return v;
}

// CRC-32 of ISO 3309 / ITU-T V.42 (reflected polynomial 0xEDB88320), as PNG uses it.
std::uint32_t crc32(const char* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ static_cast<unsigned char>(data[i])) & 0xFFu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

// Walks the PNG chunk list (ISO/IEC 15948, sections 5.3 and 5.4): every chunk must fit
// in the file, match its CRC, and the list must reach IEND. stb_image checks neither
// CRCs nor a missing end, so a truncated or damaged file would otherwise decode into
// a silently wrong picture.
void check_png_chunks(const std::string& bytes, const fs::path& file) {
  std::size_t pos = sizeof(kPngSignature);
  for (;;) {
    const std::string where = " at byte " + std::to_string(pos);
    if (bytes.size() - pos < 12) throw ImageError(file, "truncated PNG: chunk" + where + " is cut off");
    const std::uint32_t length = read_be32(bytes, pos);
    std::string type = bytes.substr(pos + 4, 4);
    for (char& c : type) c = std::isalpha(static_cast<unsigned char>(c)) ? c : '?';
    if (length > 0x7FFFFFFFu) throw ImageError(file, "corrupt PNG: chunk " + type + where + " has an invalid length");
    if (bytes.size() - pos - 12 < length)
      throw ImageError(file, "truncated PNG: chunk " + type + where + " is cut off");
    if (read_be32(bytes, pos + 8 + length) != crc32(bytes.data() + pos + 4, length + 4))
      throw ImageError(file, "corrupt PNG: CRC mismatch in chunk " + type + where);
    if (type == "IEND") return;
    pos += 12 + length;
  }
}

struct StbFree {
  void operator()(void* pixels) const { stbi_image_free(pixels); }
};

std::string stb_reason() {
  const char* reason = stbi_failure_reason();
  return reason != nullptr ? reason : "unknown error";
}

ImageRGB decode_with_stb(const std::string& bytes, const fs::path& file, Format format) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) throw ImageError(file, "file too large to decode (over 2 GiB)");
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(bytes.size());

  // The content must match the extension: stb guesses formats (a TGA test passes on
  // many random bytes), and an LDR/HDR mix-up would go through a gamma-2.2 conversion.
  const bool is_png = bytes.size() >= 8 && std::memcmp(bytes.data(), kPngSignature, 8) == 0;
  if (format == Format::kPng && !is_png) throw ImageError(file, "not a PNG file (bad signature)");
  if (format == Format::kJpeg && !(bytes.size() >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF))
    throw ImageError(file, "not a JPEG file (bad signature)");
  if (format == Format::kHdr && !stbi_is_hdr_from_memory(data, size))
    throw ImageError(file, "not a Radiance HDR file (bad signature)");
  if (is_png) check_png_chunks(bytes, file);

  int width = 0, height = 0, components = 0;
  if (!stbi_info_from_memory(data, size, &width, &height, &components))
    throw ImageError(file, "cannot decode: " + stb_reason());
  check_dimensions(width, height, file);

  int w = 0, h = 0;
  ImageRGB image(width, height);
  if (format == Format::kHdr) {
    std::unique_ptr<float, StbFree> pixels(stbi_loadf_from_memory(data, size, &w, &h, &components, 3));
    if (!pixels) throw ImageError(file, "cannot decode: " + stb_reason());
    if (w == width && h == height) std::copy_n(pixels.get(), image.rgb.size(), image.rgb.begin());
  } else if (stbi_is_16_bit_from_memory(data, size)) {
    std::unique_ptr<stbi_us, StbFree> pixels(stbi_load_16_from_memory(data, size, &w, &h, &components, 3));
    if (!pixels) throw ImageError(file, "cannot decode: " + stb_reason());
    if (w == width && h == height)
      for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = srgb_to_linear(pixels.get()[i] / 65535.0f);
  } else {
    std::unique_ptr<stbi_uc, StbFree> pixels(stbi_load_from_memory(data, size, &w, &h, &components, 3));
    if (!pixels) throw ImageError(file, "cannot decode: " + stb_reason());
    if (w == width && h == height)
      for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = srgb8_to_linear(pixels.get()[i]);
  }
  if (w != width || h != height)
    throw ImageError(file, "decoded size " + std::to_string(w) + "x" + std::to_string(h) + " differs from the header");
  return image;
}

std::string encode_png(const ImageRGB& image, const fs::path& file, const DisplayTransform& display) {
  std::vector<std::uint8_t> codes(image.rgb.size());
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    const glm::vec3 c = display_map({image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]}, display);
    for (int k = 0; k < 3; ++k) codes[i + std::size_t(k)] = linear_to_srgb8(c[k]);
  }
  std::string bytes;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, codes.data(), image.width * 3))
    throw ImageError(file, "PNG encoding failed");
  return bytes;
}

void write_image_with(const ImageRGB& image, const std::filesystem::path& file, const DisplayTransform& display,
                      const ExrExtras* extras) {
  const Format format = format_from_extension(file);
  if (format != Format::kExr && format != Format::kPng)
    throw ImageError(file, "writing " + file.extension().string() + " files is not supported (use .exr or .png)");
  if (extras != nullptr && format != Format::kExr) throw ImageError(file, "only .exr files carry extra channels");
  check_dimensions(image.width, image.height, file);
  if (image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw ImageError(file, "image holds " + std::to_string(image.rgb.size()) + " floats, expected width*height*3");
  std::string bytes;
  try {
    bytes = format == Format::kExr ? encode_exr(image, file, extras != nullptr ? *extras : ExrExtras{})
                                   : encode_png(image, file, display);
  } catch (const ImageError&) {
    throw;
  } catch (const std::bad_alloc& e) {
    throw ImageError(file, out_of_memory_message(e) + " while encoding");
  } catch (const std::exception& e) {  // Iex::BaseExc derives from std::exception
    throw ImageError(file, e.what());
  }
  write_file_atomically(file, bytes);
}

ImageRGB read_image_with(const std::filesystem::path& file, ExrExtras* extras, std::string_view prefix) {
  const Format format = format_from_extension(file);
  if (extras != nullptr && format != Format::kExr) throw ImageError(file, "not an OpenEXR file (.exr)");
  const std::string bytes = read_whole_file(file);
  try {
    return format == Format::kExr ? decode_exr(bytes, file, extras, prefix) : decode_with_stb(bytes, file, format);
  } catch (const ImageError&) {
    throw;
  } catch (const std::bad_alloc& e) {
    throw ImageError(file, out_of_memory_message(e) + " while decoding");
  } catch (const std::exception& e) {
    throw ImageError(file, e.what());
  }
}

}  // namespace

void write_image(const ImageRGB& image, const std::filesystem::path& file, const DisplayTransform& display) {
  write_image_with(image, file, display, nullptr);
}

void write_exr(const ImageRGB& image, const std::filesystem::path& file, const ExrExtras& extras) {
  write_image_with(image, file, {}, &extras);
}

ImageRGB read_image(const std::filesystem::path& file) { return read_image_with(file, nullptr, {}); }

ImageRGB read_exr(const std::filesystem::path& file, ExrExtras& extras, std::string_view prefix) {
  extras = {};
  return read_image_with(file, &extras, prefix);
}

std::size_t count_non_finite(const ImageRGB& image) {
  std::size_t count = 0;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    if (!std::isfinite(image.rgb[i]) || !std::isfinite(image.rgb[i + 1]) || !std::isfinite(image.rgb[i + 2])) ++count;
  }
  return count;
}

}  // namespace lancer
