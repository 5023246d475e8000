"""Small helpers for writing glTF 2.0 scenes from Python (standard library only):
indexed meshes with normals, tangents and texture coordinates, look-at rotations as
quaternions, and packing of accessors into one little-endian binary buffer.

Tangents follow the glTF convention (spec, "Meshes", TANGENT): xyz along increasing u,
w = +1 or -1 so that cross(normal, tangent.xyz) * w is the bitangent, which for glTF's
top-left UV origin points along decreasing v (up in the image).
"""

import math
import struct


def f32(x):
    """x rounded to IEEE single precision (what the buffer stores)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def short_f32(x):
    """The shortest decimal that reads back as the same single-precision value."""
    x = f32(x)
    for digits in range(1, 18):
        text = "%.*g" % (digits, x)
        if f32(float(text)) == x:
            return float(text) + 0.0
    return x


def round_floats(value):
    """Floats of a JSON tree written as their shortest single-precision decimals."""
    if isinstance(value, float):
        return short_f32(value)
    if isinstance(value, (list, tuple)):
        return [round_floats(v) for v in value]
    if isinstance(value, dict):
        return {k: round_floats(v) for k, v in value.items()}
    return value


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    length = math.sqrt(dot(a, a))
    return (a[0] / length + 0.0, a[1] / length + 0.0, a[2] / length + 0.0)


def tangent_frame(normal, dp_du, dp_dv):
    """The glTF tangent (x, y, z, w) of a vertex: dp_du made orthogonal to the unit
    normal, w from the side -dp_dv lies on."""
    t = normalize(sub(dp_du, scale(normal, dot(normal, dp_du))))
    w = 1.0 if dot(cross(normal, t), scale(dp_dv, -1.0)) >= 0.0 else -1.0
    return (t[0], t[1], t[2], w)


def quat_from_basis(right, up, back):
    """Unit quaternion (x, y, z, w) of the rotation whose matrix columns are the three
    orthonormal axes (Shoemake's trace method)."""
    m = [[right[r], up[r], back[r]] for r in range(3)]
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2])
        q = (0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    elif m[1][1] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2])
        q = ((m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1])
        q = ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s)
    n = math.sqrt(sum(c * c for c in q))
    return tuple(c / n + 0.0 for c in q)


def look_at_rotation(eye, target, world_up=(0.0, 1.0, 0.0)):
    """Rotation of a glTF camera node at `eye` (cameras look down local -z, +y up)."""
    forward = normalize(sub(target, eye))
    right = normalize(cross(forward, world_up))
    up = cross(right, forward)
    return quat_from_basis(right, up, scale(forward, -1.0))


def quat_axis_angle(axis, radians):
    a = normalize(axis)
    s = math.sin(0.5 * radians)
    return (a[0] * s, a[1] * s, a[2] * s, math.cos(0.5 * radians))


def quat_mul(p, q):
    """p * q: rotate by q, then by p."""
    px, py, pz, pw = p
    qx, qy, qz, qw = q
    return (pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
            pw * qw - px * qx - py * qy - pz * qz)


class Mesh:
    """Indexed triangles. `tangents` and `uvs` are either empty or one per vertex."""

    def __init__(self, name, material):
        self.name = name
        self.material = material
        self.positions, self.normals, self.tangents, self.uvs = [], [], [], []
        self.indices = []

    def vertex(self, position, normal, tangent=None, uv=None):
        self.positions.append(position)
        self.normals.append(normal)
        if tangent is not None:
            self.tangents.append(tangent)
        if uv is not None:
            self.uvs.append(uv)
        return len(self.positions) - 1

    def triangle(self, a, b, c):
        """Adds (a, b, c), wound counter-clockwise around the vertices' mean normal."""
        pa, pb, pc = self.positions[a], self.positions[b], self.positions[c]
        n = add(add(self.normals[a], self.normals[b]), self.normals[c])
        g = cross(sub(pb, pa), sub(pc, pa))
        if dot(g, g) == 0.0:
            raise ValueError("%s: degenerate triangle %d %d %d" % (self.name, a, b, c))
        self.indices.extend((a, b, c) if dot(g, n) > 0.0 else (a, c, b))


class BufferPacker:
    """Accessors packed into one binary buffer, each view 4-byte aligned."""

    def __init__(self):
        self.blob = bytearray()
        self.views = []
        self.accessors = []

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data), "target": target})
        self.blob.extend(data)
        return len(self.views) - 1

    def floats(self, values, kind, with_bounds=False):
        width = {"VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
        data = b"".join(struct.pack("<%df" % width, *v) for v in values)
        accessor = {"bufferView": self._view(data, 34962), "componentType": 5126, "count": len(values), "type": kind}
        if with_bounds:
            stored = [[f32(x) for x in v] for v in values]
            accessor["min"] = [min(v[k] for v in stored) for k in range(width)]
            accessor["max"] = [max(v[k] for v in stored) for k in range(width)]
        self.accessors.append(accessor)
        return len(self.accessors) - 1

    def indices(self, indices):
        wide = max(indices) > 65535
        data = struct.pack("<%d%s" % (len(indices), "I" if wide else "H"), *indices)
        self.accessors.append({"bufferView": self._view(data, 34963), "componentType": 5125 if wide else 5123,
                               "count": len(indices), "type": "SCALAR"})
        return len(self.accessors) - 1

    def primitive(self, mesh, material_index):
        attributes = {"POSITION": self.floats(mesh.positions, "VEC3", True),
                      "NORMAL": self.floats(mesh.normals, "VEC3")}
        if mesh.tangents:
            attributes["TANGENT"] = self.floats(mesh.tangents, "VEC4")
        if mesh.uvs:
            attributes["TEXCOORD_0"] = self.floats(mesh.uvs, "VEC2")
        return {"attributes": attributes, "indices": self.indices(mesh.indices), "material": material_index, "mode": 4}
