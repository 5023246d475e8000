"""Procedural, tileable texture sets for scenes/textured/: bricks, glazed tiles and
hammered metal. Each set is a height field (in pixels) plus colour and roughness
rules; the normal map is the height field's tangent-space normal.

Conventions (glTF 2.0, "material.normalTextureInfo"): a normal-map texel stores
(n + 1) / 2 with +X to the right and +Y up in the image, +Z out of the surface. For a
height field h over pixel columns x and rows j (j grows downwards) the surface
normal is proportional to (-dh/dx, -dh/dy_up, 1) = (-dh/dx, +dh/dj, 1).
Colour textures are sRGB-encoded (IEC 61966-2-1); metallic-roughness textures are
linear with roughness in G and metallic in B (R unused, written as 255).

Everything is a function of the pixel coordinates and fixed seeds: no randomness
from the environment, so the images are the same on every run.
"""

import math


def _hash01(i, j, seed):
    """A float in [0, 1) from two integers and a seed (32-bit integer mixing)."""
    h = (i * 0x8DA6B343 + j * 0xD8163841 + seed * 0xCB1AB31F) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x2C1B3C6D) & 0xFFFFFFFF
    h ^= h >> 12
    h = (h * 0x297A2D39) & 0xFFFFFFFF
    h ^= h >> 15
    return h / 4294967296.0


def _smooth(t):
    return t * t * (3.0 - 2.0 * t)


def smoothstep(edge0, edge1, x):
    if x <= edge0:
        return 0.0
    if x >= edge1:
        return 1.0
    return _smooth((x - edge0) / (edge1 - edge0))


def value_noise(x, y, period, seed):
    """Bilinear value noise on an integer lattice that repeats every `period` cells."""
    xi, yi = math.floor(x), math.floor(y)
    fx, fy = _smooth(x - xi), _smooth(y - yi)
    x0, x1 = xi % period, (xi + 1) % period
    y0, y1 = yi % period, (yi + 1) % period
    a = _hash01(x0, y0, seed)
    b = _hash01(x1, y0, seed)
    c = _hash01(x0, y1, seed)
    d = _hash01(x1, y1, seed)
    return (a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy


def fbm(u, v, period, octaves, seed):
    """Fractal sum of value noise in [0, 1]; (u, v) in [0, 1) tiles with period 1."""
    total, weight, norm = 0.0, 1.0, 0.0
    for k in range(octaves):
        cells = period << k
        total += weight * value_noise(u * cells, v * cells, cells, seed + k)
        norm += weight
        weight *= 0.5
    return total / norm


def srgb_encode(linear):
    """Linear [0, 1] to an 8-bit sRGB value (IEC 61966-2-1)."""
    c = min(max(linear, 0.0), 1.0)
    s = 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1.0 / 2.4) - 0.055
    return int(round(s * 255.0))


def linear_byte(value):
    return int(round(min(max(value, 0.0), 1.0) * 255.0))


def normal_map(heights, size):
    """Tangent-space normals of a square, wrapping height field (list of rows, pixels)."""
    out = bytearray()
    for j in range(size):
        up, row, down = heights[(j - 1) % size], heights[j], heights[(j + 1) % size]
        for x in range(size):
            dhdx = 0.5 * (row[(x + 1) % size] - row[(x - 1) % size])
            dhdj = 0.5 * (down[x] - up[x])
            nx, ny, nz = -dhdx, dhdj, 1.0
            inv = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
            out.extend((linear_byte(0.5 + 0.5 * nx * inv), linear_byte(0.5 + 0.5 * ny * inv),
                        linear_byte(0.5 + 0.5 * nz * inv)))
    return bytes(out)


class TextureSet:
    """Three square RGB images of one material: base colour (sRGB), normal, metallic-roughness."""

    def __init__(self, size, base_color, normal, metallic_roughness):
        self.size = size
        self.base_color = base_color
        self.normal = normal
        self.metallic_roughness = metallic_roughness


def bricks(size=512):
    """Running-bond bricks: 4 per row, 8 rows, 8-pixel mortar joints; raised bevelled
    bricks with a rough face, recessed mortar."""
    brick_w, brick_h, half_joint, bevel, depth = size // 4, size // 8, 4.0, 6.0, 4.0
    palette = [(0.50, 0.16, 0.10), (0.58, 0.22, 0.13), (0.44, 0.14, 0.10), (0.62, 0.29, 0.17), (0.40, 0.18, 0.13)]
    heights, colour, mr = [], bytearray(), bytearray()
    for j in range(size):
        y = j + 0.5
        row = int(y // brick_h)
        ly = y - row * brick_h
        height_row = []
        for i in range(size):
            x = (i + 0.5 + (row % 2) * brick_w * 0.5) % size
            col = int(x // brick_w)
            lx = x - col * brick_w
            d = min(lx - half_joint, brick_w - half_joint - lx, ly - half_joint, brick_h - half_joint - ly)
            u, v = (i + 0.5) / size, y / size
            grain = fbm(u, v, 32, 3, 11)
            if d > 0.0:
                pick = _hash01(row, col, 5)
                base = palette[int(pick * len(palette))]
                shade = (0.85 + 0.3 * _hash01(row, col, 6)) * (0.8 + 0.4 * fbm(u, v, 8, 3, 12))
                rgb = [c * shade for c in base]
                h = depth * smoothstep(0.0, bevel, d) + 0.8 * grain
                rough = 0.85
            else:
                m = 0.45 + 0.15 * grain
                rgb = [m, m * 0.97, m * 0.92]
                h = 0.6 * fbm(u, v, 64, 2, 13)
                rough = 0.95
            height_row.append(h)
            colour.extend(srgb_encode(c) for c in rgb)
            mr.extend((255, linear_byte(rough), 0))
        heights.append(height_row)
    return TextureSet(size, bytes(colour), normal_map(heights, size), bytes(mr))


def tiles(size=256):
    """Glazed square tiles, 4 x 4, with 6-pixel grooves: near-white glossy tiles (tinted
    by the material's base colour factor), dark rough grout."""
    tile, half_groove, bevel, depth = size // 4, 3.0, 5.0, 3.0
    heights, colour, mr = [], bytearray(), bytearray()
    for j in range(size):
        y = j + 0.5
        ty = int(y // tile)
        ly = y - ty * tile
        height_row = []
        for i in range(size):
            x = i + 0.5
            tx = int(x // tile)
            lx = x - tx * tile
            d = min(lx - half_groove, tile - half_groove - lx, ly - half_groove, tile - half_groove - ly)
            u, v = x / size, y / size
            if d > 0.0:
                g = 0.80 + 0.12 * _hash01(tx, ty, 21) + 0.04 * fbm(u, v, 16, 2, 22)
                rgb = (g, g, g)
                h = depth * smoothstep(0.0, bevel, d) + 1.2 * fbm(u, v, 4, 2, 23)
                rough = 0.2
            else:
                rgb = (0.22, 0.21, 0.2)
                h = 0.3 * fbm(u, v, 64, 1, 24)
                rough = 0.8
            height_row.append(h)
            colour.extend(srgb_encode(c) for c in rgb)
            mr.extend((255, linear_byte(rough), 0))
        heights.append(height_row)
    return TextureSet(size, bytes(colour), normal_map(heights, size), bytes(mr))


def hammered_metal(size=256):
    """Hammered metal: one round dent per cell of an 8 x 8 jittered grid (radius 13 to
    19 pixels, the deepest dent wins where they overlap); roughness 0.2 to 0.4,
    metallic 1. The base colour is white (the material's factor gives the metal)."""
    cells = 8
    cell = size / cells
    dents = {}
    for cy in range(cells):
        for cx in range(cells):
            jx = (_hash01(cx, cy, 31) - 0.5) * 0.5 * cell
            jy = (_hash01(cx, cy, 32) - 0.5) * 0.5 * cell
            radius = 13.0 + 6.0 * _hash01(cx, cy, 33)
            dents[(cx, cy)] = ((cx + 0.5) * cell + jx, (cy + 0.5) * cell + jy, radius)
    heights, colour, mr = [], bytearray(), bytearray()
    for j in range(size):
        y = j + 0.5
        cy = int(y // cell)
        height_row = []
        for i in range(size):
            x = i + 0.5
            cx = int(x // cell)
            h = 0.0
            for oy in (-1, 0, 1):
                for ox in (-1, 0, 1):
                    dx0, dy0, radius = dents[((cx + ox) % cells, (cy + oy) % cells)]
                    # The dent's centre in this tile's copy nearest to the pixel.
                    dx = (x - dx0 + size / 2) % size - size / 2
                    dy = (y - dy0 + size / 2) % size - size / 2
                    r2 = (dx * dx + dy * dy) / (radius * radius)
                    if r2 < 1.0:
                        h = min(h, -0.3 * radius * (1.0 - r2) ** 2)
            u, v = x / size, y / size
            h += 0.3 * fbm(u, v, 32, 2, 34)
            height_row.append(h)
            colour.extend((255, 255, 255))
            mr.extend((255, linear_byte(0.2 + 0.2 * fbm(u, v, 8, 3, 35)), 255))
        heights.append(height_row)
    return TextureSet(size, bytes(colour), normal_map(heights, size), bytes(mr))
