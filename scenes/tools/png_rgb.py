"""Minimal PNG writer for 8-bit RGB images (PNG specification, ISO/IEC 15948:2003).

Standard library only (zlib, struct). Every row uses the Paeth filter (type 4), which
suits the smooth normal maps and flat colours the texture generators produce. The
output depends only on the pixels and on the zlib version (compression level 9).
"""

import struct
import zlib


def _chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def _paeth_row(row, previous):
    """Filter type 4: each byte minus the Paeth predictor of left, up and upper-left."""
    out = bytearray(len(row))
    for i, x in enumerate(row):
        a = row[i - 3] if i >= 3 else 0
        b = previous[i]
        c = previous[i - 3] if i >= 3 else 0
        p = a + b - c
        pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
        if pa <= pb and pa <= pc:
            predictor = a
        elif pb <= pc:
            predictor = b
        else:
            predictor = c
        out[i] = (x - predictor) & 0xFF
    return bytes(out)


def write_png(path, width, height, pixels):
    """pixels: bytes of length width * height * 3, rows top to bottom, RGB."""
    if len(pixels) != width * height * 3:
        raise ValueError("%s: expected %d bytes of RGB, got %d" % (path, width * height * 3, len(pixels)))
    stride = width * 3
    raw = bytearray()
    previous = bytes(stride)
    for y in range(height):
        row = pixels[y * stride:(y + 1) * stride]
        raw.append(4)
        raw.extend(_paeth_row(row, previous))
        previous = row
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)  # 8-bit RGB, no interlace
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(_chunk(b"IHDR", header))
        f.write(_chunk(b"IDAT", zlib.compress(bytes(raw), 9)))
        f.write(_chunk(b"IEND", b""))
