#!/usr/bin/env python3
"""Writes scenes/cornell-box.gltf, scenes/cornell-box-spheres.gltf and
scenes/cornell-box-motion.gltf (the box with a ball flying in an arc and the short block
turning during the first second of an animation: a scene for --shutter).

Geometry: the published "Cornell Box Data" of the Cornell Program of Computer
Graphics (millimetres, converted here to metres with a scale of 0.001). The
original data place the camera at (278, 273, -800) looking along +z with +y up;
read as a right-handed frame that camera has world -x on its right, so the red
wall (x ~ 0.55 m) is on the left exactly as in the classic photograph. glTF
cameras look down their local -z, so the camera node is the original position
rotated 180 degrees about +y. No coordinate of the box is mirrored.

Python 3 standard library only; the output is byte-for-byte deterministic.
Usage: python3 scripts/make_cornell_box.py [output_dir]   (default: scenes/)
"""

import base64
import json
import math
import os
import struct
import sys

MM = 0.001  # millimetres to metres

# Published vertex lists (mm). Each quad is listed in the published order; the
# triangulation and winding are chosen below so every face points into the air
# of the box (walls inward, blocks outward, the light down).
FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]
CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
BACK_WALL = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
RIGHT_WALL_GREEN = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]
LEFT_WALL_RED = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]
# The published light sits in the ceiling plane (y = 548.8); it is lowered by
# 0.1 mm so it never coincides with the ceiling triangles behind it.
LIGHT_Y = 548.8 - 0.1
LIGHT = [(343.0, LIGHT_Y, 227.0), (343.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 227.0)]
SHORT_BLOCK = [
    [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
    [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
    [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
    [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
    [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
]
TALL_BLOCK = [
    [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
    [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
    [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
    [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
    [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
]

# Camera: focal length 0.035, film 0.025 x 0.025 (same units), so the vertical
# field of view is 2 atan(0.0125 / 0.035).
CAMERA_POSITION = (278.0, 273.0, -800.0)
CAMERA_YFOV = 2.0 * math.atan(0.0125 / 0.035)
# 180 degrees about +y as an (x, y, z, w) quaternion: local -z becomes world +z.
CAMERA_ROTATION = (0.0, 1.0, 0.0, 0.0)

# Spheres scene: centres over the footprints of the tall (back left) and short
# (front right) blocks, resting on the floor.
SPHERE_RADIUS_M = 0.1
MIRROR_SPHERE_CENTRE_MM = (368.0, 100.0, 351.0)
GLASS_SPHERE_CENTRE_MM = (186.0, 100.0, 168.0)
SPHERE_SLICES = 32
SPHERE_STACKS = 16

# Motion scene: a ball of radius 0.07 m thrown in an arc over the short block
# (translation keys, metres, at 0, 0.5 and 1 s), and the short block turning 60 degrees
# about its vertical axis over the same second.
BALL_RADIUS_M = 0.07
BALL_KEYS = ((0.0, (0.42, 0.10, 0.14)), (0.5, (0.31, 0.34, 0.14)), (1.0, (0.19, 0.27, 0.14)))
SHORT_BLOCK_TURN_DEGREES = 60.0
# Light radiance (W sr^-1 m^-2), the RGB value widely used for this box.
LIGHT_RADIANCE = (17.0, 12.0, 4.0)


def f32(x):
    """x rounded to IEEE single precision (what the buffer stores)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def short_f32(x):
    """The shortest decimal that reads back as the same single-precision value."""
    x = f32(x)
    for digits in range(1, 18):
        text = "%.*g" % (digits, x)
        if f32(float(text)) == x:
            return float(text)
    return x


def round_floats(value):
    if isinstance(value, float):
        return short_f32(value)
    if isinstance(value, list):
        return [round_floats(v) for v in value]
    if isinstance(value, tuple):
        return [round_floats(v) for v in value]
    if isinstance(value, dict):
        return {k: round_floats(v) for k, v in value.items()}
    return value


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def normalize(a):
    length = math.sqrt(dot(a, a))
    # "+ 0.0" turns -0.0 into 0.0 so the stored normals read cleanly.
    return (a[0] / length + 0.0, a[1] / length + 0.0, a[2] / length + 0.0)


def to_metres(p):
    return (f32(p[0] * MM), f32(p[1] * MM), f32(p[2] * MM))


class Mesh:
    """Indexed triangles with one normal per vertex."""

    def __init__(self, name, material):
        self.name = name
        self.material = material
        self.origin = None  # the node's translation (metres), positions relative to it
        self.positions = []
        self.normals = []
        self.indices = []

    def add_flat_triangle(self, a, b, c):
        # Flat shading: three vertices of its own per triangle, all with the
        # triangle's geometric normal (the published quads are not all planar).
        n = normalize(cross(sub(b, a), sub(c, a)))
        base = len(self.positions)
        for p in (a, b, c):
            self.positions.append(p)
            self.normals.append(n)
        self.indices.extend((base, base + 1, base + 2))


def add_quad(mesh, quad_mm, facing):
    """Two triangles (0,1,2) and (0,2,3), wound so the geometric normal points
    along `facing` (a direction, compared by sign)."""
    q = [to_metres(p) for p in quad_mm]
    n = cross(sub(q[1], q[0]), sub(q[2], q[0]))
    if dot(n, facing) < 0.0:
        q = [q[0], q[3], q[2], q[1]]
    mesh.add_flat_triangle(q[0], q[1], q[2])
    mesh.add_flat_triangle(q[0], q[2], q[3])


def add_block(mesh, faces_mm):
    """A block's five published faces, each facing away from the block centre."""
    points = [p for face in faces_mm for p in face]
    centre = tuple(sum(p[k] for p in points) / len(points) for k in range(3))
    for face in faces_mm:
        face_centre = tuple(sum(p[k] for p in face) / 4.0 for k in range(3))
        add_quad(mesh, face, sub(face_centre, centre))


def box_meshes(with_blocks):
    inward_centre = (278.0, 274.4, 279.6)  # centre of the box, mm
    meshes = []
    for name, material, quad in (
        ("floor", "white", FLOOR),
        ("ceiling", "white", CEILING),
        ("back_wall", "white", BACK_WALL),
        ("left_wall_red", "red", LEFT_WALL_RED),
        ("right_wall_green", "green", RIGHT_WALL_GREEN),
    ):
        mesh = Mesh(name, material)
        quad_centre = tuple(sum(p[k] for p in quad) / 4.0 for k in range(3))
        add_quad(mesh, quad, sub(inward_centre, quad_centre))
        meshes.append(mesh)
    light = Mesh("light", "light")
    add_quad(light, LIGHT, (0.0, -1.0, 0.0))
    meshes.append(light)
    if with_blocks:
        for name, faces in (("short_block", SHORT_BLOCK), ("tall_block", TALL_BLOCK)):
            mesh = Mesh(name, "white")
            add_block(mesh, faces)
            meshes.append(mesh)
    return meshes


def uv_sphere(name, material, centre_mm, radius_m, slices, stacks):
    """A closed UV sphere: single pole vertices, a shared seam, outward CCW
    winding, smooth normals (the unit direction from the centre)."""
    mesh = Mesh(name, material)
    c = (centre_mm[0] * MM, centre_mm[1] * MM, centre_mm[2] * MM)

    def vertex(d):
        d = (d[0] + 0.0, d[1] + 0.0, d[2] + 0.0)  # no -0.0 in the stored normals
        mesh.positions.append((f32(c[0] + radius_m * d[0]), f32(c[1] + radius_m * d[1]),
                               f32(c[2] + radius_m * d[2])))
        mesh.normals.append(d)
        return len(mesh.positions) - 1

    north = vertex((0.0, 1.0, 0.0))
    rings = []
    for i in range(1, stacks):
        theta = math.pi * i / stacks
        ring = []
        for j in range(slices):
            phi = 2.0 * math.pi * j / slices
            ring.append(vertex((math.sin(theta) * math.cos(phi), math.cos(theta),
                                -math.sin(theta) * math.sin(phi))))
        rings.append(ring)
    south = vertex((0.0, -1.0, 0.0))

    # phi grows counter-clockwise seen from +y, so (pole, j, j+1) faces outward.
    for j in range(slices):
        k = (j + 1) % slices
        mesh.indices.extend((north, rings[0][j], rings[0][k]))
    for i in range(stacks - 2):
        upper, lower = rings[i], rings[i + 1]
        for j in range(slices):
            k = (j + 1) % slices
            mesh.indices.extend((upper[j], lower[j], lower[k]))
            mesh.indices.extend((upper[j], lower[k], upper[k]))
    for j in range(slices):
        k = (j + 1) % slices
        mesh.indices.extend((south, rings[-1][k], rings[-1][j]))
    return mesh


def materials(with_spheres):
    def diffuse(name, rgb):
        return {
            "name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [rgb[0], rgb[1], rgb[2], 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0},
        }

    peak = max(LIGHT_RADIANCE)
    light = diffuse("light", (0.78, 0.78, 0.78))
    light["emissiveFactor"] = [v / peak for v in LIGHT_RADIANCE]
    light["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": peak}}
    result = [
        diffuse("white", (0.725, 0.71, 0.68)),
        diffuse("red", (0.63, 0.065, 0.05)),
        diffuse("green", (0.14, 0.45, 0.091)),
        light,
    ]
    if with_spheres == "motion":
        result.append(diffuse("blue", (0.15, 0.3, 0.8)))
    elif with_spheres:
        result.append({
            "name": "mirror",
            "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.95, 0.95, 1.0],
                                     "metallicFactor": 1.0, "roughnessFactor": 0.0},
        })
        result.append({
            "name": "glass",
            "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 0.0},
            "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_ior": {"ior": 1.5},
                # A solid sphere: a volume boundary (refraction), not a thin wall. The factor is
                # the sphere's diameter, the thickness KHR_materials_volume asks for.
                "KHR_materials_volume": {"thicknessFactor": 2 * SPHERE_RADIUS_M},
            },
        })
    return result


def recentred(mesh):
    """The mesh about its vertices' centre, which becomes its node's translation."""
    n = len(mesh.positions)
    centre = tuple(f32(sum(p[k] for p in mesh.positions) / n) for k in range(3))
    mesh.positions = [tuple(f32(p[k] - centre[k]) for k in range(3)) for p in mesh.positions]
    mesh.origin = centre
    return mesh


def build_gltf(meshes, mats, animations=()):
    """animations: (mesh name, path, times, values) channels of one animation."""
    material_index = {m["name"]: i for i, m in enumerate(mats)}
    blob = bytearray()
    buffer_views = []
    accessors = []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        view = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        buffer_views.append(view)
        blob.extend(data)
        return len(buffer_views) - 1

    def add_vec3(values, with_bounds):
        data = b"".join(struct.pack("<3f", *v) for v in values)
        accessor = {"bufferView": add_view(data, 34962), "componentType": 5126,
                    "count": len(values), "type": "VEC3"}
        if with_bounds:
            stored = [tuple(f32(x) for x in v) for v in values]
            accessor["min"] = [min(v[k] for v in stored) for k in range(3)]
            accessor["max"] = [max(v[k] for v in stored) for k in range(3)]
        accessors.append(accessor)
        return len(accessors) - 1

    def add_indices(indices):
        wide = max(indices) > 65535
        data = struct.pack("<%d%s" % (len(indices), "I" if wide else "H"), *indices)
        accessors.append({"bufferView": add_view(data, 34963),
                          "componentType": 5125 if wide else 5123,
                          "count": len(indices), "type": "SCALAR"})
        return len(accessors) - 1

    gltf_meshes = []
    nodes = []
    for mesh in meshes:
        primitive = {
            "attributes": {"POSITION": add_vec3(mesh.positions, True),
                           "NORMAL": add_vec3(mesh.normals, False)},
            "indices": add_indices(mesh.indices),
            "material": material_index[mesh.material],
            "mode": 4,
        }
        gltf_meshes.append({"name": mesh.name, "primitives": [primitive]})
        node = {"name": mesh.name, "mesh": len(gltf_meshes) - 1}
        if mesh.origin is not None:
            node["translation"] = list(mesh.origin)
        nodes.append(node)
    nodes.append({
        "name": "camera",
        "camera": 0,
        "translation": list(to_metres(CAMERA_POSITION)),
        "rotation": list(CAMERA_ROTATION),
    })

    samplers, channels = [], []
    node_index = {node["name"]: i for i, node in enumerate(nodes)}
    for name, path, times, values in animations:
        width = len(values[0])
        data = struct.pack("<%df" % len(times), *times)
        accessors.append({"bufferView": add_view(data, None), "componentType": 5126, "count": len(times),
                          "type": "SCALAR", "min": [f32(min(times))], "max": [f32(max(times))]})
        data = b"".join(struct.pack("<%df" % width, *v) for v in values)
        accessors.append({"bufferView": add_view(data, None), "componentType": 5126, "count": len(values),
                          "type": "VEC3" if width == 3 else "VEC4"})
        samplers.append({"input": len(accessors) - 2, "output": len(accessors) - 1, "interpolation": "LINEAR"})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": node_index[name], "path": path}})

    extensions = sorted({ext for m in mats for ext in m.get("extensions", {})})
    gltf = {
        "asset": {"version": "2.0",
                  "generator": "Lancer scripts/make_cornell_box.py (Cornell Box Data, metres)"},
        "extensionsUsed": extensions,
        "scene": 0,
        "scenes": [{"name": "cornell_box", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"name": "cornell_camera", "type": "perspective",
                     "perspective": {"yfov": CAMERA_YFOV, "aspectRatio": 1.0, "znear": 0.01}}],
        "meshes": gltf_meshes,
        "materials": mats,
        "accessors": accessors,
        "bufferViews": buffer_views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode("ascii")}],
    }
    if channels:
        gltf["animations"] = [{"name": "motion", "samplers": samplers, "channels": channels}]
    return json.dumps(round_floats(gltf), indent=2) + "\n"


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes")
    os.makedirs(out_dir, exist_ok=True)

    box = build_gltf(box_meshes(with_blocks=True), materials(with_spheres=False))
    spheres = box_meshes(with_blocks=False) + [
        uv_sphere("mirror_sphere", "mirror", MIRROR_SPHERE_CENTRE_MM, SPHERE_RADIUS_M, SPHERE_SLICES, SPHERE_STACKS),
        uv_sphere("glass_sphere", "glass", GLASS_SPHERE_CENTRE_MM, SPHERE_RADIUS_M, SPHERE_SLICES, SPHERE_STACKS),
    ]
    spheres_text = build_gltf(spheres, materials(with_spheres=True))

    motion_meshes = box_meshes(with_blocks=False)
    tall = Mesh("tall_block", "white")
    add_block(tall, TALL_BLOCK)
    short = Mesh("short_block", "white")
    add_block(short, SHORT_BLOCK)
    ball = uv_sphere("ball", "blue", (0.0, 0.0, 0.0), BALL_RADIUS_M, SPHERE_SLICES, SPHERE_STACKS)
    ball.origin = BALL_KEYS[0][1]
    motion_meshes += [tall, recentred(short), ball]
    half_turn = math.radians(SHORT_BLOCK_TURN_DEGREES) / 2.0
    turn = [(0.0, 0.0, 0.0, 1.0), (0.0, math.sin(half_turn), 0.0, math.cos(half_turn))]
    motion_text = build_gltf(motion_meshes, materials(with_spheres="motion"), animations=(
        ("ball", "translation", [t for t, _ in BALL_KEYS], [p for _, p in BALL_KEYS]),
        ("short_block", "rotation", [0.0, 1.0], turn),
    ))

    for name, text in (("cornell-box.gltf", box), ("cornell-box-spheres.gltf", spheres_text),
                       ("cornell-box-motion.gltf", motion_text)):
        path = os.path.join(out_dir, name)
        with open(path, "w", encoding="ascii", newline="\n") as f:
            f.write(text)
        print("wrote", os.path.normpath(path))


if __name__ == "__main__":
    main()
