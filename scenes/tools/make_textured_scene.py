#!/usr/bin/env python3
"""Writes scenes/textured/: still-life.gltf, still-life.bin and its PNG textures.

A brick wall and a tiled floor, a hammered copper sphere and a glazed tiled torus
standing on its rim, lit by a warm rectangular area light raking across the wall
from the left and a dim cool panel above the camera. Every surface but the lights has
TEXCOORD_0 and TANGENT; the wall, floor and torus have base colour, normal and
metallic-roughness textures, the sphere a normal and a metallic-roughness texture.
The textures are drawn by texture_patterns.py. Units: metres, +y up.

Python 3 standard library only; the output is the same on every run.
Usage: python3 scenes/tools/make_textured_scene.py [output_dir]  (default: scenes/textured/)
"""

import json
import math
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ beside the scenes
from gltf_builder import (BufferPacker, Mesh, add, cross, look_at_rotation, normalize, quat_axis_angle, quat_mul,
                          round_floats, scale, sub, tangent_frame)
from png_rgb import write_png
import texture_patterns

SCENE_NAME = "still-life"

# Back wall (z = WALL_Z, facing +z) and floor (y = 0, facing +y), both WALL_HALF_WIDTH
# either side of x = 0. One brick texture covers 1 m x 1 m (bricks 0.25 m x 0.125 m),
# one tile texture 0.8 m x 0.8 m (tiles 0.2 m).
WALL_Z, WALL_HALF_WIDTH, WALL_HEIGHT, FLOOR_FRONT_Z = -1.2, 2.5, 3.0, 3.0
BRICK_TEXTURE_M, FLOOR_TILE_TEXTURE_M = 1.0, 0.8

SPHERE_RADIUS, SPHERE_CENTRE = 0.35, (-0.5, 0.35, -0.35)
SPHERE_SLICES, SPHERE_STACKS, SPHERE_UV_REPEAT = 64, 32, (6.0, 3.0)
# Torus standing on its rim: major radius R, tube radius r; the ring's plane is turned
# TORUS_YAW about +y from facing the camera.
TORUS_R, TORUS_r, TORUS_CENTRE_XZ, TORUS_YAW = 0.3, 0.11, (0.5, 0.05), math.radians(-30.0)
TORUS_SLICES, TORUS_SIDES, TORUS_UV_REPEAT = 72, 24, (8.0, 3.0)

CAMERA_EYE, CAMERA_TARGET, CAMERA_YFOV = (0.0, 1.0, 3.0), (0.0, 0.42, -0.4), math.radians(32.0)

# Area lights: centre, point it faces, width x height (m), radiance (W sr^-1 m^-2).
KEY_LIGHT = ((-2.2, 1.7, 0.2), (0.2, 0.6, -1.0), (0.9, 0.6), (34.0, 30.0, 24.0))
FILL_LIGHT = ((0.0, 2.6, 3.2), (0.0, 0.3, -0.5), (2.4, 0.5), (1.6, 1.8, 2.2))


def plane(name, material, corner, axis_u, axis_v, size_u, size_v, texture_size, normal):
    """A rectangle corner + [0, size_u] axis_u + [0, size_v] axis_v; uv = distance
    along the axes over texture_size (so axis_v must point down the image)."""
    mesh = Mesh(name, material)
    tangent = tangent_frame(normal, axis_u, axis_v)
    ids = []
    for fu, fv in ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)):
        p = add(corner, add(scale(axis_u, fu * size_u), scale(axis_v, fv * size_v)))
        ids.append(mesh.vertex(p, normal, tangent, (fu * size_u / texture_size, fv * size_v / texture_size)))
    mesh.triangle(ids[0], ids[1], ids[2])
    mesh.triangle(ids[0], ids[2], ids[3])
    return mesh


def uv_sphere(name, material, radius, slices, stacks, uv_repeat):
    """Sphere around the origin, poles on +-y; u grows with the angle phi counter-
    clockwise seen from +y, v from the north pole (top of the image) to the south.
    Seam and pole vertices are duplicated per column so the UVs stay continuous."""
    mesh = Mesh(name, material)
    grid = []
    for k in range(stacks + 1):
        theta = math.pi * k / stacks
        row = []
        for s in range(slices + 1):
            # Pole vertices take the middle of their column's u range.
            fu = (s + 0.5) / slices if k in (0, stacks) else s / slices
            phi = 2.0 * math.pi * fu
            st, ct, sp, cp = math.sin(theta), math.cos(theta), math.sin(phi), math.cos(phi)
            n = (st * cp, ct, -st * sp)
            dp_du = (-sp, 0.0, -cp)  # d/dphi, divided by sin(theta) (unit even at the poles)
            dp_dv = (ct * cp, -st, -ct * sp)  # d/dtheta
            row.append(mesh.vertex(scale(n, radius), n, tangent_frame(n, dp_du, dp_dv),
                                   (fu * uv_repeat[0], k / stacks * uv_repeat[1])))
        grid.append(row)
    for k in range(stacks):
        for s in range(slices):
            a, b, c, d = grid[k][s], grid[k + 1][s], grid[k + 1][s + 1], grid[k][s + 1]
            if k != stacks - 1:
                mesh.triangle(a, b, c)
            if k != 0:
                mesh.triangle(a, c, d)
    return mesh


def torus(name, material, major, minor, slices, sides, uv_repeat):
    """Torus around the +y axis through the origin; u along the ring (phi), v around
    the tube (psi, from the outer equator over the top)."""
    mesh = Mesh(name, material)
    grid = []
    for k in range(sides + 1):
        psi = 2.0 * math.pi * k / sides
        row = []
        for s in range(slices + 1):
            phi = 2.0 * math.pi * s / slices
            sp, cp, ss, cs = math.sin(phi), math.cos(phi), math.sin(psi), math.cos(psi)
            n = (cs * cp, ss, -cs * sp)
            p = ((major + minor * cs) * cp, minor * ss, -(major + minor * cs) * sp)
            dp_du = (-sp, 0.0, -cp)
            dp_dv = (-ss * cp, cs, ss * sp)
            row.append(mesh.vertex(p, n, tangent_frame(n, dp_du, dp_dv),
                                   (s / slices * uv_repeat[0], k / sides * uv_repeat[1])))
        grid.append(row)
    for k in range(sides):
        for s in range(slices):
            a, b, c, d = grid[k][s], grid[k + 1][s], grid[k + 1][s + 1], grid[k][s + 1]
            mesh.triangle(a, b, c)
            mesh.triangle(a, c, d)
    return mesh


def area_light(name, material, centre, target, size):
    """A rectangle of `size` centred at `centre`, emitting towards `target`."""
    facing = normalize(sub(target, centre))
    right = normalize(cross(facing, (0.0, 1.0, 0.0)))
    up = cross(right, facing)
    mesh = Mesh(name, material)
    ids = [mesh.vertex(add(centre, add(scale(right, fu * size[0] * 0.5), scale(up, fv * size[1] * 0.5))), facing)
           for fu, fv in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    mesh.triangle(ids[0], ids[1], ids[2])
    mesh.triangle(ids[0], ids[2], ids[3])
    return mesh


def texture_ref(index):
    return {"index": index, "texCoord": 0}


def materials():
    """Materials and the image files they use, in texture index order."""
    images = ["bricks_basecolor.png", "bricks_normal.png", "bricks_metallic_roughness.png",
              "tiles_basecolor.png", "tiles_normal.png", "tiles_metallic_roughness.png",
              "hammered_normal.png", "hammered_metallic_roughness.png"]
    t = {name: i for i, name in enumerate(images)}

    def textured(name, prefix, factor, metallic):
        pbr = {"baseColorFactor": list(factor) + [1.0], "metallicFactor": metallic, "roughnessFactor": 1.0,
               "metallicRoughnessTexture": texture_ref(t[prefix + "_metallic_roughness.png"])}
        if prefix + "_basecolor.png" in t:
            pbr["baseColorTexture"] = texture_ref(t[prefix + "_basecolor.png"])
        return {"name": name, "pbrMetallicRoughness": pbr,
                "normalTexture": dict(texture_ref(t[prefix + "_normal.png"]), scale=1.0)}

    def emitter(name, radiance):
        peak = max(radiance)
        return {"name": name,
                "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                         "roughnessFactor": 1.0},
                "emissiveFactor": [c / peak for c in radiance],
                "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": peak}}}

    mats = [
        textured("bricks", "bricks", (1.0, 1.0, 1.0), 1.0),
        textured("floor_tiles", "tiles", (0.72, 0.66, 0.58), 1.0),
        textured("glazed_torus", "tiles", (0.18, 0.38, 0.85), 1.0),
        textured("hammered_copper", "hammered", (0.955, 0.638, 0.538), 1.0),
        emitter("key_light", KEY_LIGHT[3]),
        emitter("fill_light", FILL_LIGHT[3]),
    ]
    return mats, images


def meshes_and_nodes():
    """(mesh, node translation, node rotation) for every object."""
    wall = plane("brick_wall", "bricks", (-WALL_HALF_WIDTH, WALL_HEIGHT, WALL_Z), (1.0, 0.0, 0.0),
                 (0.0, -1.0, 0.0), 2.0 * WALL_HALF_WIDTH, WALL_HEIGHT, BRICK_TEXTURE_M, (0.0, 0.0, 1.0))
    floor = plane("floor", "floor_tiles", (-WALL_HALF_WIDTH, 0.0, WALL_Z), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0),
                  2.0 * WALL_HALF_WIDTH, FLOOR_FRONT_Z - WALL_Z, FLOOR_TILE_TEXTURE_M, (0.0, 1.0, 0.0))
    sphere = uv_sphere("hammered_sphere", "hammered_copper", SPHERE_RADIUS, SPHERE_SLICES, SPHERE_STACKS,
                       SPHERE_UV_REPEAT)
    ring = torus("glazed_torus", "glazed_torus", TORUS_R, TORUS_r, TORUS_SLICES, TORUS_SIDES, TORUS_UV_REPEAT)
    # Stand the ring up (its axis from +y to +z), then turn it about +y.
    stand = quat_mul(quat_axis_angle((0.0, 1.0, 0.0), TORUS_YAW), quat_axis_angle((1.0, 0.0, 0.0), math.pi / 2))
    torus_centre = (TORUS_CENTRE_XZ[0], TORUS_R + TORUS_r, TORUS_CENTRE_XZ[1])
    key = area_light("key_light", "key_light", *KEY_LIGHT[:3])
    fill = area_light("fill_light", "fill_light", *FILL_LIGHT[:3])
    return [(wall, None, None), (floor, None, None), (sphere, SPHERE_CENTRE, None), (ring, torus_centre, stand),
            (key, None, None), (fill, None, None)]


def build(bin_name):
    mats, images = materials()
    material_index = {m["name"]: i for i, m in enumerate(mats)}
    packer = BufferPacker()
    gltf_meshes, nodes = [], []
    for mesh, translation, rotation in meshes_and_nodes():
        gltf_meshes.append({"name": mesh.name, "primitives": [packer.primitive(mesh, material_index[mesh.material])]})
        node = {"name": mesh.name, "mesh": len(gltf_meshes) - 1}
        if translation is not None:
            node["translation"] = list(translation)
        if rotation is not None:
            node["rotation"] = list(rotation)
        nodes.append(node)
    nodes.append({"name": "camera", "camera": 0, "translation": list(CAMERA_EYE),
                  "rotation": list(look_at_rotation(CAMERA_EYE, CAMERA_TARGET))})
    gltf = {
        "asset": {"version": "2.0", "generator": "Lancer scenes/tools/make_textured_scene.py (metres)"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"name": SCENE_NAME, "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"name": "still_life_camera", "type": "perspective",
                     "perspective": {"yfov": CAMERA_YFOV, "aspectRatio": 1.0, "znear": 0.01}}],
        "meshes": gltf_meshes,
        "materials": mats,
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": name} for name in images],
        "textures": [{"sampler": 0, "source": i} for i in range(len(images))],
        "accessors": packer.accessors,
        "bufferViews": packer.views,
        "buffers": [{"byteLength": len(packer.blob), "uri": bin_name}],
    }
    return json.dumps(round_floats(gltf), indent=1) + "\n", bytes(packer.blob), images


def write_textures(out_dir, images):
    sets = {"bricks": texture_patterns.bricks(), "tiles": texture_patterns.tiles(),
            "hammered": texture_patterns.hammered_metal()}
    for name in images:
        prefix, kind = name[:-len(".png")].split("_", 1)
        tex = sets[prefix]
        pixels = {"basecolor": tex.base_color, "normal": tex.normal, "metallic_roughness": tex.metallic_roughness}[kind]
        path = os.path.join(out_dir, name)
        write_png(path, tex.size, tex.size, pixels)
        print("wrote", os.path.normpath(path))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "textured")
    os.makedirs(out_dir, exist_ok=True)
    text, blob, images = build(SCENE_NAME + ".bin")
    for name, data, mode in ((SCENE_NAME + ".gltf", text.encode("ascii"), "wb"), (SCENE_NAME + ".bin", blob, "wb")):
        path = os.path.join(out_dir, name)
        with open(path, mode) as f:
            f.write(data)
        print("wrote", os.path.normpath(path))
    write_textures(out_dir, images)


if __name__ == "__main__":
    main()
