// Writing and reading ImageRGB files, chosen by extension (case-insensitive):
//   .exr                     OpenEXR, 32-bit float R, G, B, linear (ZIP compressed)
//   .png                     8-bit sRGB (written and read); 16-bit PNGs are also read
//   .jpg / .jpeg             8-bit sRGB (read only)
//   .hdr                     Radiance RGBE, linear (read only)
// Every failure throws ImageError naming the file; nothing is ever written half.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "render/display.h"
#include "render/image.h"

namespace lancer {

// The one exception of image I/O; the message is "<file>: <what>".
class ImageError : public std::runtime_error {
 public:
  ImageError(const std::filesystem::path& file, const std::string& what)
      : std::runtime_error(file.string() + ": " + what) {}
};

// Images larger than this many pixels are refused before any allocation (a corrupt
// header must not make us allocate gigabytes).
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 28;

// Writes `image` to `file`. The bytes go to "<file>.tmp" in the same directory, are
// flushed to disk, and the temporary is then renamed over `file`, so an interrupted
// program never leaves a partial file under the final name. EXR stores values as they
// are (NaN and infinities included: use count_non_finite to warn); PNG clamps to
// [0, 1] with NaN written as 0. Throws ImageError on an unknown extension, an
// inconsistent image, or any OS or encoder failure (with the OS reason).
// `display` (exposure and tone curve, render/display.h) shapes PNG output only; the
// default is the identity, clamped.
void write_image(const ImageRGB& image, const std::filesystem::path& file, const DisplayTransform& display = {});

// Reads `file` as linear RGB. EXR: channels R, G, B of any pixel type, or a lone Y
// channel as grey; the data window becomes the image. PNG/JPEG: decoded from sRGB.
// HDR: linear as stored. Throws ImageError for a missing, corrupt, truncated or
// oversized file, naming the file and the decoder's reason.
ImageRGB read_image(const std::filesystem::path& file);

// What an EXR file may carry beside its picture (the render state of `lancer render --resume`):
// 32-bit unsigned channels of width * height values each, row-major, and string and int
// header attributes. Other programs show the RGB picture and keep or ignore the rest.
// The most extra UINT channels read_exr reads under one prefix (a checkpoint has up to 19:
// sums 6, counts 1, light sums 6, a pending light pass 6): each costs a full image of
// memory, so a hostile file may not ask for hundreds.
inline constexpr std::size_t kMaxExrExtraChannels = 19;

struct ExrExtras {
  std::vector<std::pair<std::string, std::vector<std::uint32_t>>> uint_channels;
  std::vector<std::pair<std::string, std::string>> strings;
  std::vector<std::pair<std::string, int>> ints;
};

// write_image to a .exr file with `extras` added (names must not clash with R, G, B or the
// standard attributes). Throws ImageError as write_image does, and for a channel of the wrong size.
void write_exr(const ImageRGB& image, const std::filesystem::path& file, const ExrExtras& extras);

// read_image of a .exr file that also returns, in `extras`, every full-resolution UINT channel
// and every string and int attribute whose name starts with `prefix`.
ImageRGB read_exr(const std::filesystem::path& file, ExrExtras& extras, std::string_view prefix);

// Number of pixels with at least one NaN or infinite channel.
std::size_t count_non_finite(const ImageRGB& image);

}  // namespace lancer
