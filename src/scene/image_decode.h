// Texture images from encoded bytes to lancer::Image, shared by the glTF and OBJ
// readers: stb_image decodes, libwebp decodes WebP (which stb cannot read), and the
// checks stb does not make are made here.
#pragma once

#include <cstddef>
#include <span>
#include <string>

#include "scene/scene.h"

namespace lancer {

// Images with more pixels than this are refused before decoding: a corrupt header could
// otherwise ask stb for gigabytes.
inline constexpr long long kMaxImagePixels = 1ll << 28;

// Decodes PNG, JPEG, BMP, TGA, ... (whatever stb_image reads) into 8-bit pixels with the
// file's own channel count (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), rows top to bottom.
// WebP (a RIFF "WEBP" file: EXT_texture_webp) is decoded by libwebp to RGB, or RGBA when it
// has alpha; an animated one is refused. `name` becomes Image::name. Throws
// SceneError(file, what + " ...") when the bytes cannot be decoded, the size is zero or
// absurd, or a PNG, JPEG or WebP is truncated (see below).
Image decode_image(std::span<const unsigned char> bytes, std::string name, const std::string& file,
                   const std::string& what);

// Why a PNG or JPEG byte stream is incomplete, or "" when it is complete or neither
// format. stb_image decodes a JPEG cut short without a word, filling the missing
// blocks with grey, so the container is walked here:
//  - PNG (ISO/IEC 15948, sec. 5): the 8-byte signature, then chunks
//    (length, type, data, CRC) up to and including a whole IEND chunk.
//  - JPEG (ITU-T T.81, annex B): marker segments from SOI, each scan's entropy-coded
//    data up to the next marker (0xFF followed by neither 0x00 stuffing nor RSTn),
//    until the EOI marker 0xFFD9. Segments are skipped by their length, so a thumbnail
//    inside APP1 (with its own EOI) does not count. Bytes after EOI are allowed.
std::string truncation_problem(std::span<const unsigned char> bytes);

}  // namespace lancer
