// Texture lookups: an Image sampled through a glTF Texture (sampler) at a UV.
//
// Conventions (glTF 2.0 spec, "Textures", "Samplers"):
//  - UV (0, 0) is the top-left corner of the image, (1, 1) the bottom-right; texel
//    (i, j) covers [i, i+1]/W x [j, j+1]/H and its centre is ((i + 0.5)/W, (j + 0.5)/H).
//  - Wrap modes per axis: 10497 repeat, 33071 clamp to edge, 33648 mirrored repeat
//    (period 2, the image then its mirror image, as OpenGL's MIRRORED_REPEAT).
//  - Filters: 9728 nearest, 9729 linear (bilinear between the four nearest texel
//    centres). There are no mipmaps: the mipmap minification modes act as their base
//    filter (9984/9986 nearest, 9985/9987 linear). An absent filter means linear.
//    Without ray differentials a lookup does not know whether it magnifies or
//    minifies; lookups use the magnification filter unless the caller says otherwise.
//  - 8-bit values become floats in [0, 1]. Colour textures (base colour, emissive,
//    specular colour) hold sRGB-encoded RGB and are decoded to linear (IEC 61966-2-1)
//    before filtering; data textures (metallic-roughness, normal, occlusion,
//    transmission, specular, thickness) are linear. Alpha is always linear.
//  - Channels: grey -> (g, g, g, 1), grey + alpha -> (g, g, g, a), RGB -> (r, g, b, 1).
//
// A lookup allocates nothing and takes no lock; non-finite coordinates read the texel
// at UV (0, 0).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "scene/scene.h"

namespace lancer {

inline constexpr int kWrapRepeat = 10497;
inline constexpr int kWrapClampToEdge = 33071;
inline constexpr int kWrapMirroredRepeat = 33648;
inline constexpr int kFilterNearest = 9728;
inline constexpr int kFilterLinear = 9729;

enum class TexelEncoding { Linear, Srgb };
enum class TexelFilter { Nearest, Linear };

// The texture's filter for magnification (texel larger than the footprint) or
// minification, following the rules above.
TexelFilter texel_filter(const Texture& texture, bool minifying = false);

// `image` sampled at `uv` with the texture's wrap modes and `filter`. The image must be
// consistent (width, height >= 1, 1 to 4 channels, width * height * channels bytes), as
// the readers guarantee.
glm::vec4 sample_image(const Image& image, const Texture& texture, glm::vec2 uv, TexelEncoding encoding,
                       TexelFilter filter);

// KHR_texture_transform: (ref.transform * vec3(uv, 1)).xy.
glm::vec2 transform_uv(const TextureRef& ref, glm::vec2 uv);

// The image behind `ref`, or null when the reference is absent or its texture has no
// image (a glTF texture whose source only an unsupported extension provides). Shading
// treats both as "no texture".
const Image* texture_image(const Scene& scene, const TextureRef& ref);

// The full lookup for a material's texture: picks TEXCOORD_0 or _1 by ref.texcoord,
// applies the transform and samples with the magnification filter. Returns (1, 1, 1, 1)
// when texture_image() is null, the neutral value for every factor * texture product.
glm::vec4 sample_texture(const Scene& scene, const TextureRef& ref, glm::vec2 uv0, glm::vec2 uv1,
                         TexelEncoding encoding);

}  // namespace lancer
